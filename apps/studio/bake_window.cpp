// SPDX-License-Identifier: MIT
#include "bake_window.h"

#include "input_mesh.h"  // apps/hdm: the input read as `hdm bake` reads it

#include <hdm/pipeline/bake_input.h>

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <exception>
#include <filesystem>
#include <mutex>
#include <thread>

namespace hdm::studio {
namespace {

// The worker's progress, read by the render thread (not a servo thread: a mutex is fine here).
struct Progress {
  std::mutex mutex;
  std::string stage = "read";
  double fraction = 0;
  std::vector<std::string> stages{"read"};
  void set(const char* s, double f) {
    std::lock_guard lock(mutex);
    if (stage != s) stage = s, stages.push_back(s);
    fraction = std::clamp(f, 0.0, 1.0);
  }
};

}  // namespace

bool is_slab_model_path(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".hdm";
}

SlabModel bake_in_window(GLFWwindow* window, const std::string& mesh_path, WindowBake& report) {
  report.input = mesh_path;
  Progress progress;
  std::atomic<bool> done{false};
  std::exception_ptr error;
  SlabModel model;
  BakeInputReport bake;
  const auto start = std::chrono::steady_clock::now();
  // As `hdm bake MESH` with its defaults (bake_input(): the same model, byte for byte).
  std::thread worker([&] {
    try {
      BakeInputOptions o;
      o.bake.progress = [&](const char* stage, double f) { progress.set(stage, f); };
      model = bake_input(app::read_input(mesh_path, uint64_t(1) << 30), mesh_path, o, &bake);
    } catch (...) {
      error = std::current_exception();
    }
    done.store(true, std::memory_order_release);
  });
  const std::string name = std::filesystem::path(mesh_path).filename().string();
  do {  // at least one frame, however quick the bake
    glfwPollEvents();
    report.closed = report.closed || glfwWindowShouldClose(window);
    std::string stage;
    double fraction = 0;
    {
      std::lock_guard lock(progress.mutex);
      stage = progress.stage, fraction = progress.fraction;
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    const ImVec2 size = ImGui::GetIO().DisplaySize;
    ImGui::SetNextWindowPos(ImVec2(size.x / 2, size.y / 2), ImGuiCond_Always, ImVec2(0.5f, 0.5f));
    ImGui::SetNextWindowSize(ImVec2(std::min(size.x - 20, 460.0f), 0), ImGuiCond_Always);
    ImGui::Begin("baking", nullptr, ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove);
    ImGui::Text("baking %s into slabs (as hdm bake)", name.c_str());
    ImGui::Text("%s", stage.c_str());
    ImGui::ProgressBar(static_cast<float>(fraction), ImVec2(-1, 0));
    ImGui::Text("%.1f s", seconds);
    ImGui::End();
    ImGui::Render();
    int w = 0, h = 0;
    glfwGetFramebufferSize(window, &w, &h);
    glViewport(0, 0, w, h);
    glClearColor(1, 1, 1, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    glfwSwapBuffers(window);
    ++report.frames;
    std::this_thread::sleep_for(std::chrono::milliseconds(30));  // leave the cores to the bake
  } while (!done.load(std::memory_order_acquire));
  worker.join();
  if (error) std::rethrow_exception(error);
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  report.stages = progress.stages;
  report.slabs = model.slab_count();
  report.grid = model.grid_n;
  if (!bake.rounds.empty()) {
    const Fidelity& f = bake.rounds.back().fidelity;
    report.max_pct = f.max_pct, report.max_back_pct = f.max_back_pct;
    report.rms_pct = f.rms_pct, report.rms_back_pct = f.rms_back_pct;
    report.met = bake.rounds.back().met;
  }
  return model;
}

}  // namespace hdm::studio
