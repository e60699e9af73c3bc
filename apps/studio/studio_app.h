// SPDX-License-Identifier: MIT
#pragma once
// The studio's render thread as one object: the window's frame loop (studio.cpp), the mouse and
// scripts driving the device and the camera (studio_input.cpp), the report (studio_report.cpp).
// Internal to hdm-studio.

#include "studio.h"

#include "bake_window.h"
#include "glyphs.h"
#include "mouse_device.h"
#include "orbit_camera.h"
#include "panels.h"
#include "servo_thread.h"
#include "snapshot_uploader.h"
#include "studio_report.h"
#include "studio_script.h"
#include "window.h"

#include <hdm/bridge/bridge_device.h>
#include <hdm/bridge/bridge_secret.h>
#include <hdm/core/error.h>
#include <hdm/io/export_mesh.h>
#include <hdm/io/hdm_file.h>
#include <hdm/render/png.h>
#include <hdm/render/slab_renderer.h>
#include <hdm/session/sculpt_session.h>

#include <Eigen/Core>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace hdm::studio {

/// Seconds on the steady clock [s]: frame times and the script's waits.
double seconds_now();

/// The studio: a SculptSession ticked by its servo thread, drawn by the slab renderer from
/// snapshots, driven by the mouse, a script, a replay or the device bridge.
class Studio final : public ScriptHost {
 public:
  Studio(Window& window, SlabModel model, const StudioOptions& o, const WindowBake* bake = nullptr);
  ~Studio() override;
  int run();

  // ---- ScriptHost ----
  ToolSettings& tool_settings() override { return settings_; }
  void set_cursor(double x, double y, bool button) override;
  bool settled() override;
  void screenshot(const std::string& path, bool ui, bool footprint) override;
  void probe(const std::string& name) override;
  bool device_ended() override { return servo_->ended(); }
  void undo() override { command(SessionCommand::Undo); }
  void redo() override { command(SessionCommand::Redo); }
  void save(const std::string& path) override;
  void export_model(const std::string& path) override;
  void view(double azimuth_deg, double elevation_deg, double zoom, bool on_tool) override;
  void turn_tool(double yaw_deg, double pitch_deg) override;

 private:
  void command(SessionCommand::Kind kind);

  // Stiffness and friction from the panel (or a script) to the servo thread: a command it applies
  // at its next tick, so the servo never waits and never allocates for it.
  void post_proxy_if_changed();

  // The footprint of the brush on the surface: the surface points the brush sphere holds (carve:
  // the sphere whose deepest point is the HIP; add: the one standing `height` above the surface;
  // the others: the sphere about the surface contact point). False when there is none to draw.
  bool set_footprint(const ToolState& t);
  void set_button(bool down);
  void post_brush_if_changed();

  // The mouse in an interactive session: camera on the right and middle buttons and the wheel,
  // the tool on the left button (unless a panel has the mouse), shortcuts.
  void interactive_input();
  void apply_panel(const PanelActions& a);

  // The cursor ray meets the surface drawn (the depth buffer); the handle goes in along the ray
  // by the tool depth. While a stroke lasts, the surface as it was when the stroke began is used,
  // so the tool does not dig into its own groove frame after frame.
  void drive_device(const RenderCamera& cam);

  // The level of detail: fixed, or coarser while the last 8 frames' median is over the budget and
  // finer again under 40 % of it, with 8 frames between changes so that each is measured.
  void choose_level();
  void status_panel(const UploadFrame& up, const ToolState& tool, float width);
  SlabModel snapshot_model() const;

  // The back buffer as drawn so far: the model view before the panels and glyphs, the window after.
  void write_screenshot(const std::string& path, int w, int h);

  // --screenshot: one more frame's model view at the end.
  void last_screenshot();
  void write_report(const ServoStats& st);
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
  PanelFiles files_;
  std::string message_;
  KeyEdge key_z_, key_y_, key_f_;
  // cursor and device
  Eigen::Vector2d cursor_ = Eigen::Vector2d::Zero();
  bool cursor_valid_ = false, button_ = false, stroke_frozen_ = false;
  double last_distance_ = 1;
  // The handle's orientation (device frame) and the turn asked for since the last frame [rad]
  Eigen::Quaterniond handle_orientation_ = Eigen::Quaterniond::Identity();
  double turn_yaw_ = 0, turn_pitch_ = 0;
  std::vector<float> frozen_;
  RenderCamera frozen_cam_;
  int frozen_w_ = 0, frozen_h_ = 0;
  int64_t quiet_after_tick_ = 0, tool_off_since_ = -1;
  Vec3 last_set_ = Vec3::Zero();
  bool have_last_set_ = false;
  // figures
  int level_ = 0;
  long level_changed_at_ = 0;
  uint64_t drawn_epoch_ = 0;
  double epoch_changed_at_ = 0, edits_per_s_ = 0;
  long epoch_changed_frame_ = 0;  // fig_.frames when the drawn epoch last changed
  ServoFigures figures_;
  std::vector<std::string> screenshots_, ui_screenshots_, footprint_screenshots_;
  StudioFigures fig_;
};

}  // namespace hdm::studio
