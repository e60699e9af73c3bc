// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// hdm's exception hierarchy (after pmp-library's exceptions.h). Thrown only off the servo path;
/// every message names the file or argument and the reason.

#include <stdexcept>
#include <string>

namespace hdm {

/// Bad input: an argument or a mesh that breaks a documented precondition.
struct InvalidInput : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

/// A file could not be read or written, or its content is truncated, corrupt or of the wrong
/// version.
struct IoError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// A numerical procedure failed (for example a slab shell that cannot be made valid).
struct NumericalError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Rendering failed (no EGL display, no OpenGL 4.5 context, shader errors).
struct RenderError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace hdm
