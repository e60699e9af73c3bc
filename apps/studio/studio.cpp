// SPDX-License-Identifier: MIT
// The studio's window and render thread: GLFW + Dear ImGui, the slab renderer fed from
// snapshots, the mouse as a device, scripted sessions. Threads and figures: docs/studio.md.
#include "studio_app.h"

#include <hdm/core/percentile.h>

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>

namespace hdm::studio {

double seconds_now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

Studio::Studio(Window& window, SlabModel model, const StudioOptions& o, const WindowBake* bake)
    : o_(o), window_(window) {
  if (bake) bake_ = *bake;
  if (!o.script.empty()) player_.emplace(read_studio_script(o.script));
  const Aabb box = surface_box(model);
  const Workspace ws = fit_workspace(box, DeviceSpec{}.workspace_m);
  mm_ = ws.scale / 1000;
  SessionOptions so;
  so.proxy.force.stiffness = o.stiffness;
  so.proxy.friction_scale = o.friction_scale;
  if (o.ball) so.mode = RenderMode::Sphere;
  if (o.burr) so.mode = RenderMode::RigidTool;
  // Lockstep: each tick finishes its edits and publications, whatever they cost (no time budget).
  if (o.ticks_per_frame > 0) so.edit_budget_s = 10;
  posted_proxy_ = so.proxy;
  settings_.stiffness = static_cast<float>(o.stiffness);
  settings_.friction = static_cast<float>(o.friction_scale);
  workspace_ = ws;
  slabs_ = model.slab_count();
  session_ = std::make_unique<SculptSession>(std::move(model), ws, so);
  renderer_ = std::make_unique<SlabRenderer>();
  // Before the servo starts: the uploader's first upload reads the live model.
  uploader_ = std::make_unique<SnapshotUploader>(*session_->snapshots(), *renderer_, o.verify_uploads);
  const RenderCamera fitted = fit_camera(session_->snapshots()->model(), o.width, o.height, 0, 15);
  camera_.centre = camera_.target = fitted.target;
  camera_.radius = fitted.radius;
  last_distance_ = (fitted.eye - fitted.target).norm();
  if (!o.device.empty()) {
    bridge::BridgeOptions bo;
    bo.secret = bridge::load_bridge_secret(o.secret_file);
    bo.watchdog_s = o.watchdog_ms * 1e-3;
    // The burr's torque goes out to a 6-DOF driver, clamped as the rigid tool clamps it.
    if (o.burr) bo.spec.max_torque_nm = so.rigid.max_torque;
    auto bridge = bridge::BridgeDevice::open(o.device, bo);
    bridge_ = bridge.get();
    device_ = std::move(bridge);
    settings_.brush = BrushTool::Carve;  // the driver's tool button strokes with the panel's brush
    post_brush_if_changed();
  } else if (o.replay.empty()) {
    auto mouse = std::make_unique<MouseDevice>(o.rate_hz);
    mouse_ = mouse.get();
    device_ = std::move(mouse);
  } else {
    device_ = std::make_unique<ReplayDevice>(o.replay);
    settings_.brush = BrushTool::Carve;  // the recording's tool button strokes with the panel's brush
    post_brush_if_changed();
  }
  servo_ = std::make_unique<ServoThread>(*session_, *device_, o.rate_hz, bridge_, o.ticks_per_frame > 0);
}

Studio::~Studio() {
  if (servo_) servo_->stop();
}

int Studio::run() {
  int code = 0;
  double last = seconds_now(), figures_at = last;
  int64_t sweeps_then = 0;
  bool last_frame = false;  // the script has ended: draw this frame (its screenshots), then stop
  for (long frame = 0; !last_frame && !glfwWindowShouldClose(window_.handle) && (o_.frames < 0 || frame < o_.frames);
       ++frame) {
    const double start = seconds_now();
    if (frame > 0) fig_.frame_ms.push_back((start - last) * 1e3);
    last = start;
    glfwPollEvents();
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();

    if (player_ && !script_done_) {
      try {
        script_done_ = !player_->frame(*this);
        last_frame = script_done_ && o_.frames < 0;
      } catch (const std::exception& e) {
        std::fprintf(stderr, "hdm-studio: %s\n", e.what());
        code = 1;
        break;
      }
    } else if (!player_) {
      interactive_input();
    }
    post_brush_if_changed();
    post_proxy_if_changed();

    const UploadFrame up = uploader_->update();
    fig_.uploads.push_back(up.uploaded);
    if (up.dirty >= 0) fig_.dirty_total += up.dirty, fig_.mismatched_total += up.mismatched;
    if (up.epoch != drawn_epoch_)
      drawn_epoch_ = up.epoch, epoch_changed_at_ = start, epoch_changed_frame_ = fig_.frames;

    int w = 0, h = 0;
    glfwGetFramebufferSize(window_.handle, &w, &h);
    if (w <= 0 || h <= 0) {  // minimised
      glfwSwapBuffers(window_.handle);
      ImGui::Render();
      continue;
    }
    const RenderCamera cam = camera_.camera(w, h);
    glViewport(0, 0, w, h);
    glClearColor(1, 1, 1, 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    choose_level();
    const ToolState& tool = servo_->tool();
    const bool footprint = set_footprint(tool);
    renderer_->draw(cam, false, level_);
    fig_.levels.push_back(level_);
    drive_device(cam);
    servo_->step(o_.ticks_per_frame);       // lockstep: this frame's ticks, with this frame's handle
    if (!footprint_screenshots_.empty()) {  // the model view with the footprint, at full detail
      if (level_ > 0) glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT), renderer_->draw(cam);
      for (const std::string& path : footprint_screenshots_) write_screenshot(path, w, h);
      footprint_screenshots_.clear();
    }
    if (!screenshots_.empty() && (level_ > 0 || footprint)) {  // screenshots at full detail, no footprint
      renderer_->set_footprint(Vec3::Zero(), 0);
      glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
      renderer_->draw(cam);
    }
    for (const std::string& path : screenshots_) write_screenshot(path, w, h);
    screenshots_.clear();

    // Panels and glyphs.
    GlyphOptions g;
    g.brush_radius = settings_.radius_mm * mm_;
    g.newton_length = 5 * mm_;  // 5 mm per newton
    g.shell = &session_->tool_shell();
    draw_tool_glyphs(ImGui::GetBackgroundDrawList(), cam, tool, g);
    if (start - figures_at >= 0.5) {
      const ServoFigures f = servo_->figures();
      edits_per_s_ = (f.sweeps - sweeps_then) / (start - figures_at);
      sweeps_then = f.sweeps, figures_at = start, figures_ = f;
    }
    status_panel(up, tool, static_cast<float>(w));
    const PanelActions a = draw_tools_panel(settings_, files_, message_);
    if (!player_) apply_panel(a);
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    for (const std::string& path : ui_screenshots_) write_screenshot(path, w, h);
    ui_screenshots_.clear();
    glfwSwapBuffers(window_.handle);
    ++fig_.frames;
  }
  if (player_ && !script_done_ && code == 0) {
    std::fprintf(stderr, "hdm-studio: %s: the script stopped at step %zu after %ld frames (--frames)\n",
                 o_.script.c_str(), player_->step() + 1, fig_.frames);
    code = 1;
  }
  if (!o_.screenshot.empty()) last_screenshot();
  const ServoStats& st = servo_->stop();
  write_report(st);
  return code;
}

void Studio::command(SessionCommand::Kind kind) {
  SessionCommand c;
  c.kind = kind;
  if (!session_->post(c)) message_ = "the servo's command queue is full";
  quiet_after_tick_ = servo_->ticks() + static_cast<int64_t>(0.03 * o_.rate_hz) + 1;
}

void Studio::post_proxy_if_changed() {
  if (settings_.stiffness == posted_proxy_.force.stiffness && settings_.friction == posted_proxy_.friction_scale)
    return;
  SessionCommand c;
  c.kind = SessionCommand::SetProxy;
  c.proxy = posted_proxy_;
  c.proxy.force.stiffness = settings_.stiffness;
  c.proxy.friction_scale = settings_.friction;
  if (!session_->post(c)) return;  // the queue is full: try again next frame
  posted_proxy_ = c.proxy;
  quiet_after_tick_ = servo_->ticks() + static_cast<int64_t>(0.03 * o_.rate_hz) + 1;
}

void Studio::post_brush_if_changed() {
  if (!settings_.brush) return;
  const Brush b = tool_brush(settings_, mm_);
  const Brush& p = posted_brush_;
  if (posted_ && b.tool == p.tool && b.radius == p.radius && b.strength == p.strength && b.falloff == p.falloff &&
      b.resilience == p.resilience && b.height == p.height && b.field == p.field && b.colour == p.colour &&
      b.value == p.value)
    return;
  SessionCommand c;
  c.kind = SessionCommand::SetBrush;
  c.brush = b;
  if (session_->post(c)) posted_brush_ = b, posted_ = true;
}

void Studio::choose_level() {
  const int levels = renderer_->level_count();
  if (o_.lod >= 0) {
    level_ = std::min(o_.lod, levels - 1);
    return;
  }
  if (fig_.frame_ms.size() < 8 || static_cast<long>(fig_.frame_ms.size()) - level_changed_at_ < 8) return;
  std::vector<double> last(fig_.frame_ms.end() - 8, fig_.frame_ms.end());
  std::nth_element(last.begin(), last.begin() + 4, last.end());
  const double median = last[4];
  const int before = level_;
  if (median > o_.frame_budget_ms && level_ + 1 < levels)
    ++level_;
  else if (median < 0.4 * o_.frame_budget_ms && level_ > 0)
    --level_;
  if (level_ != before) level_changed_at_ = static_cast<long>(fig_.frame_ms.size());
}

void Studio::status_panel(const UploadFrame& up, const ToolState& tool, float width) {
  StatusFigures s;
  s.servo_rate_hz = figures_.rate_hz;
  s.target_rate_hz = o_.rate_hz;
  s.tick_p99_us = figures_.tick_p99_ns / 1e3;
  s.late_ticks = figures_.late_ticks;
  if (bridge_) {
    const bridge::BridgeCounters c = bridge_->counters();
    s.bridge = bridge_->endpoint().c_str();
    s.bridge_accepted = c.accepted;
    s.bridge_dropped = c.dropped();
    s.bridge_watchdog_trips = c.watchdog_trips;
  }
  if (!fig_.frame_ms.empty()) {
    std::vector<double> recent(fig_.frame_ms.end() - std::min<size_t>(fig_.frame_ms.size(), 120), fig_.frame_ms.end());
    s.frame_ms_median = percentile(recent, 0.5);
    s.frame_ms_p99 = percentile(recent, 0.99);
  }
  s.uploaded = up.uploaded;
  s.uploaded_total = uploader_->total_uploaded();
  s.edits_per_s = edits_per_s_;
  s.epoch = up.epoch;
  s.contact = tool.contact;
  s.force_n = tool.force.norm();
  s.slabs = slabs_;
  s.level = level_;
  s.grid = session_->snapshots()->model().grid_n >> level_;
  draw_status_overlay(s, width);
}

SlabModel Studio::snapshot_model() const {
  SnapshotReader reader(*session_->snapshots());
  return reader.stored_model();
}

void Studio::write_report(const ServoStats& st) {
  if (o_.report.empty()) return;
  const StudioReportContext c{o_,         fig_,
                              slabs_,     renderer_->level_count(),
                              workspace_, servo_->realtime_note() ? servo_->realtime_note() : "SCHED_FIFO",
                              mouse_,     bake_ ? &*bake_ : nullptr};
  write_studio_report(c, st, session_->stats());  // the servo has stopped
}

namespace {

void check_options(const StudioOptions& options) {
  if (!(options.rate_hz >= 100 && options.rate_hz <= 20000))
    throw InvalidInput("--rate " + std::to_string(options.rate_hz) + ": the servo rate must be in [100, 20000] Hz");
  if (options.width < 64 || options.height < 64 || options.width > 8192 || options.height > 8192)
    throw InvalidInput("--size: the window must be 64..8192 pixels on each side");
  if (options.ticks_per_frame < 0 ||
      (options.ticks_per_frame > 0 && (options.script.empty() || !options.device.empty() || !options.replay.empty())))
    throw InvalidInput("--ticks-per-frame: a scripted session with the mouse only, and not negative");
}

}  // namespace

int run_studio(SlabModel model, const StudioOptions& options) {
  check_options(options);
  Window window(options.width, options.height, "hdm studio - " + options.model_name,
                options.vsync && options.script.empty());
  Studio studio(window, std::move(model), options);
  return studio.run();
}

int run_studio_baking(const std::string& mesh_path, const StudioOptions& options) {
  check_options(options);
  Window window(options.width, options.height, "hdm studio - " + options.model_name,
                options.vsync && options.script.empty());
  WindowBake bake;
  SlabModel model = bake_in_window(window.handle, mesh_path, bake);
  if (bake.closed) return 0;
  Studio studio(window, std::move(model), options, &bake);
  return studio.run();
}

}  // namespace hdm::studio
