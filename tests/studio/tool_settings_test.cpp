// SPDX-License-Identifier: MIT
// The studio's tool settings (apps/studio/tool_settings.cpp, what the tools panel and the studio's
// scripts set): every registered brush is a tool by its name, and its settings become the brush
// the servo thread strokes with: the documented default falloff, lengths from device millimetres.
#include "studio.h"

#include <hdm/core/error.h>
#include <hdm/edit/brush_registry.h>

#include <gtest/gtest.h>

#include <map>
#include <string>

namespace hdm::studio {
namespace {

// As tool_brush() documents it: carve and add are the exact boolean (constant), smooth and flatten blend
// with smoothstep (as does drill), paint with the paper's linear cone.
const std::map<std::string, Falloff> kFalloff = {{"carve", Falloff::Constant}, {"add", Falloff::Constant},
                                                 {"smooth", Falloff::Smooth},  {"flatten", Falloff::Smooth},
                                                 {"paint", Falloff::Linear},   {"drill", Falloff::Smooth}};

TEST(ToolSettings, EveryBrushIsAToolAndBecomesItsBrush) {
  const double mm = 0.25;  // model units per device millimetre
  for (const BrushInfo& info : brush_registry()) {
    SCOPED_TRACE(info.name);
    ToolSettings t;
    t.brush = parse_tool(info.name);
    ASSERT_TRUE(t.brush.has_value());
    EXPECT_EQ(*t.brush, info.tool);
    EXPECT_STREQ(tool_name(t), info.name);
    t.radius_mm = 4, t.strength = 0.5f, t.height_mm = 2, t.resilience_mm = 0.5f;
    t.field = static_cast<int>(BrushField::LayerThickness), t.value = 1.5f;
    const Brush b = tool_brush(t, mm);
    EXPECT_EQ(b.tool, info.tool);
    const auto falloff = kFalloff.find(info.name);
    ASSERT_NE(falloff, kFalloff.end()) << "no documented falloff for the brush '" << info.name << "'";
    EXPECT_EQ(b.falloff, falloff->second);
    EXPECT_DOUBLE_EQ(b.radius, 1.0);
    EXPECT_DOUBLE_EQ(b.strength, 0.5);
    EXPECT_DOUBLE_EQ(b.height, 0.5);
    EXPECT_DOUBLE_EQ(b.resilience, 0.125);
    EXPECT_EQ(b.field, BrushField::LayerThickness);
    EXPECT_FLOAT_EQ(b.value, 0.375f);  // a thickness in millimetres, converted
    EXPECT_NO_THROW(check_brush(b));
  }
}

TEST(ToolSettings, ProbeAndUnknownTools) {
  ToolSettings t;
  EXPECT_FALSE(t.brush.has_value());  // the studio starts with the probe
  EXPECT_STREQ(tool_name(t), "probe");
  EXPECT_FALSE(parse_tool("probe").has_value());
  try {
    parse_tool("chisel");
    FAIL() << "accepted the tool 'chisel'";
  } catch (const InvalidInput& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("chisel"), std::string::npos) << m;
    for (const BrushInfo& info : brush_registry()) EXPECT_NE(m.find(info.name), std::string::npos) << m;
  }
  ToolSettings colour;
  colour.brush = parse_tool("paint");
  colour.field = static_cast<int>(BrushField::Colour);
  colour.value = 0.7f;
  EXPECT_FLOAT_EQ(tool_brush(colour, 0.25).value, 0.7f);  // not a length: unconverted
}

}  // namespace
}  // namespace hdm::studio
