// SPDX-License-Identifier: MIT
// The brush registry: one entry per brush. Adding a brush: its kernel in src/edit/flood_<family>.cpp
// (a BrushHooks of its start and flood functions) and its entry below.
#include <hdm/edit/brush_registry.h>

#include <hdm/core/error.h>
#include "edit_job.h"

#include <cmath>
#include <cstdio>
#include <limits>

namespace hdm::edit::detail {
// Each brush's kernel, defined in its kernel file.
extern const BrushHooks carve_brush, add_brush, smooth_brush, flatten_brush, paint_brush, drill_brush;
}  // namespace hdm::edit::detail

namespace hdm {
namespace {

constexpr uint16_t bit(BrushParam p) { return uint16_t(1u << static_cast<int>(p)); }
constexpr uint16_t kCommon = bit(BrushParam::Radius) | bit(BrushParam::Strength) | bit(BrushParam::Falloff);

// The registry: in BrushTool order (a brush's BrushTool value is its index here).
constexpr BrushInfo kBrushes[] = {
    {BrushTool::Carve, "carve", "carve",
     "removes material in the swept sphere whose bottom is the tool position (paper §4.1)",
     kCommon | bit(BrushParam::Resilience), Falloff::Constant, ToolPlacement::BehindHip, true,
     &edit::detail::carve_brush},
    {BrushTool::Add, "add", "add", "adds a ridge of `height` above the stroke's starting surface (paper §4.2)",
     kCommon | bit(BrushParam::Height), Falloff::Constant, ToolPlacement::StartSurface, true, &edit::detail::add_brush},
    {BrushTool::Smooth, "smooth", "smooth",
     "relaxes the surface towards its neighbours' mean at strength·pressure·20 /s of contact",
     kCommon | bit(BrushParam::Pressure), Falloff::Smooth, ToolPlacement::Contact, false, &edit::detail::smooth_brush},
    {BrushTool::Flatten, "flatten", "flatten",
     "relaxes the surface towards the tool's plane at strength·pressure·20 /s of contact",
     kCommon | bit(BrushParam::Pressure), Falloff::Smooth, ToolPlacement::Contact, true, &edit::detail::flatten_brush},
    {BrushTool::Paint, "paint", "paint", "blends a field (colour, roughness, friction, ...) towards a value (paper §5)",
     kCommon | bit(BrushParam::Field) | bit(BrushParam::Colour) | bit(BrushParam::Value) | bit(BrushParam::Pressure),
     Falloff::Linear, ToolPlacement::Contact, false, &edit::detail::paint_brush},
    {BrushTool::Drill, "drill", "drill",
     "removes the volume K·F·v·dt/H of Archard's wear law under the burr (force, speed, hardness)",
     kCommon | bit(BrushParam::WearCoefficient) | bit(BrushParam::Rpm), Falloff::Smooth, ToolPlacement::Contact, false,
     &edit::detail::drill_brush},
};
constexpr size_t kCount = sizeof kBrushes / sizeof kBrushes[0];

constexpr bool in_tool_order() {
  for (size_t k = 0; k < kCount; ++k)
    if (static_cast<size_t>(kBrushes[k].tool) != k) return false;
  return true;
}
static_assert(in_tool_order(), "the registry lists the brushes in BrushTool order");

constexpr double kInf = std::numeric_limits<double>::infinity();
// In BrushParam order.
constexpr BrushParamRange kRanges[] = {
    {BrushParam::Radius, "radius", "model units", 0, kInf, true},
    {BrushParam::Strength, "strength", "", 0, 1, false},
    {BrushParam::Falloff, "falloff", "", 0, 0, false},
    {BrushParam::Resilience, "resilience", "model units", 0, kInf, false},
    {BrushParam::Height, "height", "model units", 0, kInf, false},
    {BrushParam::Field, "field", "", 0, 0, false},
    {BrushParam::Colour, "colour", "linear RGB", 0, 1, false},
    {BrushParam::Value, "value", "", -kInf, kInf, false},
    {BrushParam::Pressure, "pressure_force_n", "N", 0, kInf, true},
    {BrushParam::WearCoefficient, "wear_coefficient", "", 0, 1, true},
    {BrushParam::Rpm, "rpm", "rpm", 0, 1e6, true},
};
static_assert(sizeof kRanges / sizeof kRanges[0] == brush_param_count);

std::string number_text(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

// "must be > 0 and finite", "must be in [0, 1]".
std::string reason(const BrushParamRange& r) {
  if (std::isinf(r.hi))
    return std::isinf(r.lo) ? "must be finite"
                            : std::string("must be ") + (r.lo_open ? "> " : ">= ") + number_text(r.lo) + " and finite";
  return std::string("must be in ") + (r.lo_open ? "(" : "[") + number_text(r.lo) + ", " + number_text(r.hi) + "]";
}

void check(BrushParam p, double x) {
  const BrushParamRange& r = brush_param_range(p);
  const bool ok = std::isfinite(x) && (r.lo_open ? x > r.lo : x >= r.lo) && x <= r.hi;
  if (!ok) throw InvalidInput(std::string(r.name) + " = " + number_text(x) + ": " + reason(r));
}

}  // namespace

std::span<const BrushInfo> brush_registry() noexcept { return {kBrushes, kCount}; }

const BrushInfo* find_brush(BrushTool tool) noexcept {
  const size_t k = static_cast<size_t>(tool);
  return k < kCount ? &kBrushes[k] : nullptr;
}

const BrushInfo* find_brush(std::string_view name) noexcept {
  for (const BrushInfo& b : kBrushes)
    if (name == b.name) return &b;
  return nullptr;
}

const BrushParamRange& brush_param_range(BrushParam p) noexcept { return kRanges[static_cast<size_t>(p)]; }

std::string brush_names() {
  std::string s;
  for (size_t k = 0; k < kCount; ++k)
    s += (k == 0 ? "" : k + 1 == kCount ? " or " : ", ") + std::string(kBrushes[k].name);
  return s;
}

void check_brush(const Brush& b) {
  if (!find_brush(b.tool))
    throw InvalidInput("tool = " + std::to_string(static_cast<int>(b.tool)) + ": not a registered brush");
  check(BrushParam::Radius, b.radius);
  check(BrushParam::Strength, b.strength);
  check(BrushParam::Resilience, b.resilience);
  check(BrushParam::Height, b.height);
  for (int c = 0; c < 3; ++c) check(BrushParam::Colour, b.colour[c]);
  check(BrushParam::Value, b.value);
  // Friction and hardness are stored as binary16 (SlabModel): a larger value would store infinity.
  const bool half = b.field == BrushField::FrictionStatic || b.field == BrushField::FrictionDynamic ||
                    b.field == BrushField::Hardness;
  if (half && std::abs(b.value) > Half16::max)
    throw InvalidInput("value = " + number_text(b.value) +
                       ": friction and hardness are stored as 16-bit floats, at most 65,504 in magnitude");
  check(BrushParam::Pressure, b.pressure_force_n);
  check(BrushParam::WearCoefficient, b.wear_coefficient);
  check(BrushParam::Rpm, b.rpm);
}

}  // namespace hdm
