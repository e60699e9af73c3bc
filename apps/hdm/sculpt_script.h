// SPDX-License-Identifier: MIT
#pragma once
// Sculpting scripts for the simulated device: strokes over the model's surface (JSON), turned into
// a per-tick device trajectory before the servo loop starts.

#include <hdm/haptics/force.h>
#include <hdm/query/slab_query.h>

#include <string>
#include <vector>

namespace hdm::app {

enum class Tool : uint8_t { None, Probe, Carve, Add, Paint };

/// One stroke. Lengths are device-space millimetres (the workspace maps them to the model).
struct Stroke {
  Tool tool = Tool::Probe;
  Vec3 from = Vec3::Zero(), to = Vec3::Zero();  ///< ends in normalised bounding-box coordinates [0,1]³
  double radius_mm = 3, depth_mm = 1, speed_mm_s = 30;
  double resilience_mm = 0.3;  ///< carve: resilient band
  double height_mm = 0.02;     ///< add: cone height per edit
  Vec3f colour{0.8f, 0.1f, 0.1f};  ///< paint: linear RGB
};

struct Script {
  std::string name;
  double workspace_m = 0.16;
  ForceParams force;
  std::vector<Stroke> strokes;
};

/// Reads a script; throws InvalidInput naming the file and the field on errors.
Script read_script(const std::string& path);

/// Per-tick device trajectory: device position [m] and active tool per tick.
struct Trajectory {
  std::vector<Vec3> position;
  std::vector<Tool> tool;
  std::vector<int16_t> stroke;  ///< stroke index per tick, -1 while travelling
};

/// Projects every stroke on the model surface (marching its own haptic query inward from the
/// bounding-box point towards the box centre) and samples the device path at @p rate_hz.
/// Throws InvalidInput when a stroke point does not reach the surface.
Trajectory build_trajectory(const Script& script, const SlabModel& model, const SlabLocator& locator,
                            const Workspace& ws, double rate_hz);

}  // namespace hdm::app
