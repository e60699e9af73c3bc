// SPDX-License-Identifier: MIT
#pragma once
// Sculpting scripts for the simulated device: strokes over the model's surface (JSON), turned into
// a per-tick device trajectory before the servo loop starts.

#include <hdm/edit/brush.h>
#include <hdm/haptics/force.h>
#include <hdm/io/read_file.h>
#include <hdm/query/slab_query.h>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace hdm::app {

/// A script step: a stroke with a brush (Stroke::brush), a probe (touches without editing), or an
/// undo / redo step.
enum class Tool : uint8_t { None, Probe, Brush, Undo, Redo };

/// One step. Lengths are device-space millimetres (the workspace maps them to the model).
struct Stroke {
  Tool tool = Tool::Probe;
  BrushTool brush = BrushTool::Carve;           ///< Tool::Brush: the registered brush ("tool" names it)
  Vec3 from = Vec3::Zero(), to = Vec3::Zero();  ///< ends in normalised bounding-box coordinates [0,1]³
  double radius_mm = 3, speed_mm_s = 30;
  double depth_mm = 1;         ///< the hand's target this far under the surface (the closed loop presses less deep)
  double resilience_mm = 0.3;  ///< carve: resilient band
  double height_mm = 0.5;      ///< add: ridge height above the stroke's starting surface
  double strength = 1;         ///< brush strength in [0,1]
  Falloff falloff = Falloff::Constant;                 ///< brush falloff (default: see parse_script())
  BrushField field = BrushField::Colour;               ///< paint: the field written
  float value = 0;                                     ///< paint of a scalar field (layer_thickness in mm)
  double pressure_force_n = 1.0;                       ///< paint, smooth, flatten: normal force of full pressure [N]
  double wear_coefficient = Brush{}.wear_coefficient;  ///< drill: Archard's K
  double rpm = Brush{}.rpm;                            ///< drill: burr speed [rev/min]
  Vec3f colour{0.8f, 0.1f, 0.1f};                      ///< paint: linear RGB
  int count = 1;                                       ///< undo / redo: how many strokes
};

/// The under-layer a script sets before its strokes (SlabModel::layer_displacement, under_layer).
struct ScriptLayer {
  bool present = false;
  double thickness_mm = 1.5;  ///< depth of the under-layer's top below the surface
  UnderLayer material;
};

/// The top material's finish a script sets before its strokes (every texel).
struct ScriptSurface {
  bool has_colour = false, has_roughness = false;
  Vec3f colour{0.82f, 0.8f, 0.76f};  ///< linear RGB
  float roughness = 1.0f;            ///< [0,1]
};

struct Script {
  std::string name;
  double workspace_m = 0.16;
  ForceParams force;
  double hand_stiffness = 200;  ///< the simulated hand's grip [N/m] (SimulatedDeviceOptions::hand_stiffness)
  double hand_damping = 2;      ///< [N·s/m]
  ScriptLayer layer;
  ScriptSurface surface;
  std::vector<Stroke> strokes;
};

/// The brush of stroke @p s, with lengths converted by @p model_units_per_mm.
Brush stroke_brush(const Stroke& s, double model_units_per_mm);

/// @brief Parses a script from the JSON text @p json; @p name starts every error message.
///
/// Fields (defaults in Script and Stroke): name; workspace_m in [0.001, 10]; stiffness_n_per_m and
/// hand_stiffness_n_per_m in [0.001, 1e7]; damping_ns_per_m and hand_damping_ns_per_m in [0, 1e5];
/// max_force_n in [0.001, 1e4]; surface {colour (three numbers in [0, 1]), roughness in [0, 1]};
/// under_layer {thickness_mm in [0, 1e4], colour, stiffness and roughness in [0, 1],
/// friction_static and friction_dynamic in [0, 10], hardness_hv in [1, 1e5]}; strokes, a non-empty array of objects:
/// either
/// {"undo": n} or {"redo": n} with a whole n in [1, 1000], or tool (probe or a registered brush's
/// name: carve, add, smooth, flatten, paint, drill; hdm::brush_registry()), from and to (three numbers each in [-1, 2],
/// normalised box coordinates), radius_mm in [0.001, 1e4], depth_mm, resilience_mm and height_mm in [0, 1e4],
/// speed_mm_s in [0.01, 1e5], colour (three numbers in [0, 1]), strength in [0, 1], pressure_force_n in [0.001, 1e4],
/// falloff and field (strings), value in [-1e4, 1e4], wear_coefficient in [1e-9, 1], rpm in [1e-3, 1e6]. The default
/// falloff is the brush's when that is constant (carve, add: the exact boolean), linear otherwise. Any other key is
/// refused, naming the nearest known one (a misspelt key would otherwise leave its default in force).
/// @throws InvalidInput "<name>: ..." naming the field when the text is not JSON, a field has the
///         wrong type or lies outside its range.
/// @note O(text size); the JSON document takes a small multiple of the text's size in memory.
Script parse_script(std::string_view json, const std::string& name);

/// @brief Reads the script file @p path (at most @p max_bytes bytes) with parse_script().
/// @throws InvalidInput naming the file (and the field) on every error, the file's size included.
Script read_script(const std::string& path, uint64_t max_bytes = default_max_input_bytes);

/// Most strokes (and undo / redo steps) a script may hold: Trajectory numbers them in 16 bits.
inline constexpr size_t max_script_strokes = 30'000;

/// Most device ticks build_trajectory() makes (about 14 hours at 1 kHz): a script that asks for
/// more is refused before the trajectory outgrows memory.
inline constexpr size_t max_trajectory_ticks = 50'000'000;

/// Per-tick hand targets [m] and the step under way per tick.
struct Trajectory {
  std::vector<Vec3> position;
  std::vector<Tool> tool;
  std::vector<int16_t> stroke;  ///< step index per tick, -1 while travelling
  /// Undo / redo steps: (tick, step index), in tick order.
  std::vector<std::pair<int64_t, int16_t>> commands;
};

/// The number of ticks build_trajectory() makes for the same arguments, without storing them (the
/// projection runs as it does there). Throws what build_trajectory() throws.
int64_t count_trajectory_ticks(const Script& script, const SlabModel& model, const SlabLocator& locator,
                               const Workspace& ws, double rate_hz);

/// Projects every stroke on the model surface (marching its own haptic query inward from the
/// bounding-box point towards the box centre) and samples the hand's path at @p rate_hz; an undo
/// or redo step is a 50 ms pause at which the command is given.
/// @p ticks: what count_trajectory_ticks() returned for the same arguments (0: counted here), so
/// the trajectory is allocated once at its size. Throws InvalidInput when a stroke point does not
/// reach the surface, or when the trajectory would take more than max_trajectory_ticks ticks.
Trajectory build_trajectory(const Script& script, const SlabModel& model, const SlabLocator& locator,
                            const Workspace& ws, double rate_hz, int64_t ticks = 0);

}  // namespace hdm::app
