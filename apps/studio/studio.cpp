// SPDX-License-Identifier: MIT
// The studio's window and render thread: GLFW + Dear ImGui, the slab renderer fed from
// snapshots, the mouse as a device, scripted sessions. Threads and figures: docs/studio.md.
#include "studio.h"

#include "bake_window.h"
#include "glyphs.h"
#include "mouse_device.h"
#include "orbit_camera.h"
#include "panels.h"
#include "servo_thread.h"
#include "snapshot_uploader.h"
#include "studio_script.h"

#include <hdm/bridge/bridge_device.h>
#include <hdm/bridge/bridge_secret.h>
#include <hdm/core/error.h>
#include <hdm/io/export_mesh.h>
#include <hdm/io/hdm_file.h>
#include <hdm/render/png.h>
#include <hdm/render/slab_renderer.h>
#include <hdm/session/sculpt_session.h>

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
namespace {

double seconds_now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Median, 99th percentile and maximum of a copy of @p v.
nlohmann::json percentiles(std::vector<double> v) {
  if (v.empty()) return {{"median", nullptr}, {"p99", nullptr}, {"max", nullptr}, {"count", 0}};
  std::sort(v.begin(), v.end());
  const size_t p99 = std::min(v.size() - 1, static_cast<size_t>(0.99 * double(v.size())));
  return {{"median", v[v.size() / 2]}, {"p99", v[p99]}, {"max", v.back()}, {"count", v.size()}};
}

// GLFW's window and context, and Dear ImGui on them; torn down in reverse.
struct Window {
  GLFWwindow* handle = nullptr;
  bool imgui = false;
  Window(int width, int height, const std::string& title, bool vsync) {
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
  ~Window() {
    if (imgui) {
      ImGui_ImplOpenGL3_Shutdown();
      ImGui_ImplGlfw_Shutdown();
      ImGui::DestroyContext();
    }
    glfwDestroyWindow(handle);
    glfwTerminate();
  }
};

// Edge detection of a key held down.
struct KeyEdge {
  bool was = false;
  bool pressed(GLFWwindow* w, int key) {
    const bool now = glfwGetKey(w, key) == GLFW_PRESS;
    const bool edge = now && !was;
    was = now;
    return edge;
  }
};

class Studio final : public ScriptHost {
 public:
  Studio(Window& window, SlabModel model, const StudioOptions& o, const WindowBake* bake = nullptr)
      : o_(o), window_(window) {
    if (bake) bake_ = *bake;
    if (!o.script.empty()) player_.emplace(read_studio_script(o.script));
    Aabb box;
    for (const Vec3f& p : model.positions) box.extend(p.cast<double>());
    const Workspace ws = fit_workspace(box, DeviceSpec{}.workspace_m);
    mm_ = ws.scale / 1000;
    SessionOptions so;
    so.proxy.force.stiffness = o.stiffness;
    so.proxy.friction_scale = o.friction_scale;
    if (o.ball) so.mode = RenderMode::Sphere;
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
      auto bridge = bridge::BridgeDevice::open(o.device, bo);
      bridge_ = bridge.get();
      device_ = std::move(bridge);
      settings_.kind = ToolSettings::Carve;  // the driver's tool button strokes with the panel's brush
      post_brush_if_changed();
    } else if (o.replay.empty()) {
      auto mouse = std::make_unique<MouseDevice>(o.rate_hz);
      mouse_ = mouse.get();
      device_ = std::move(mouse);
    } else {
      device_ = std::make_unique<ReplayDevice>(o.replay);
      settings_.kind = ToolSettings::Carve;  // the recording's tool button strokes with the panel's brush
      post_brush_if_changed();
    }
    servo_ = std::make_unique<ServoThread>(*session_, *device_, o.rate_hz, bridge_);
  }

  ~Studio() override {
    if (servo_) servo_->stop();
  }

