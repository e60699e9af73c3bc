// SPDX-License-Identifier: MIT
#include <hdm/core/error.h>
#include <hdm/edit/brush.h>

namespace hdm {

BrushTool parse_brush_tool(const std::string& name) {
  if (name == "carve") return BrushTool::Carve;
  if (name == "add") return BrushTool::Add;
  if (name == "smooth") return BrushTool::Smooth;
  if (name == "flatten") return BrushTool::Flatten;
  if (name == "paint") return BrushTool::Paint;
  throw InvalidInput("brush tool '" + name + "': expected carve, add, smooth, flatten or paint");
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
  throw InvalidInput("paint field '" + name +
                     "': expected colour, roughness, friction_static, friction_dynamic, stiffness or layer_thickness");
}

const char* brush_tool_name(BrushTool tool) noexcept {
  switch (tool) {
    case BrushTool::Carve:
      return "carve";
    case BrushTool::Add:
      return "add";
    case BrushTool::Smooth:
      return "smooth";
    case BrushTool::Flatten:
      return "flatten";
    case BrushTool::Paint:
      return "paint";
  }
  return "?";
}

}  // namespace hdm
