// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// A headless OpenGL 4.5 core context (EGL surfaceless platform, e.g. Mesa llvmpipe without a GPU
/// or display server). Render into a framebuffer object; there is no default framebuffer.

namespace hdm {

/// Owns one EGL context and makes it current on the constructing thread.
///
/// The EGL display is initialised once per process and never terminated: eglTerminate would also
/// invalidate contexts other code holds on the same display (EGL displays are not reference
/// counted), so keeping it is the only safe choice. That display is the only global state.
/// @note The context is owned by the calling thread: construct, use and destroy the object on
///       one thread. Not copyable or movable. Construction costs a few ms on llvmpipe.
/// @see paper §6 (rendering runs beside, and independently of, the haptic loop)
class EglContext {
 public:
  /// @brief Creates an OpenGL 4.5 core context and makes it current (no surface).
  /// @throws RenderError naming what is missing: no EGL display or surfaceless platform
  ///         ("install libegl1 and libgl1-mesa-dri"), no desktop OpenGL API, no 4.5 core context.
  EglContext();
  /// Releases the context (made non-current first if it is current).
  ~EglContext();
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

  /// @brief Makes this context current on the calling thread again (after other GL code ran).
  /// @throws RenderError if EGL refuses.
  void make_current();

  /// The GL_RENDERER string, for diagnostics (for example "llvmpipe (LLVM 15.0.6, 256 bits)").
  /// @pre this context is current on the calling thread.
  const char* renderer() const;

 private:
  void* display_ = nullptr;  // EGLDisplay
  void* context_ = nullptr;  // EGLContext
};

}  // namespace hdm