  int run() {
    int code = 0;
    double last = seconds_now(), figures_at = last;
    int64_t sweeps_then = 0;
    bool last_frame = false;  // the script has ended: draw this frame (its screenshots), then stop
    for (long frame = 0; !last_frame && !glfwWindowShouldClose(window_.handle) && (o_.frames < 0 || frame < o_.frames);
         ++frame) {
      const double start = seconds_now();
      if (frame > 0) frame_ms_.push_back((start - last) * 1e3);
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
      uploads_.push_back(up.uploaded);
      if (up.dirty >= 0) dirty_total_ += up.dirty, mismatched_total_ += up.mismatched;
      if (up.epoch != drawn_epoch_) drawn_epoch_ = up.epoch, epoch_changed_at_ = start;

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
      levels_.push_back(level_);
      drive_device(cam);
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
      ++frames_;
    }
    if (player_ && !script_done_ && code == 0) {
      std::fprintf(stderr, "hdm-studio: %s: the script stopped at step %zu after %ld frames (--frames)\n",
                   o_.script.c_str(), player_->step() + 1, frames_);
      code = 1;
    }
    if (!o_.screenshot.empty()) last_screenshot();
    const ServoStats& st = servo_->stop();
    write_report(st);
    return code;
  }

  // ---- ScriptHost ----
  ToolSettings& tool_settings() override { return settings_; }
  void set_cursor(double x, double y, bool button) override {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_.handle, &w, &h);
    cursor_ = Eigen::Vector2d(x * w, y * h);
    cursor_valid_ = true;
    set_button(button);
  }
  bool settled() override {
    const ToolState& t = servo_->tool();
    // The mouse's button reaches the servo up to a frame late (MouseDevice's smoothing): count the
    // quiet ticks from the first tick seen with the tool off.
    if (t.tool_on)
      tool_off_since_ = -1;
    else if (tool_off_since_ < 0)
      tool_off_since_ = t.tick;
    const bool quiet = tool_off_since_ >= 0 && t.tick - tool_off_since_ >= static_cast<int64_t>(0.03 * o_.rate_hz);
    return !button_ && !t.tool_on && quiet && !t.edit_pending && t.tick >= quiet_after_tick_ &&
           session_->snapshots()->epoch() == drawn_epoch_ && seconds_now() - epoch_changed_at_ > 0.05;
  }
  void screenshot(const std::string& path, bool ui, bool footprint) override {
    (ui ? ui_screenshots_ : footprint ? footprint_screenshots_ : screenshots_).push_back(path);
  }
  void probe(const std::string& name) override {
    const ToolState& t = servo_->tool();
    auto v = [](const Vec3& p) { return nlohmann::json::array({p.x(), p.y(), p.z()}); };
    probes_[name] = {{"tick", t.tick},
                     {"contact", t.contact},
                     {"hip_m", v(workspace_.to_device(t.hip))},
                     {"proxy_m", v(workspace_.to_device(t.proxy))},
                     {"normal", v(t.normal)},
                     {"force_n", v(t.force)},
                     {"stiffness_n_per_m", settings_.stiffness},
                     {"friction", settings_.friction}};
  }
  bool device_ended() override { return servo_->ended(); }
  void undo() override { command(SessionCommand::Undo); }
  void redo() override { command(SessionCommand::Redo); }
  void save(const std::string& path) override {
    SlabModel copy = snapshot_model();
    save_model(copy, path);
    message_ = "saved " + path;
  }
  void export_model(const std::string& path) override {
    SlabModel copy = snapshot_model();
    rebuild_derived(copy);
    export_mesh(copy, path);
    message_ = "exported " + path;
  }
  void view(double azimuth_deg, double elevation_deg, double zoom) override {
    camera_.azimuth_deg = azimuth_deg, camera_.elevation_deg = elevation_deg;
    camera_.fit();
    camera_.zoom = zoom;
  }

