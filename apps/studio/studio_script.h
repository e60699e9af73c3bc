// SPDX-License-Identifier: MIT
#pragma once
// Scripted studio sessions: device and UI actions without a person, for tests and demos
// (`hdm-studio MODEL --script S.json --frames N --screenshot OUT.png`). Format: docs/studio.md.
#include "studio.h"

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace hdm::studio {

/// One step of a script.
struct ScriptStep {
  enum Kind {
    Tool,
    Cursor,
    Stroke,
    Wait,
    Settle,
    Screenshot,
    Undo,
    Redo,
    Save,
    Export,
    View,
    Probe,
    Turn,
    DeviceEnd
  } kind = Wait;
  nlohmann::json tool;                  ///< Tool: the settings it changes
  std::vector<Eigen::Vector2d> points;  ///< Cursor (one) / Stroke (two or more): window coordinates in [0,1], y down
  int frames = 0;                       ///< Stroke: frames the cursor takes along the points; Wait: frames
  std::string path;                     ///< Screenshot, Save, Export: output file; Probe: the record's name
  bool ui = false;                      ///< Screenshot: the whole window, panels and tool glyphs included
  bool footprint = false;               ///< Screenshot: the model view with the brush's footprint on the surface
  double azimuth_deg = 0, elevation_deg = 15, zoom = 1;  ///< View
  /// View: about the tool's tip (the god-object's, else the proxy) instead of the model's centre
  bool on_tool = false;
  /// Turn: the tool's turn about the view's vertical and horizontal axes [degrees]
  double yaw_deg = 0, pitch_deg = 0;
};

/// @brief Reads a script file: {"steps": [ {action: ...}, ... ]}.
/// @throws IoError when @p path cannot be read; InvalidInput naming the file and the step on a
///         malformed step (unknown action, bad coordinates, unknown tool or field).
std::vector<ScriptStep> read_studio_script(const std::string& path);

/// @brief Applies the settings of a "tool" step (`tool`, `radius_mm`, `strength`, `depth_mm`,
/// `height_mm`, `resilience_mm`, `field`, `colour`, `value`, `stiffness`, `friction`) to @p t.
/// @throws InvalidInput naming @p where and the key on an unknown key or a value out of range.
void apply_tool_json(const nlohmann::json& j, ToolSettings& t, const std::string& where);

/// What a script acts on: the studio.
class ScriptHost {
 public:
  virtual ~ScriptHost() = default;
  virtual ToolSettings& tool_settings() = 0;
  /// The cursor at window coordinates (x, y) in [0,1], with the tool button held or not.
  virtual void set_cursor(double x, double y, bool button) = 0;
  /// True when the tool is off, the servo has no edit work left and the newest epoch is drawn.
  virtual bool settled() = 0;
  /// A PNG of this frame's model view (@p ui: of the whole window, panels and glyphs included;
  /// @p footprint: the model view with the brush's footprint drawn on the surface).
  virtual void screenshot(const std::string& path, bool ui, bool footprint) = 0;
  /// Records the tool state the servo thread left (HIP, proxy, normal, force, contact) under
  /// @p name in the report.
  virtual void probe(const std::string& name) = 0;
  /// True once the device has ended (a replay's last row, the bridge driver's end packet) and the
  /// servo loop has stopped.
  virtual bool device_ended() = 0;
  virtual void undo() = 0;
  virtual void redo() = 0;
  virtual void save(const std::string& path) = 0;
  virtual void export_model(const std::string& path) = 0;
  /// Sets the camera: view direction [degrees, as `hdm render --view`] and zoom (1: the model
  /// fits) about the model's centre, or with @p on_tool about the tool's tip as the servo left it.
  virtual void view(double azimuth_deg, double elevation_deg, double zoom, bool on_tool) = 0;
  /// Turns the handle (a rigid tool) by @p yaw_deg about the view's vertical axis, then
  /// @p pitch_deg about its horizontal axis, as Alt with the mouse does.
  virtual void turn_tool(double yaw_deg, double pitch_deg) = 0;
};

/// Plays a script one frame at a time.
class ScriptPlayer {
 public:
  explicit ScriptPlayer(std::vector<ScriptStep> steps) : steps_(std::move(steps)) {}
  /// @brief Runs the steps due at this frame (instant steps run together; a stroke, a wait or a
  /// settle takes frames). @return false once every step has run.
  /// @throws InvalidInput when a settle waits longer than 20 s (the session never goes idle) or a
  /// device_end longer than 60 s.
  bool frame(ScriptHost& host);
  bool done() const noexcept { return next_ >= steps_.size(); }
  /// Index of the step running or next.
  size_t step() const noexcept { return next_; }

 private:
  // A waiting step: true once @p done (the step ends); throws InvalidInput naming @p what after
  // @p limit_s seconds of waiting.
  bool waited(bool done, double limit_s, const char* what);

  std::vector<ScriptStep> steps_;
  size_t next_ = 0;
  int frame_in_step_ = 0;
  double settle_started_ = -1;
};

}  // namespace hdm::studio
