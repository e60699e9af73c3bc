// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// The tool scenarios of `hdm feel`: a simulated hand drives a tool-shaped renderer (the sphere
/// proxy, the rigid tool) on analytic geometry built in code, a block of grid cubes (voxel_surface()) baked into
/// slabs, and the run is scored against that exact input (Embree closest point,
/// hdm::ExactMeshQuery), as the point scenarios are (scenarios.h).
///
/// Frames and units: the block is [-1, 1]² × [-1, 0] in model units, its top face z = 0, at 10
/// model units per metre (0.2 m wide at the device); the ball's radius is r = 0.3 model units
/// (3 cm). Forces in N, percentages of r or of the maximum force.

#include <hdm/haptics/device.h>
#include <hdm/haptics/proxy.h>

#include <string>
#include <vector>

namespace hdm {

/// The tool scenarios of `hdm feel` (no model file: each builds its own geometry).
enum class ToolScenario : uint8_t {
  /// The sphere proxy pressed down over a slot 0.4 wide and 0.4 deep (narrower than the ball's
  /// 2r = 0.6) until the hand pushes with `press_force_n`, then held: the ball must rest on the
  /// slot's two rims, its centre sqrt(r² − 0.2²) above the top, and not enter the walls.
  Slot,
  /// The sphere proxy rolled over the block's convex edge (x = 1, z = 0) by a hand pressing with
  /// `press_force_n`: along the top, round the edge, down the side face at `speed_m_s`. The force
  /// turns from the top's normal to the side's continuously, along the direction from the edge (or
  /// the face) to the ball's centre.
  RollEdge,
  /// A rigid dental burr (burr_shell(), head radius 0.1, shaft radius 0.04; rigid_tool_step()) held
  /// at 50° from the vertical by a hand pressing it down and towards a step: its head rests on the
  /// floor (z = −0.4) of a pit x > 0 while its shaft leans on the pit's edge (x = 0, z = 0), two
  /// contacts. The torque about the tip is scored against the lever-arm reference r × F of the
  /// edge's contact force (the floor's contact is straight below the tip: no moment). The hand
  /// leans the handle 5° past the tool's rest with the simulated device's wrist (`device`'s
  /// wrist_stiffness: the default yields to the torque, +infinity holds the attitude rigidly).
  ShaftEdge,
  /// The rigid burr (head radius 1 mm, the block 2 cm wide) drilling with the drill brush (K = 0.01,
  /// 200,000 rpm; SculptSession with RenderMode::RigidTool) for 0.5 s, pressed with `press_force_n`:
  /// once on the surface material (enamel, 300 HV) and once where the under-layer is exposed (dentin,
  /// 55 HV). The removal per N·s of the head's contact force (the drop of the displaced surface's
  /// enclosed volume) is scored against Archard's K·v_s/H for each, and their ratio against the
  /// hardness ratio 300 / 55.
  DrillLayers,
};

/// @brief Parses slot, roll_edge, shaft_edge or drill_layers. @throws InvalidInput otherwise, naming the name.
ToolScenario parse_tool_scenario(const std::string& name);
/// @brief Whether @p name names a tool scenario (slot, roll_edge, shaft_edge, drill_layers). noexcept.
bool is_tool_scenario(const std::string& name) noexcept;
/// Name of @p s (as `hdm feel --scenario` takes it).
const char* tool_scenario_name(ToolScenario s) noexcept;

/// Settings of a tool scenario run.
struct ToolScenarioOptions {
  ToolScenario scenario = ToolScenario::Slot;  ///< which geometry and motion
  double rate_hz = 1000;                       ///< servo rate [Hz], in [100, 1e6]
  ProxyParams proxy;                           ///< the ball's stiffness, damping, force limit (frictionless: the
                                               ///< friction scale is set to 0, so the force is the contact normal)
  double press_force_n = 1.0;                  ///< the hand's push into the surface [N], > 0
  double speed_m_s = 0.05;                     ///< RollEdge: the hand target's speed along its path [m/s], > 0
  SimulatedDeviceOptions device;               ///< handle mass, hand spring and damper (rate, max force set from above)
  bool keep_trace = false;                     ///< fill ToolScenarioReport::centre and force
};

/// Scores of one tool scenario run, against the exact input (the block's own mesh).
struct ToolScenarioReport {
  std::string scenario;  ///< tool_scenario_name()
  double rate_hz = 0;    ///< servo rate simulated [Hz]
  double radius = 0;     ///< the ball's radius r [model units]
  /// @{ Ticks run and ticks with the ball in contact.
  int64_t ticks = 0, contact_ticks = 0;
  /// @}
  /// Slot, RollEdge: deepest the ball went into the input over the run, r minus the exact distance
  /// from its centre to the input mesh, as % of r (target <= 2 %).
  double max_penetration_pct_r = 0;
  /// Slot: the held ball's centre height above the top against the analytic sqrt(r² − (w/2)²), as
  /// % of r; ShaftEdge: the held tip's height against r above the floor, as % of r; RollEdge: 0.
  double rest_height_error_pct_r = 0;
  bool entered = false;  ///< Slot: the ball's centre went below the top (into the slot)
  /// Largest tick-to-tick |ΔF| over ticks in contact, as % of the maximum force.
  double max_force_step_pct = 0;
  /// Largest tick-to-tick turn of the force direction over ticks in contact above 0.05 N [deg].
  double max_direction_step_deg = 0;
  /// @{ The force direction against the exact input's contact normal, the direction from the
  /// closest input point to the ball's centre, over ticks in contact above 0.05 N: p95 and max [deg].
  double normal_error_p95_deg = 0, normal_error_max_deg = 0;
  /// @}
  /// @{ Largest force and mean force over the contact ticks [N].
  double max_force_n = 0, mean_contact_force_n = 0;
  /// @}
  /// Slot, RollEdge, ShaftEdge: the work the rendered force (and, on the rigid tool, torque) held
  /// over each period did on the handle's motion in that period, returned over absorbed (the
  /// contact is passive at <= 1: Colgate & Schenkel; 0 without contact), as for the point scenarios.
  double energy_ratio = 0;
  /// @{ ShaftEdge, held (the mean over the last 0.1 s): shell points pushing on the burr's head and
  /// on its shaft (the last tick), the torque [N·m] about the tip against the lever-arm reference
  /// (c − tip) × F_edge, F_edge the edge's share of the force along the shaft's normal at the edge
  /// c, as % of the reference's magnitude, and whether the two turn the same way.
  int head_contacts = 0, shaft_contacts = 0;
  double torque_error_pct = 0;
  bool torque_sense_ok = false;
  /// @}
  /// @{ ShaftEdge, held: the god-object's tip [model units], its axis (unit, tool +z in the model
  /// frame), the force [N] and the torque about the tip [N·m] sent (means over the last 0.1 s).
  Vec3 tool_tip = Vec3::Zero(), tool_axis = Vec3::UnitZ(), tool_force = Vec3::Zero(), tool_torque = Vec3::Zero();
  /// @}
  /// @{ DrillLayers: removal per N·s of the head's contact force [mm³/(N·s)] on enamel and on
  /// dentin, Archard's K·v_s/H for each, and the dentin / enamel ratio of the removal against the
  /// hardness ratio, as % of the latter.
  double enamel_rate = 0, dentin_rate = 0, enamel_archard = 0, dentin_archard = 0, ratio_error_pct = 0;
  /// @}
  std::string note;          ///< what the scenario did
  std::vector<Vec3> centre;  ///< keep_trace: the ball's centre per tick [model units]
  std::vector<Vec3> force;   ///< keep_trace: the rendered force per tick [N, device frame]
};

/// @brief Runs one tool scenario: builds its block, bakes it (500 slabs, n = 8), and drives the
/// sphere proxy (sphere_proxy_step(), r = 0.3) or, for ShaftEdge and DrillLayers, the rigid burr
/// (rigid_tool_step() with `proxy`'s stiffness and force limit) with a SimulatedDevice, scored
/// against the block (DrillLayers: against Archard's law on its displaced surface).
/// @throws InvalidInput for a rate outside [100, 1e6] Hz, a press force or speed that is not
/// positive and finite, or a maximum force that is not positive (naming the option).
/// @note Simulated time, ticks back to back on the calling thread; allocates before the tick loop
///       and for the trace. The bake takes about a second.
ToolScenarioReport run_tool_scenario(const ToolScenarioOptions& options);

}  // namespace hdm