 private:
  void command(SessionCommand::Kind kind) {
    SessionCommand c;
    c.kind = kind;
    if (!session_->post(c)) message_ = "the servo's command queue is full";
    quiet_after_tick_ = servo_->ticks() + static_cast<int64_t>(0.03 * o_.rate_hz) + 1;
  }

  // Stiffness and friction from the panel (or a script) to the servo thread: a command it applies
  // at its next tick, so the servo never waits and never allocates for it.
  void post_proxy_if_changed() {
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

  // The footprint of the brush on the surface: the surface points the brush sphere holds (carve:
  // the sphere whose deepest point is the HIP; add: the one standing `height` above the surface;
  // the others: the sphere about the surface contact point). False when there is none to draw.
  bool set_footprint(const ToolState& t) {
    const double r = settings_.radius_mm * mm_;
    Vec3 centre = t.proxy;
    if (settings_.kind == ToolSettings::Carve)  // a ball's centre is the HIP, a point's is r above it
      centre = t.hip + t.normal * ((t.ball ? 0.0 : r) + settings_.resilience_mm * mm_);
    else if (settings_.kind == ToolSettings::Add)
      centre = t.proxy + t.normal * (settings_.height_mm * mm_ - r);
    const bool on = t.contact && settings_.kind != ToolSettings::Probe && centre.allFinite();
    renderer_->set_footprint(centre, on ? r : 0.0);
    return on;
  }

  void set_button(bool down) {
    if (button_ && !down) quiet_after_tick_ = servo_->ticks() + static_cast<int64_t>(0.03 * o_.rate_hz) + 1;
    button_ = down;
  }

  void post_brush_if_changed() {
    if (settings_.kind == ToolSettings::Probe) return;
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

  // The mouse in an interactive session: camera on the right and middle buttons and the wheel,
  // the tool on the left button (unless a panel has the mouse), shortcuts.
  void interactive_input() {
    ImGuiIO& io = ImGui::GetIO();
    GLFWwindow* win = window_.handle;
    int h = 0, w = 0;
    glfwGetFramebufferSize(win, &w, &h);
    if (!io.WantCaptureMouse) {
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
      cursor_ = Eigen::Vector2d(io.MousePos.x, io.MousePos.y);
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

  void apply_panel(const PanelActions& a) {
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

  // The cursor ray meets the surface drawn (the depth buffer); the handle goes in along the ray
  // by the tool depth. While a stroke lasts, the surface as it was when the stroke began is used,
  // so the tool does not dig into its own groove frame after frame.
  void drive_device(const RenderCamera& cam) {
    if (!cursor_valid_ || !mouse_) return;
    const int w = cam.width, h = cam.height;
    const int px = std::clamp(static_cast<int>(cursor_.x()), 0, w - 1);
    const int py = std::clamp(static_cast<int>(cursor_.y()), 0, h - 1);
    const bool editing = button_ && settings_.kind != ToolSettings::Probe;
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
    MouseHandle m;
    m.position = session_->workspace().to_device(hip);
    m.buttons = editing ? 1u : 0u;
    if (have_last_set_) max_frame_step_m_ = std::max(max_frame_step_m_, (m.position - last_set_).norm());
    last_set_ = m.position, have_last_set_ = true;
    mouse_->set(m);
  }

  // The level of detail: fixed, or coarser while the last 8 frames' median is over the budget and
  // finer again under 40 % of it, with 8 frames between changes so that each is measured.
  void choose_level() {
    const int levels = renderer_->level_count();
    if (o_.lod >= 0) {
      level_ = std::min(o_.lod, levels - 1);
      return;
    }
    if (frame_ms_.size() < 8 || static_cast<long>(frame_ms_.size()) - level_changed_at_ < 8) return;
    std::vector<double> last(frame_ms_.end() - 8, frame_ms_.end());
    std::nth_element(last.begin(), last.begin() + 4, last.end());
    const double median = last[4];
    const int before = level_;
    if (median > o_.frame_budget_ms && level_ + 1 < levels)
      ++level_;
    else if (median < 0.4 * o_.frame_budget_ms && level_ > 0)
      --level_;
    if (level_ != before) level_changed_at_ = static_cast<long>(frame_ms_.size());
  }

  void status_panel(const UploadFrame& up, const ToolState& tool, float width) {
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
    if (!frame_ms_.empty()) {
      std::vector<double> recent(frame_ms_.end() - std::min<size_t>(frame_ms_.size(), 120), frame_ms_.end());
      std::sort(recent.begin(), recent.end());
      s.frame_ms_median = recent[recent.size() / 2];
      s.frame_ms_p99 = recent[std::min(recent.size() - 1, static_cast<size_t>(0.99 * double(recent.size())))];
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

  SlabModel snapshot_model() const {
    SnapshotReader reader(*session_->snapshots());
    return reader.stored_model();
  }

  // The back buffer as drawn so far: the model view before the panels and glyphs, the window after.
  void write_screenshot(const std::string& path, int w, int h) {
    std::vector<uint8_t> rgb(static_cast<size_t>(w) * h * 3), flipped(rgb.size());
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, w, h, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
    const size_t row = static_cast<size_t>(w) * 3;
    for (int r = 0; r < h; ++r) std::copy_n(&rgb[(h - 1 - r) * row], row, &flipped[r * row]);
    write_png(path, w, h, flipped);
    screenshot_files_.push_back(path);
  }

  // --screenshot: one more frame's model view at the end.
  void last_screenshot() {
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

  std::vector<long> frames_per_level() const {
    std::vector<long> n(static_cast<size_t>(std::max(renderer_->level_count(), 1)), 0);
    for (int l : levels_) ++n[static_cast<size_t>(l)];
    return n;
  }

  void write_report(const ServoStats& st) {
    if (o_.report.empty()) return;
    const SessionStats& ss = session_->stats();  // the servo has stopped
    std::vector<double> skip_first(frame_ms_.begin() + std::min<size_t>(frame_ms_.size(), 3), frame_ms_.end());
    int64_t total = 0, frames_with = 0, most = 0;
    for (int u : uploads_) total += u, frames_with += u > 0, most = std::max<int64_t>(most, u);
    nlohmann::json j = {
        {"model", o_.model_name},
        {"size", {o_.width, o_.height}},
        {"frames", frames_},
        {"frame_ms", percentiles(skip_first)},
        {"slabs", slabs_},
        {"lod",
         {{"mode", o_.lod < 0 ? nlohmann::json("auto") : nlohmann::json(o_.lod)},
          {"frame_budget_ms", o_.frame_budget_ms},
          {"frames_per_level", frames_per_level()}}},
        {"uploads",
         {{"total", total}, {"frames_with_uploads", frames_with}, {"max_per_frame", most}, {"per_frame", uploads_}}},
        {"servo",
         {{"target_rate_hz", o_.rate_hz},
          {"rate_hz", st.rate_hz},
          {"ticks", st.ticks},
          {"seconds", st.seconds},
          {"late_ticks", st.overruns},
          {"long_ticks", st.long_ticks},
          {"watchdog_trips", st.watchdog_trips},
          {"realtime", servo_->realtime_note() ? servo_->realtime_note() : "SCHED_FIFO"},
          {"tick_ns", {{"median", st.compute_ns.median}, {"p99", st.compute_ns.p99}, {"max", st.compute_ns.max}}},
          {"period_ns", {{"median", st.period_ns.median}, {"p99", st.period_ns.p99}, {"max", st.period_ns.max}}}}},
        {"session",
         {{"sweeps", ss.sweeps},
          {"changed", ss.changed},
          {"publications", ss.publications},
          {"slabs_published", ss.slabs_published},
          {"publish_deferred", ss.publish_deferred}}},
        {"screenshots", screenshot_files_},
        {"workspace",
         {{"origin", {workspace_.origin.x(), workspace_.origin.y(), workspace_.origin.z()}},
          {"scale", workspace_.scale}}},
        {"probes", probes_}};
    if (mouse_)  // the mouse's smoothing: the handle's largest move per tick against per frame
      j["mouse"] = {{"max_tick_step_m", mouse_->max_tick_step_m()}, {"max_frame_step_m", max_frame_step_m_}};
    if (bake_)
      j["bake"] = {{"input", bake_->input},
                   {"seconds", bake_->seconds},
                   {"frames", bake_->frames},
                   {"stages", bake_->stages},
                   {"slabs", bake_->slabs},
                   {"grid", bake_->grid},
                   {"met", bake_->met},
                   {"max_pct", bake_->max_pct},
                   {"max_back_pct", bake_->max_back_pct},
                   {"rms_pct", bake_->rms_pct},
                   {"rms_back_pct", bake_->rms_back_pct}};
    if (o_.verify_uploads) j["uploads"]["dirty_total"] = dirty_total_, j["uploads"]["mismatched"] = mismatched_total_;
    const std::string text = j.dump(1);
    write_file_atomic(o_.report, text.data(), text.size());
  }

  StudioOptions o_;
  Window& window_;
  std::optional<WindowBake> bake_;
  std::optional<ScriptPlayer> player_;
  bool script_done_ = false;
  double mm_ = 1;
  int slabs_ = 0;
  std::unique_ptr<SculptSession> session_;
  std::unique_ptr<SlabRenderer> renderer_;
  std::unique_ptr<SnapshotUploader> uploader_;
  std::unique_ptr<HapticDevice> device_;
  MouseDevice* mouse_ = nullptr;            // the device when it is the mouse
  bridge::BridgeDevice* bridge_ = nullptr;  // the device when it comes through the bridge
  std::unique_ptr<ServoThread> servo_;
  OrbitCamera camera_;
  ToolSettings settings_;
  Brush posted_brush_;
  bool posted_ = false;
  ProxyParams posted_proxy_;
  Workspace workspace_;
  nlohmann::json probes_ = nlohmann::json::object();
  PanelFiles files_;
  std::string message_;
  KeyEdge key_z_, key_y_, key_f_;
  // cursor and device
  Eigen::Vector2d cursor_ = Eigen::Vector2d::Zero();
  bool cursor_valid_ = false, button_ = false, stroke_frozen_ = false;
  double last_distance_ = 1;
  std::vector<float> frozen_;
  RenderCamera frozen_cam_;
  int frozen_w_ = 0, frozen_h_ = 0;
  int64_t quiet_after_tick_ = 0, tool_off_since_ = -1;
  Vec3 last_set_ = Vec3::Zero();
  bool have_last_set_ = false;
  double max_frame_step_m_ = 0;
  // figures
  std::vector<double> frame_ms_;
  std::vector<int> uploads_;
  int64_t dirty_total_ = 0, mismatched_total_ = 0;
  int level_ = 0;
  long level_changed_at_ = 0;
  std::vector<int> levels_;
  long frames_ = 0;
  uint64_t drawn_epoch_ = 0;
  double epoch_changed_at_ = 0, edits_per_s_ = 0;
  ServoFigures figures_;
  std::vector<std::string> screenshots_, ui_screenshots_, footprint_screenshots_, screenshot_files_;
};

}  // namespace

namespace {

void check_options(const StudioOptions& options) {
  if (!(options.rate_hz >= 100 && options.rate_hz <= 20000))
    throw InvalidInput("--rate " + std::to_string(options.rate_hz) + ": the servo rate must be in [100, 20000] Hz");
  if (options.width < 64 || options.height < 64 || options.width > 8192 || options.height > 8192)
    throw InvalidInput("--size: the window must be 64..8192 pixels on each side");
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
