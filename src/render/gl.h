// SPDX-License-Identifier: MIT
#pragma once
// Internal: the one place that includes the OpenGL headers. Functions come straight from glvnd's
// libOpenGL (GL_GLEXT_PROTOTYPES), which dispatches to whatever context is current, EGL or not.
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>

#include <string>

namespace hdm::render_detail {

/// Throws RenderError("<what>: OpenGL error 0x...") if glGetError() reports anything; drains it.
void check_gl(const char* what);

/// Compiles and links a vertex + fragment program; throws RenderError with the info log.
GLuint link_program(const char* vertex_source, const char* fragment_source);

}  // namespace hdm::render_detail
