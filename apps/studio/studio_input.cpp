// SPDX-License-Identifier: MIT
// The studio's inputs: the mouse as the haptic device and the camera's handle, the tools panel's
// actions, and the script host's calls (cursor, probes, screenshots, saving, the view).
#include "studio_app.h"

#include <hdm/edit/brush_registry.h>

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <numbers>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>

namespace hdm::studio {

void Studio::set_cursor(double x, double y, bool button) {
  int w = 0, h = 0;
  glfwGetFramebufferSize(window_.handle, &w, &h);
  cursor_ = Eigen::Vector2d(x * w, y * h);
  cursor_valid_ = true;
  set_button(button);
}

bool Studio::settled() {
  const ToolState& t = servo_->tool();
  // The mouse's button reaches the servo up to a frame late (MouseDevice's smoothing): count the
  // quiet ticks from the first tick seen with the tool off.
  if (t.tool_on)
    tool_off_since_ = -1;
  else if (tool_off_since_ < 0)
    tool_off_since_ = t.tick;
  const bool quiet = tool_off_since_ >= 0 && t.tick - tool_off_since_ >= static_cast<int64_t>(0.03 * o_.rate_hz);
  // The newest epoch drawn for a while: 50 ms, or in lockstep two frames (a frame count, so that the
  // settle ends at the same tick every run).
  const bool drawn =
      o_.ticks_per_frame > 0 ? fig_.frames - epoch_changed_frame_ >= 2 : seconds_now() - epoch_changed_at_ > 0.05;
  return !button_ && !t.tool_on && quiet && !t.edit_pending && t.tick >= quiet_after_tick_ &&
         session_->snapshots()->epoch() == drawn_epoch_ && drawn;
}

void Studio::screenshot(const std::string& path, bool ui, bool footprint) {
  (ui ? ui_screenshots_ : footprint ? footprint_screenshots_ : screenshots_).push_back(path);
}

void Studio::probe(const std::string& name) {
  const ToolState& t = servo_->tool();
  auto v = [](const Vec3& p) { return nlohmann::json::array({p.x(), p.y(), p.z()}); };
  fig_.probes[name] = {{"tick", t.tick},
                       {"contact", t.contact},
                       {"hip_m", v(workspace_.to_device(t.hip))},
                       {"proxy_m", v(workspace_.to_device(t.proxy))},
                       {"normal", v(t.normal)},
                       {"force_n", v(t.force)},
                       {"stiffness_n_per_m", settings_.stiffness},
                       {"friction", settings_.friction}};
  if (t.rigid) {
    const Eigen::Quaterniond& q = t.orientation;
    fig_.probes[name]["tip_m"] = v(workspace_.to_device(t.ball_centre));
    fig_.probes[name]["orientation_wxyz"] = {q.w(), q.x(), q.y(), q.z()};
    fig_.probes[name]["torque_nm"] = v(t.torque);
    fig_.probes[name]["tool_contacts"] = t.tool_contacts;
    // The head's and the shaft's contacts: how many, their force on the tool and where they press.
    auto part = [&](const ToolPartContacts& c) {
      return nlohmann::json{
          {"contacts", c.contacts}, {"force_n", v(c.force)}, {"point_m", v(workspace_.to_device(c.point))}};
    };
    fig_.probes[name]["head"] = part(t.head);
    fig_.probes[name]["shaft"] = part(t.shaft);
  }
}

void Studio::turn_tool(double yaw_deg, double pitch_deg) {
  turn_yaw_ += yaw_deg * std::numbers::pi / 180;
  turn_pitch_ += pitch_deg * std::numbers::pi / 180;
}

void Studio::save(const std::string& path) {
  SlabModel copy = snapshot_model();
  save_model(copy, path);
  message_ = "saved " + path;
}

void Studio::export_model(const std::string& path) {
  SlabModel copy = snapshot_model();
  rebuild_derived(copy);
  export_mesh(copy, path);
  message_ = "exported " + path;
}

void Studio::view(double azimuth_deg, double elevation_deg, double zoom, bool on_tool) {
  camera_.azimuth_deg = azimuth_deg, camera_.elevation_deg = elevation_deg;
  camera_.fit();
  camera_.zoom = zoom;
  if (on_tool) {  // a close view of the tool where it touches; the mouse's handle follows the new view
    const ToolState& t = servo_->tool();
    camera_.target = t.rigid || t.ball ? t.ball_centre : t.proxy;
  }
}

bool Studio::set_footprint(const ToolState& t) {
  const double r = settings_.radius_mm * mm_;
  Vec3 centre = t.proxy;
  const BrushInfo* info = settings_.brush ? find_brush(*settings_.brush) : nullptr;
  const ToolPlacement place = info ? info->placement : ToolPlacement::Contact;
  if (place == ToolPlacement::BehindHip)  // a ball's centre is the HIP, a point's is r above it
    centre = t.hip + t.normal * ((t.ball ? 0.0 : r) + settings_.resilience_mm * mm_);
  else if (place == ToolPlacement::StartSurface)
    centre = t.proxy + t.normal * (settings_.height_mm * mm_ - r);
  const bool on = t.contact && info && centre.allFinite();
  renderer_->set_footprint(centre, on ? r : 0.0);
  return on;
}

void Studio::set_button(bool down) {
  if (button_ && !down) quiet_after_tick_ = servo_->ticks() + static_cast<int64_t>(0.03 * o_.rate_hz) + 1;
  button_ = down;
}

void Studio::interactive_input() {
  ImGuiIO& io = ImGui::GetIO();
  GLFWwindow* win = window_.handle;
  int h = 0, w = 0;
  glfwGetFramebufferSize(win, &w, &h);
  if (!io.WantCaptureMouse) {
    // Alt held: the mouse turns the handle (a rigid tool) instead of moving it, 0.5° per pixel.
    const bool turning = io.KeyAlt && o_.burr;
    if (turning) turn_tool(0.5 * io.MouseDelta.x, 0.5 * io.MouseDelta.y);
    const bool pan = io.MouseDown[2] || (io.MouseDown[1] && io.KeyShift);
    if (pan)
      camera_.pan(io.MouseDelta.x, io.MouseDelta.y, h);
    else if (io.MouseDown[1])
      camera_.orbit(io.MouseDelta.x, io.MouseDelta.y);
    if (io.MouseWheel != 0) {
      if (io.KeyShift)
        settings_.depth_mm = std::clamp(settings_.depth_mm + 0.1f * io.MouseWheel, 0.0f, 5.0f);
      else
        camera_.dolly(io.MouseWheel);
    }
    if (!turning) cursor_ = Eigen::Vector2d(io.MousePos.x, io.MousePos.y);
    cursor_valid_ = ImGui::IsMousePosValid();
    set_button(io.MouseDown[0]);
  } else if (!io.MouseDown[0]) {
    set_button(false);
  }
  if (!io.WantCaptureKeyboard) {
    const bool ctrl = io.KeyCtrl, shift = io.KeyShift;
    if (key_z_.pressed(win, GLFW_KEY_Z) && ctrl) shift ? redo() : undo();
    if (key_y_.pressed(win, GLFW_KEY_Y) && ctrl) redo();
    if (key_f_.pressed(win, GLFW_KEY_F)) camera_.fit();
  }
}

void Studio::apply_panel(const PanelActions& a) {
  try {
    if (a.undo) undo();
    if (a.redo) redo();
    if (a.fit) camera_.fit();
    if (a.save) save(files_.save);
    if (a.export_model) export_model(files_.export_path);
    if (a.screenshot)
      screenshot(files_.screenshot, false, false), message_ = std::string("screenshot ") + files_.screenshot;
  } catch (const std::exception& e) {
    message_ = e.what();  // a failed save keeps the previous file (save_model is atomic)
  }
}

void Studio::drive_device(const RenderCamera& cam) {
  if (!cursor_valid_ || !mouse_) return;
  const int w = cam.width, h = cam.height;
  const int px = std::clamp(static_cast<int>(cursor_.x()), 0, w - 1);
  const int py = std::clamp(static_cast<int>(cursor_.y()), 0, h - 1);
  const bool editing = button_ && settings_.brush.has_value();
  if (editing && (!stroke_frozen_ || frozen_cam_.view != cam.view || frozen_cam_.projection != cam.projection ||
                  frozen_w_ != w || frozen_h_ != h)) {
    frozen_.resize(static_cast<size_t>(w) * h);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, w, h, GL_DEPTH_COMPONENT, GL_FLOAT, frozen_.data());
    frozen_cam_ = cam, frozen_w_ = w, frozen_h_ = h, stroke_frozen_ = true;
  }
  if (!editing) stroke_frozen_ = false;
  float depth = 1;
  if (stroke_frozen_)
    depth = frozen_[static_cast<size_t>(h - 1 - py) * w + px];
  else
    glReadPixels(px, h - 1 - py, 1, 1, GL_DEPTH_COMPONENT, GL_FLOAT, &depth);
  const double x = px + 0.5, y = py + 0.5;
  const Vec3 far_point = unproject(cam, x, y, 1.0);
  const Vec3 dir = (far_point - cam.eye).normalized();
  if (depth < 1) last_distance_ = (unproject(cam, x, y, depth) - cam.eye).norm();
  const Vec3 hip = cam.eye + (last_distance_ + settings_.depth_mm * mm_) * dir;
  // The turn asked for since the last frame, about the view's axes (model and device axes agree).
  const Eigen::Matrix3d view = cam.view.topLeftCorner<3, 3>().cast<double>();
  if (!have_last_set_)  // held like a pen: the tool's +z (a burr's shaft) up the screen, toward the eye
    handle_orientation_ =
        Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), (view.row(1) + 0.5 * view.row(2)).transpose());
  handle_orientation_ = (Eigen::AngleAxisd(turn_pitch_, view.row(0).transpose()) *
                         Eigen::AngleAxisd(turn_yaw_, view.row(1).transpose()) * handle_orientation_)
                            .normalized();
  turn_yaw_ = turn_pitch_ = 0;
  MouseHandle m;
  m.position = session_->workspace().to_device(hip);
  m.orientation = handle_orientation_;
  m.buttons = editing ? 1u : 0u;
  if (have_last_set_) fig_.max_frame_step_m = std::max(fig_.max_frame_step_m, (m.position - last_set_).norm());
  last_set_ = m.position, have_last_set_ = true;
  mouse_->set(m);
}

void Studio::write_screenshot(const std::string& path, int w, int h) {
  std::vector<uint8_t> rgb(static_cast<size_t>(w) * h * 3), flipped(rgb.size());
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, w, h, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
  const size_t row = static_cast<size_t>(w) * 3;
  for (int r = 0; r < h; ++r) std::copy_n(&rgb[(h - 1 - r) * row], row, &flipped[r * row]);
  write_png(path, w, h, flipped);
  fig_.screenshot_files.push_back(path);
}

void Studio::last_screenshot() {
  int w = 0, h = 0;
  glfwGetFramebufferSize(window_.handle, &w, &h);
  uploader_->update();
  const RenderCamera cam = camera_.camera(w, h);
  glViewport(0, 0, w, h);
  glClearColor(1, 1, 1, 1);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  renderer_->draw(cam);
  write_screenshot(o_.screenshot, w, h);
}

}  // namespace hdm::studio
