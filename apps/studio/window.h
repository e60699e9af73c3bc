// SPDX-License-Identifier: MIT
#pragma once
// The studio's window: GLFW's window and OpenGL 4.5 core context with Dear ImGui on them, and
// key-press edges for shortcuts.

#include <string>

struct GLFWwindow;

namespace hdm::studio {

/// GLFW's window and context, and Dear ImGui on them; torn down in reverse.
struct Window {
  GLFWwindow* handle = nullptr;  ///< the window, its context current on the constructing thread
  bool imgui = false;            ///< Dear ImGui was set up on it
  /// @brief Opens a width × height window [pixels] titled @p title, vsync on or off.
  /// @throws RenderError naming what is missing (no window system, no OpenGL 4.5 core).
  Window(int width, int height, const std::string& title, bool vsync);
  ~Window();
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;
};

/// Edge detection of a key held down.
struct KeyEdge {
  bool was = false;  ///< the key was down at the last call
  /// True on the first call that sees @p key down after a call that saw it up.
  bool pressed(GLFWwindow* w, int key);
};

}  // namespace hdm::studio
