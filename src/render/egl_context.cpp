// SPDX-License-Identifier: MIT
#include <hdm/core/error.h>
#include <hdm/render/egl_context.h>

#include "gl.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdio>
#include <cstring>
#include <string>

namespace hdm {
namespace {

const char* const kInstallHint = "install libegl1 and libgl1-mesa-dri";

std::string egl_error_text() {
  char code[16];
  std::snprintf(code, sizeof code, "0x%04X", static_cast<unsigned>(eglGetError()));
  return std::string("EGL error ") + code;
}

bool has_extension(const char* list, const char* name) {
  if (!list) return false;
  const size_t len = std::strlen(name);
  for (const char* p = std::strstr(list, name); p; p = std::strstr(p + 1, name))
    if ((p == list || p[-1] == ' ') && (p[len] == ' ' || p[len] == '\0')) return true;
  return false;
}

// The surfaceless display, initialised on first use and kept for the process (see the header:
// eglTerminate is not reference counted). A failed attempt is retried on the next call.
EGLDisplay surfaceless_display() {
  static const EGLDisplay display = [] {
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!has_extension(client, "EGL_MESA_platform_surfaceless"))
      throw RenderError(std::string("no EGL display: the EGL surfaceless platform "
                                    "(EGL_MESA_platform_surfaceless) is missing; ") +
                        kInstallHint);
    auto get_platform_display =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (!get_platform_display)
      throw RenderError(std::string("no EGL display: eglGetPlatformDisplayEXT is missing; ") + kInstallHint);
    EGLDisplay d = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (d == EGL_NO_DISPLAY) throw RenderError(std::string("no EGL display: ") + kInstallHint);
    EGLint major = 0, minor = 0;
    if (!eglInitialize(d, &major, &minor))
      throw RenderError("EGL display cannot be initialised (" + egl_error_text() + "); " + kInstallHint);
    return d;
  }();
  return display;
}

}  // namespace

EglContext::EglContext() {
  EGLDisplay display = surfaceless_display();
  if (!eglBindAPI(EGL_OPENGL_API))
    throw RenderError("EGL offers no desktop OpenGL API (" + egl_error_text() + "); " + kInstallHint);

  // Rendering goes to FBOs, so no config is needed where EGL allows that.
  EGLConfig config = EGL_NO_CONFIG_KHR;
  if (!has_extension(eglQueryString(display, EGL_EXTENSIONS), "EGL_KHR_no_config_context")) {
    const EGLint wanted[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLint found = 0;
    if (!eglChooseConfig(display, wanted, &config, 1, &found) || found < 1)
      throw RenderError("EGL has no OpenGL-capable config; " + std::string(kInstallHint));
  }
  const EGLint attributes[] = {
      EGL_CONTEXT_MAJOR_VERSION,           4,       EGL_CONTEXT_MINOR_VERSION, 5, EGL_CONTEXT_OPENGL_PROFILE_MASK,
      EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, attributes);
  if (context == EGL_NO_CONTEXT)
    throw RenderError("no OpenGL 4.5 core context (" + egl_error_text() +
                      "): needs Mesa >= 20 (llvmpipe) or a GPU driver; " + kInstallHint);
  display_ = display;
  context_ = context;
  try {
    make_current();
  } catch (...) {
    eglDestroyContext(display, context);
    throw;
  }
}

EglContext::~EglContext() {
  if (eglGetCurrentContext() == context_) eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(display_, context_);
}

void EglContext::make_current() {
  if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
    throw RenderError("EGL cannot make the OpenGL context current (" + egl_error_text() + ")");
}

const char* EglContext::renderer() const {
  const GLubyte* name = glGetString(GL_RENDERER);
  return name ? reinterpret_cast<const char*>(name) : "unknown";
}

}  // namespace hdm
