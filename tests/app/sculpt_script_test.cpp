// SPDX-License-Identifier: MIT
// The sculpting-script parser of `hdm sculpt` (apps/hdm/sculpt_script.h), checked against its
// documentation: every key lands in its field in its unit, and absent keys keep the documented
// defaults. Its refusals: sculpt_script_refusal_test.cpp.
#include "sculpt_script_test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace hdm::app {
namespace {

using namespace hdm::app::test;

TEST(SculptScript, EveryTopLevelKeyIsRead) {
  json j = with_strokes({plain_stroke()});
  j["name"] = "bunny ears";
  j["workspace_m"] = 0.25;
  j["hand_stiffness_n_per_m"] = 350.0;
  j["hand_damping_ns_per_m"] = 4.5;
  j["stiffness_n_per_m"] = 800.0;
  j["damping_ns_per_m"] = 0.75;
  j["max_force_n"] = 2.5;
  const Script s = parse(j);
  EXPECT_EQ(s.name, "bunny ears");
  EXPECT_DOUBLE_EQ(s.workspace_m, 0.25);
  EXPECT_DOUBLE_EQ(s.hand_stiffness, 350.0);
  EXPECT_DOUBLE_EQ(s.hand_damping, 4.5);
  EXPECT_DOUBLE_EQ(s.force.stiffness, 800.0);
  EXPECT_DOUBLE_EQ(s.force.damping, 0.75);
  EXPECT_DOUBLE_EQ(s.force.max_force, 2.5);
  ASSERT_EQ(s.strokes.size(), 1u);
}

TEST(SculptScript, AbsentTopLevelKeysKeepTheirDefaults) {
  const Script s = parse(with_strokes({plain_stroke()}));
  // Without a name the script is called by the name it was read under, so later messages
  // (build_trajectory) still say which script failed.
  EXPECT_EQ(s.name, kName);
  EXPECT_DOUBLE_EQ(s.workspace_m, 0.16);
  EXPECT_DOUBLE_EQ(s.hand_stiffness, 200.0);
  EXPECT_DOUBLE_EQ(s.hand_damping, 2.0);
  EXPECT_DOUBLE_EQ(s.force.stiffness, 1000.0);
  EXPECT_DOUBLE_EQ(s.force.damping, 1.0);
  EXPECT_DOUBLE_EQ(s.force.max_force, 3.3);
  EXPECT_FALSE(s.layer.present);
  EXPECT_FALSE(s.surface.has_colour);
  EXPECT_FALSE(s.surface.has_roughness);
}

TEST(SculptScript, UnderLayerKeysAreRead) {
  json j = with_strokes({plain_stroke()});
  j["under_layer"] = {{"thickness_mm", 2.5},    {"colour", {0.1, 0.2, 0.3}}, {"stiffness", 0.25},
                      {"friction_static", 0.7}, {"friction_dynamic", 0.4},   {"roughness", 0.6}};
  const Script s = parse(j);
  EXPECT_TRUE(s.layer.present);
  EXPECT_DOUBLE_EQ(s.layer.thickness_mm, 2.5);
  EXPECT_FLOAT_EQ(s.layer.material.colour.x(), 0.1f);
  EXPECT_FLOAT_EQ(s.layer.material.colour.y(), 0.2f);
  EXPECT_FLOAT_EQ(s.layer.material.colour.z(), 0.3f);
  EXPECT_FLOAT_EQ(s.layer.material.stiffness_scale, 0.25f);  // "stiffness" is a scale, not N/m
  EXPECT_FLOAT_EQ(s.layer.material.friction_static, 0.7f);
  EXPECT_FLOAT_EQ(s.layer.material.friction_dynamic, 0.4f);
  EXPECT_FLOAT_EQ(s.layer.material.roughness, 0.6f);
}

TEST(SculptScript, EmptyUnderLayerIsPresentWithDefaults) {
  json j = with_strokes({plain_stroke()});
  j["under_layer"] = json::object();
  const Script s = parse(j);
  EXPECT_TRUE(s.layer.present);
  EXPECT_DOUBLE_EQ(s.layer.thickness_mm, 1.5);
  EXPECT_FLOAT_EQ(s.layer.material.colour.x(), 0.85f);
  EXPECT_FLOAT_EQ(s.layer.material.colour.y(), 0.62f);
  EXPECT_FLOAT_EQ(s.layer.material.colour.z(), 0.3f);
  EXPECT_FLOAT_EQ(s.layer.material.stiffness_scale, 0.5f);
  EXPECT_FLOAT_EQ(s.layer.material.friction_static, 0.3f);
  EXPECT_FLOAT_EQ(s.layer.material.friction_dynamic, 0.2f);
  EXPECT_FLOAT_EQ(s.layer.material.roughness, 1.0f);
}

TEST(SculptScript, SurfaceKeysAreReadAndFlagged) {
  json j = with_strokes({plain_stroke()});
  j["surface"] = {{"colour", {0.3, 0.4, 0.5}}, {"roughness", 0.2}};
  Script s = parse(j);
  EXPECT_TRUE(s.surface.has_colour);
  EXPECT_TRUE(s.surface.has_roughness);
  EXPECT_FLOAT_EQ(s.surface.colour.x(), 0.3f);
  EXPECT_FLOAT_EQ(s.surface.colour.y(), 0.4f);
  EXPECT_FLOAT_EQ(s.surface.colour.z(), 0.5f);
  EXPECT_FLOAT_EQ(s.surface.roughness, 0.2f);

  // Each half is flagged on its own: an absent one must leave the model's finish alone.
  j["surface"] = {{"roughness", 0.2}};
  s = parse(j);
  EXPECT_FALSE(s.surface.has_colour);
  EXPECT_TRUE(s.surface.has_roughness);
  j["surface"] = {{"colour", {0.3, 0.4, 0.5}}};
  s = parse(j);
  EXPECT_TRUE(s.surface.has_colour);
  EXPECT_FALSE(s.surface.has_roughness);
  EXPECT_FLOAT_EQ(s.surface.roughness, 1.0f);
}

TEST(SculptScript, EveryStrokeKeyIsRead) {
  const json stroke = {{"tool", "paint"},
                       {"from", {0.1, 0.2, 0.3}},
                       {"to", {0.4, 0.5, 0.6}},
                       {"radius_mm", 4.5},
                       {"depth_mm", 0.8},
                       {"speed_mm_s", 12.5},
                       {"resilience_mm", 0.6},
                       {"height_mm", 1.25},
                       {"colour", {0.2, 0.7, 0.9}},
                       {"strength", 0.4},
                       {"pressure_force_n", 2.5},
                       {"falloff", "smooth"},
                       {"field", "layer_thickness"},
                       {"value", -2.5}};
  const Script s = parse(with_strokes({stroke}));
  ASSERT_EQ(s.strokes.size(), 1u);
  const Stroke& st = s.strokes[0];
  EXPECT_EQ(st.tool, Tool::Brush);
  EXPECT_EQ(st.brush, BrushTool::Paint);
  EXPECT_TRUE(st.from.isApprox(Vec3(0.1, 0.2, 0.3)));
  EXPECT_TRUE(st.to.isApprox(Vec3(0.4, 0.5, 0.6)));
  EXPECT_DOUBLE_EQ(st.radius_mm, 4.5);
  EXPECT_DOUBLE_EQ(st.depth_mm, 0.8);
  EXPECT_DOUBLE_EQ(st.speed_mm_s, 12.5);
  EXPECT_DOUBLE_EQ(st.resilience_mm, 0.6);
  EXPECT_DOUBLE_EQ(st.height_mm, 1.25);
  EXPECT_FLOAT_EQ(st.colour.x(), 0.2f);
  EXPECT_FLOAT_EQ(st.colour.y(), 0.7f);
  EXPECT_FLOAT_EQ(st.colour.z(), 0.9f);
  EXPECT_DOUBLE_EQ(st.strength, 0.4);
  EXPECT_DOUBLE_EQ(st.pressure_force_n, 2.5);
  EXPECT_EQ(st.falloff, Falloff::Smooth);
  EXPECT_EQ(st.field, BrushField::LayerThickness);
  EXPECT_FLOAT_EQ(st.value, -2.5f);
  EXPECT_EQ(st.count, 1);
}

TEST(SculptScript, AbsentStrokeKeysKeepTheirDefaults) {
  const Script s = parse(with_strokes({plain_stroke()}));
  ASSERT_EQ(s.strokes.size(), 1u);
  const Stroke& st = s.strokes[0];
  EXPECT_EQ(st.tool, Tool::Probe);
  EXPECT_DOUBLE_EQ(st.radius_mm, 3.0);
  EXPECT_DOUBLE_EQ(st.speed_mm_s, 30.0);
  EXPECT_DOUBLE_EQ(st.depth_mm, 1.0);
  EXPECT_DOUBLE_EQ(st.resilience_mm, 0.3);
  EXPECT_DOUBLE_EQ(st.height_mm, 0.5);
  EXPECT_DOUBLE_EQ(st.strength, 1.0);
  EXPECT_EQ(st.falloff, Falloff::Linear);  // linear for every tool but carve and add
  EXPECT_EQ(st.field, BrushField::Colour);
  EXPECT_FLOAT_EQ(st.value, 0.0f);
  EXPECT_DOUBLE_EQ(st.pressure_force_n, 1.0);
  EXPECT_FLOAT_EQ(st.colour.x(), 0.8f);
  EXPECT_FLOAT_EQ(st.colour.y(), 0.1f);
  EXPECT_FLOAT_EQ(st.colour.z(), 0.1f);
}

TEST(SculptScript, FalloffDefaultsToConstantOnlyForCarveAndAdd) {
  // Constant is the exact boolean for carve and add; the others blend with a linear cone.
  const std::vector<std::pair<std::string, Falloff>> cases = {
      {"probe", Falloff::Linear}, {"carve", Falloff::Constant}, {"add", Falloff::Constant},
      {"paint", Falloff::Linear}, {"smooth", Falloff::Linear},  {"flatten", Falloff::Linear}};
  for (const auto& [tool, falloff] : cases) {
    json stroke = plain_stroke();
    stroke["tool"] = tool;
    EXPECT_EQ(parse(with_strokes({stroke})).strokes[0].falloff, falloff) << tool;
  }
  json stroke = plain_stroke();
  stroke["tool"] = "carve";
  stroke["falloff"] = "linear";  // an explicit falloff wins over the tool's default
  EXPECT_EQ(parse(with_strokes({stroke})).strokes[0].falloff, Falloff::Linear);
}

TEST(SculptScript, EveryToolFalloffAndFieldNameIsRead) {
  json probe = plain_stroke();
  probe["tool"] = "probe";
  EXPECT_EQ(parse(with_strokes({probe})).strokes[0].tool, Tool::Probe);
  const std::vector<std::pair<std::string, BrushTool>> brushes = {{"carve", BrushTool::Carve},
                                                                  {"add", BrushTool::Add},
                                                                  {"paint", BrushTool::Paint},
                                                                  {"smooth", BrushTool::Smooth},
                                                                  {"flatten", BrushTool::Flatten}};
  for (const auto& [name, brush] : brushes) {
    json stroke = plain_stroke();
    stroke["tool"] = name;
    const Stroke st = parse(with_strokes({stroke})).strokes[0];
    EXPECT_EQ(st.tool, Tool::Brush) << name;
    EXPECT_EQ(st.brush, brush) << name;
  }
  const std::vector<std::pair<std::string, Falloff>> falloffs = {
      {"constant", Falloff::Constant}, {"linear", Falloff::Linear}, {"smooth", Falloff::Smooth}};
  for (const auto& [name, falloff] : falloffs) {
    json stroke = plain_stroke();
    stroke["falloff"] = name;
    EXPECT_EQ(parse(with_strokes({stroke})).strokes[0].falloff, falloff) << name;
  }
  const std::vector<std::pair<std::string, BrushField>> fields = {{"colour", BrushField::Colour},
                                                                  {"color", BrushField::Colour},
                                                                  {"roughness", BrushField::Roughness},
                                                                  {"friction_static", BrushField::FrictionStatic},
                                                                  {"friction_dynamic", BrushField::FrictionDynamic},
                                                                  {"stiffness", BrushField::Stiffness},
                                                                  {"layer_thickness", BrushField::LayerThickness}};
  for (const auto& [name, field] : fields) {
    json stroke = plain_stroke();
    stroke["tool"] = "paint";
    stroke["field"] = name;
    EXPECT_EQ(parse(with_strokes({stroke})).strokes[0].field, field) << name;
  }
}

TEST(SculptScript, UndoAndRedoStepsAreRead) {
  const Script s = parse(with_strokes({plain_stroke(), {{"undo", 3}}, {{"redo", 1}}, {{"undo", 1000}}}));
  ASSERT_EQ(s.strokes.size(), 4u);
  EXPECT_EQ(s.strokes[0].tool, Tool::Probe);
  EXPECT_EQ(s.strokes[1].tool, Tool::Undo);
  EXPECT_EQ(s.strokes[1].count, 3);
  EXPECT_EQ(s.strokes[2].tool, Tool::Redo);
  EXPECT_EQ(s.strokes[2].count, 1);
  EXPECT_EQ(s.strokes[3].tool, Tool::Undo);
  EXPECT_EQ(s.strokes[3].count, 1000);
}
TEST(SculptScript, StrokeBrushConvertsMillimetres) {
  json stroke = {{"tool", "carve"}, {"from", {0.5, 0.5, 1}}, {"to", {0.5, 0.6, 1}},
                 {"radius_mm", 4},  {"resilience_mm", 0.5},  {"height_mm", 2},
                 {"strength", 0.5}, {"pressure_force_n", 3}, {"falloff", "smooth"}};
  const double units_per_mm = 0.25;
  Brush b = stroke_brush(parse(with_strokes({stroke})).strokes[0], units_per_mm);
  EXPECT_EQ(b.tool, BrushTool::Carve);
  EXPECT_DOUBLE_EQ(b.radius, 1.0);
  EXPECT_DOUBLE_EQ(b.resilience, 0.125);
  EXPECT_DOUBLE_EQ(b.height, 0.5);
  EXPECT_DOUBLE_EQ(b.strength, 0.5);
  EXPECT_DOUBLE_EQ(b.pressure_force_n, 3.0);  // a force: not scaled
  EXPECT_EQ(b.falloff, Falloff::Smooth);

  // A painted layer thickness is a length (mm, scaled); other painted values are not.
  stroke = {
      {"tool", "paint"}, {"from", {0.5, 0.5, 1}}, {"to", {0.5, 0.6, 1}}, {"field", "layer_thickness"}, {"value", 2}};
  b = stroke_brush(parse(with_strokes({stroke})).strokes[0], units_per_mm);
  EXPECT_EQ(b.tool, BrushTool::Paint);
  EXPECT_EQ(b.field, BrushField::LayerThickness);
  EXPECT_FLOAT_EQ(b.value, 0.5f);
  stroke["field"] = "roughness";
  stroke["value"] = 0.75;
  b = stroke_brush(parse(with_strokes({stroke})).strokes[0], units_per_mm);
  EXPECT_FLOAT_EQ(b.value, 0.75f);
}

}  // namespace
}  // namespace hdm::app
