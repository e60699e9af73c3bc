// SPDX-License-Identifier: MIT
// The tool settings' names and brushes (studio.h), kept apart from the panel that draws them so
// that they are tested without a window.
#include "studio.h"

#include <hdm/core/error.h>
#include <hdm/edit/brush_registry.h>

namespace hdm::studio {

const char* tool_name(const ToolSettings& t) noexcept {
  if (!t.brush) return "probe";
  const BrushInfo* b = find_brush(*t.brush);
  return b ? b->name : "?";
}

std::optional<BrushTool> parse_tool(const std::string& name) {
  if (name == "probe") return std::nullopt;
  if (const BrushInfo* b = find_brush(name)) return b->tool;
  throw InvalidInput("tool \"" + name + "\": expected probe, " + brush_names());
}

Brush tool_brush(const ToolSettings& t, double mm) {
  Brush b;
  const BrushInfo* info = t.brush ? find_brush(*t.brush) : nullptr;
  if (info) b.tool = info->tool, b.falloff = info->falloff;
  b.radius = t.radius_mm * mm;
  b.strength = t.strength;
  b.resilience = t.resilience_mm * mm;
  b.height = t.height_mm * mm;
  b.field = static_cast<BrushField>(t.field);
  b.colour = Vec3f(t.colour[0], t.colour[1], t.colour[2]);
  b.value = b.field == BrushField::LayerThickness ? static_cast<float>(t.value * mm) : t.value;
  return b;
}

}  // namespace hdm::studio
