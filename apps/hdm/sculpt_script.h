// SPDX-License-Identifier: MIT
#pragma once
// Sculpting scripts for the simulated device: strokes over the model's surface (JSON), turned into
// a per-tick device trajectory before the servo loop starts.

#include <hdm/haptics/force.h>
#include <hdm/io/read_file.h>
#include <hdm/query/slab_query.h>

#include <cstdint>
#include <string>
#include <string_view>
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

/// @brief Parses a script from the JSON text @p json; @p name starts every error message.
///
/// Fields (defaults in Script and Stroke): name; workspace_m in [0.001, 10]; stiffness_n_per_m in
/// [0.001, 1e7]; damping_ns_per_m in [0, 1e5]; max_force_n in [0.001, 1e4]; strokes, a non-empty
/// array of objects with tool (probe, carve, add, paint), from and to (three numbers each in
/// [-1, 2], normalised box coordinates), radius_mm in [0.001, 1e4], depth_mm, resilience_mm and
/// height_mm in [0, 1e4], speed_mm_s in [0.01, 1e5], colour (three numbers in [0, 1]).
/// @throws InvalidInput "<name>: ..." naming the field when the text is not JSON, a field has the
///         wrong type or lies outside its range.
/// @note O(text size); the JSON document takes a small multiple of the text's size in memory.
Script parse_script(std::string_view json, const std::string& name);

/// @brief Reads the script file @p path (at most @p max_bytes bytes) with parse_script().
/// @throws InvalidInput naming the file (and the field) on every error, the file's size included.
Script read_script(const std::string& path, uint64_t max_bytes = default_max_input_bytes);

/// Most device ticks build_trajectory() makes (about 14 hours at 1 kHz): a script that asks for
/// more is refused before the trajectory outgrows memory.
inline constexpr size_t max_trajectory_ticks = 50'000'000;

/// Per-tick device trajectory: device position [m] and active tool per tick.
struct Trajectory {
  std::vector<Vec3> position;
  std::vector<Tool> tool;
  std::vector<int16_t> stroke;  ///< stroke index per tick, -1 while travelling
};

/// Projects every stroke on the model surface (marching its own haptic query inward from the
/// bounding-box point towards the box centre) and samples the device path at @p rate_hz.
/// Throws InvalidInput when a stroke point does not reach the surface, or when the trajectory
/// would take more than max_trajectory_ticks ticks.
Trajectory build_trajectory(const Script& script, const SlabModel& model, const SlabLocator& locator,
                            const Workspace& ws, double rate_hz);

}  // namespace hdm::app
