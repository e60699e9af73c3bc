// SPDX-License-Identifier: MIT
#include "window.h"

#include <hdm/core/error.h>

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include <cstdio>

namespace hdm::studio {

Window::Window(int width, int height, const std::string& title, bool vsync) {
  glfwSetErrorCallback(
      [](int code, const char* text) { std::fprintf(stderr, "hdm-studio: GLFW error %d: %s\n", code, text); });
  if (!glfwInit())
    throw RenderError(
        "studio: no window system (GLFW could not initialise: set DISPLAY, or run under Xvfb: "
        "xvfb-run -a hdm-studio ...)");
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_DEPTH_BITS, 24);
  handle = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!handle) {
    glfwTerminate();
    throw RenderError("studio: no OpenGL 4.5 core window (" + std::to_string(width) + "x" + std::to_string(height) +
                      "); on a machine without a GPU, Mesa's llvmpipe (libgl1-mesa-dri) gives one");
  }
  glfwMakeContextCurrent(handle);
  glfwSwapInterval(vsync ? 1 : 0);
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini left in the working directory
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL(handle, true);
  ImGui_ImplOpenGL3_Init("#version 450 core");
  imgui = true;
}

Window::~Window() {
  if (imgui) {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
  }
  glfwDestroyWindow(handle);
  glfwTerminate();
}

bool KeyEdge::pressed(GLFWwindow* w, int key) {
  const bool now = glfwGetKey(w, key) == GLFW_PRESS;
  const bool edge = now && !was;
  was = now;
  return edge;
}

}  // namespace hdm::studio
