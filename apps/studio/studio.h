// SPDX-License-Identifier: MIT
#pragma once
// hdm studio: a window where a person sculpts and paints a slab model with the mouse (or, later,
// a device through the bridge) while the servo loop runs on its own thread. The render thread
// reads the model only through SlabSnapshots and re-uploads only the slabs published since the
// last frame (paper §6-7).
#include <hdm/edit/brush.h>
#include <hdm/slab/slab_model.h>

#include <optional>
#include <string>

namespace hdm::studio {

/// How the studio starts.
struct StudioOptions {
  std::string model_name;          ///< shown in the title and the report
  int width = 1280, height = 720;  ///< window size [pixels]
  double rate_hz = 1000;           ///< servo rate: 1000 or 10000 [Hz]
  double stiffness = 1000;         ///< proxy stiffness as felt at the device [N/m]
  double friction_scale = 1;       ///< factor on the model's friction coefficients
  /// Feel the brush as a ball of its radius held outside the surface (RenderMode::Sphere) instead
  /// of a point: the ball cannot enter a gap narrower than itself, and carving cuts with it.
  bool ball = false;
  /// Feel the tool as a rigid dental burr with torque (RenderMode::RigidTool: a 6-DOF god-object,
  /// rigid_tool.h), drawn as its point shell; the mouse turns it with Alt held. Excludes `ball`.
  bool burr = false;
  std::string script;  ///< scripted session (JSON); empty: interactive
  /// Replay this recording (`hdm sculpt --forces` CSV: positions and the tool button) as the
  /// device instead of the mouse; the strokes use the panel's brush (carve unless changed).
  std::string replay;
  /// Take the device from the bridge (docs/bridge.md): "udp:PORT" or "shm:NAME"; the strokes use
  /// the panel's brush (carve unless changed). Empty: the mouse (or the replay).
  std::string device;
  /// The bridge's shared secret file (bridge::load_bridge_secret(); empty: HDM_BRIDGE_SECRET).
  std::string secret_file;
  /// With `device`: the silence after which the bridge releases the tool and ramps the force out
  /// [ms] (bridge::BridgeOptions::watchdog_s), > 0.
  double watchdog_ms = 5;
  /// Scripted sessions: the servo loop runs exactly this many ticks per frame, back to back, in
  /// lockstep with the frames (and edits without a time budget), so that a script's run is the same
  /// every time; 0: in real time beside the frames.
  int ticks_per_frame = 0;
  long frames = -1;             ///< stop after this many frames (-1: when the script ends or the window closes)
  std::string screenshot;       ///< write the last frame's model view here (PNG)
  std::string report;           ///< write the session's figures here (JSON)
  bool verify_uploads = false;  ///< compare every slab's data each frame to count the really changed ones
  bool vsync = true;            ///< interactive sessions wait for the display; scripted ones never
  /// Level of detail (paper §6): -1 chooses it from the frame time (coarser while the median of the
  /// last 8 frames is over frame_budget_ms, finer again under 40 % of it); k >= 0 draws level k
  /// (SlabRenderer::draw). Screenshots are always drawn at full detail.
  int lod = -1;
  double frame_budget_ms = 50;  ///< frame time the automatic level of detail aims under [ms]
};

/// The tool settings of the panel (and of scripts). Lengths in device millimetres.
struct ToolSettings {
  /// The brush (one of hdm::brush_registry()); empty: the probe, which touches without editing.
  std::optional<BrushTool> brush;
  float radius_mm = 3;                   ///< tool radius
  float strength = 1;                    ///< see hdm::BrushTool
  float depth_mm = 0.8f;                 ///< how far the mouse pushes the tool in below the surface under the cursor
  float height_mm = 1;                   ///< add: ridge height
  float resilience_mm = 0;               ///< carve: resilient band (paper §4.1)
  int field = 0;                         ///< paint: hdm::BrushField
  float colour[3] = {0.8f, 0.1f, 0.1f};  ///< paint colour: linear RGB
  float value = 0.5f;                    ///< paint of a scalar field (layer thickness in mm)
  float stiffness = 1000;  ///< proxy stiffness as felt at the device [N/m] (live: SessionCommand::SetProxy)
  float friction = 1;      ///< factor on the model's friction coefficients (live)
};

/// @brief The brush of @p t for a model with @p mm model units per device millimetre, with the
/// brush's default falloff (BrushInfo::falloff: carve and add constant, the exact boolean; smooth
/// and flatten smoothstep; paint the paper's linear cone). The probe gives a default Brush.
Brush tool_brush(const ToolSettings& t, double mm);
/// @brief Name of the tool of @p t: "probe" or the brush's registered name; parse_tool() reads it
/// back and throws InvalidInput naming @p name for anything else.
const char* tool_name(const ToolSettings& t) noexcept;
std::optional<BrushTool> parse_tool(const std::string& name);

/// @brief Opens the window and runs the studio on @p model until the window closes, the script
/// ends or options.frames frames are drawn.
/// @throws InvalidInput on bad options or script; RenderError when no window or OpenGL 4.5 core
///         context can be made (no display: run under Xvfb); IoError from saves and screenshots.
/// @return the process exit code (0: the session ran; 1: the script could not finish).
int run_studio(SlabModel model, const StudioOptions& options);

/// @brief As run_studio(), on the model `hdm bake` makes of the mesh @p mesh_path with its
/// defaults (repair, the error-bounded bake), baked on a worker thread while the window shows the
/// stage and its progress; the report gets the bake's figures ("bake"). Save keeps the result.
/// @throws what run_studio() throws, and what `hdm bake` throws for the mesh.
int run_studio_baking(const std::string& mesh_path, const StudioOptions& options);

}  // namespace hdm::studio
