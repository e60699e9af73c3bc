// SPDX-License-Identifier: MIT
#pragma once
// Sculpting scripts for the simulated device: strokes over the model's surface (JSON), turned into
// a per-tick device trajectory before the servo loop starts.

#include <hdm/edit/brush.h>
#include <hdm/haptics/force.h>
#include <hdm/query/slab_query.h>

#include <string>
#include <vector>

namespace hdm::app {

/// A script step: a stroke with a tool (Probe touches without editing), or an undo / redo step.
enum class Tool : uint8_t { None, Probe, Carve, Add, Paint, Smooth, Flatten, Undo, Redo };

/// One step. Lengths are device-space millimetres (the workspace maps them to the model).
struct Stroke {
  Tool tool = Tool::Probe;
  Vec3 from = Vec3::Zero(), to = Vec3::Zero();  ///< ends in normalised bounding-box coordinates [0,1]³
  double radius_mm = 3, speed_mm_s = 30;
  double depth_mm = 1;         ///< the hand's target this far under the surface (the closed loop presses less deep)
  double resilience_mm = 0.3;  ///< carve: resilient band
  double height_mm = 0.5;      ///< add: ridge height above the stroke's starting surface
  double strength = 1;         ///< brush strength in [0,1]
  Falloff falloff = Falloff::Constant;  ///< brush falloff (default: constant for carve and add, linear otherwise)
  BrushField field = BrushField::Colour;  ///< paint: the field written
  float value = 0;             ///< paint of a scalar field (layer_thickness in mm)
  double pressure_force_n = 1.0;  ///< paint, smooth, flatten: normal force of full pressure [N]
  Vec3f colour{0.8f, 0.1f, 0.1f};  ///< paint: linear RGB
  int count = 1;               ///< undo / redo: how many strokes
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

/// Reads a script; throws InvalidInput naming the file and the field on errors.
Script read_script(const std::string& path);

/// Per-tick hand targets [m] and the step under way per tick.
struct Trajectory {
  std::vector<Vec3> position;
  std::vector<Tool> tool;
  std::vector<int16_t> stroke;  ///< step index per tick, -1 while travelling
  /// Undo / redo steps: (tick, step index), in tick order.
  std::vector<std::pair<int64_t, int16_t>> commands;
};

/// Projects every stroke on the model surface (marching its own haptic query inward from the
/// bounding-box point towards the box centre) and samples the hand's path at @p rate_hz; an undo
/// or redo step is a 50 ms pause at which the command is given.
/// Throws InvalidInput when a stroke point does not reach the surface.
Trajectory build_trajectory(const Script& script, const SlabModel& model, const SlabLocator& locator,
                            const Workspace& ws, double rate_hz);

}  // namespace hdm::app
