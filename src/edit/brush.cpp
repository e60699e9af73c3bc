// SPDX-License-Identifier: MIT
#include <hdm/core/error.h>
#include <hdm/edit/brush.h>
#include <hdm/edit/brush_registry.h>

namespace hdm {

BrushTool parse_brush_tool(const std::string& name) {
  if (const BrushInfo* b = find_brush(name)) return b->tool;
  throw InvalidInput("brush tool '" + name + "': expected " + brush_names());
}

Falloff parse_falloff(const std::string& name) {
  if (name == "constant") return Falloff::Constant;
  if (name == "linear") return Falloff::Linear;
  if (name == "smooth") return Falloff::Smooth;
  throw InvalidInput("falloff '" + name + "': expected constant, linear or smooth");
}

BrushField parse_brush_field(const std::string& name) {
  if (name == "colour" || name == "color") return BrushField::Colour;
  if (name == "roughness") return BrushField::Roughness;
  if (name == "friction_static") return BrushField::FrictionStatic;
  if (name == "friction_dynamic") return BrushField::FrictionDynamic;
  if (name == "stiffness") return BrushField::Stiffness;
  if (name == "layer_thickness") return BrushField::LayerThickness;
  if (name == "hardness") return BrushField::Hardness;
  throw InvalidInput("paint field '" + name +
                     "': expected colour, roughness, friction_static, friction_dynamic, stiffness, layer_thickness or "
                     "hardness");
}

const char* brush_tool_name(BrushTool tool) noexcept {
  const BrushInfo* b = find_brush(tool);
  return b ? b->name : "?";
}

}  // namespace hdm
