// SPDX-License-Identifier: MIT
// The brush registry: every brush is found by its BrushTool and its name, the defaults and
// parameters are those docs/editing.md gives, every range check names its parameter, and an
// unregistered tool edits nothing (without throwing: edits run in the servo tick).
#include "support/test_models.h"

#include <hdm/core/error.h>
#include <hdm/edit/brush_registry.h>
#include <hdm/edit/edit_tools.h>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <string>

using namespace hdm;

namespace {

// What docs/editing.md documents for each brush: its default falloff and its own parameters
// (beyond radius, strength and falloff, which every brush reads).
struct Documented {
  Falloff falloff;
  std::vector<BrushParam> own;
};
const std::map<std::string, Documented> kDocumented = {
    {"carve", {Falloff::Constant, {BrushParam::Resilience}}},
    {"add", {Falloff::Constant, {BrushParam::Height}}},
    {"smooth", {Falloff::Smooth, {BrushParam::Pressure}}},
    {"flatten", {Falloff::Smooth, {BrushParam::Pressure}}},
    {"paint", {Falloff::Linear, {BrushParam::Field, BrushParam::Colour, BrushParam::Value, BrushParam::Pressure}}},
    {"drill", {Falloff::Smooth, {BrushParam::WearCoefficient, BrushParam::Rpm}}},
};

std::string refusal(const Brush& b) {
  try {
    check_brush(b);
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "";
}

Brush valid_brush() {
  Brush b;
  b.radius = 0.1;
  return b;
}

}  // namespace

TEST(BrushRegistry, EveryBrushIsFoundByItsToolAndItsName) {
  ASSERT_FALSE(brush_registry().empty());
  for (const BrushInfo& info : brush_registry()) {
    SCOPED_TRACE(info.name);
    EXPECT_EQ(find_brush(info.tool), &info);
    EXPECT_EQ(find_brush(std::string_view(info.name)), &info);
    EXPECT_EQ(parse_brush_tool(info.name), info.tool);
    EXPECT_STREQ(brush_tool_name(info.tool), info.name);
    EXPECT_NE(brush_names().find(info.name), std::string::npos);
    EXPECT_NE(std::string(info.label), "");
    EXPECT_NE(std::string(info.summary), "");
    EXPECT_NE(info.hooks, nullptr);
  }
  EXPECT_EQ(find_brush(std::string_view("chisel")), nullptr);
  EXPECT_EQ(find_brush(static_cast<BrushTool>(200)), nullptr);
  EXPECT_STREQ(brush_tool_name(static_cast<BrushTool>(200)), "?");
  EXPECT_THROW(parse_brush_tool("chisel"), InvalidInput);
}

TEST(BrushRegistry, DefaultsAndParametersAreTheDocumentedOnes) {
  for (const BrushInfo& info : brush_registry()) {
    SCOPED_TRACE(info.name);
    const auto doc = kDocumented.find(info.name);
    ASSERT_NE(doc, kDocumented.end()) << "document the brush '" << info.name << "' here and in docs/editing.md";
    EXPECT_EQ(info.falloff, doc->second.falloff);
    for (BrushParam p : {BrushParam::Radius, BrushParam::Strength, BrushParam::Falloff}) EXPECT_TRUE(info.uses(p));
    for (int p = 0; p < brush_param_count; ++p) {
      const BrushParam param = static_cast<BrushParam>(p);
      if (param == BrushParam::Radius || param == BrushParam::Strength || param == BrushParam::Falloff) continue;
      const bool own = std::find(doc->second.own.begin(), doc->second.own.end(), param) != doc->second.own.end();
      EXPECT_EQ(info.uses(param), own) << brush_param_range(param).name;
    }
  }
}

TEST(BrushRegistry, EveryRangeCheckNamesItsParameterAndTheReason) {
  EXPECT_EQ(refusal(valid_brush()), "");
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  struct Case {
    const char* name;
    std::function<void(Brush&)> set;
  };
  const std::vector<Case> bad = {
      {"radius", [](Brush& b) { b.radius = 0; }},
      {"radius", [](Brush& b) { b.radius = -1; }},
      {"radius", [&](Brush& b) { b.radius = nan; }},
      {"radius", [&](Brush& b) { b.radius = inf; }},
      {"strength", [](Brush& b) { b.strength = -0.01; }},
      {"strength", [](Brush& b) { b.strength = 1.01; }},
      {"resilience", [](Brush& b) { b.resilience = -1e-9; }},
      {"height", [](Brush& b) { b.height = -1; }},
      {"height", [&](Brush& b) { b.height = inf; }},
      {"colour", [](Brush& b) { b.colour = Vec3f(0.5f, 1.5f, 0.5f); }},
      {"colour", [](Brush& b) { b.colour = Vec3f(-0.1f, 0.5f, 0.5f); }},
      {"value", [&](Brush& b) { b.value = static_cast<float>(nan); }},
      {"pressure_force_n", [](Brush& b) { b.pressure_force_n = 0; }},
      {"wear_coefficient", [](Brush& b) { b.wear_coefficient = 0; }},
      {"wear_coefficient", [](Brush& b) { b.wear_coefficient = 1.5; }},
      {"wear_coefficient", [&](Brush& b) { b.wear_coefficient = nan; }},
      {"rpm", [](Brush& b) { b.rpm = -1; }},
      {"rpm", [](Brush& b) { b.rpm = 2e6; }},
  };
  for (const Case& c : bad) {
    Brush b = valid_brush();
    c.set(b);
    const std::string m = refusal(b);
    EXPECT_EQ(m.rfind(std::string(c.name) + " = ", 0), 0u) << c.name << ": " << m;
    EXPECT_NE(m.find("must be"), std::string::npos) << m;
  }
  // The bounds themselves are valid where the range is closed.
  Brush edge = valid_brush();
  edge.strength = 0, edge.resilience = 0, edge.height = 0, edge.colour = Vec3f(0, 1, 0), edge.value = -1e6f;
  edge.wear_coefficient = 1, edge.rpm = 1e6;
  EXPECT_EQ(refusal(edge), "");
  edge.strength = 1;
  EXPECT_EQ(refusal(edge), "");
  Brush unknown = valid_brush();
  unknown.tool = static_cast<BrushTool>(200);
  EXPECT_NE(refusal(unknown).find("tool"), std::string::npos);
}

TEST(BrushRegistry, FieldsStoredAsHalfFloatsRefuseValuesTheyCannotHold) {
  // Friction and hardness are IEEE binary16 in the model: 65,504 is the largest finite value.
  for (BrushField f : {BrushField::FrictionStatic, BrushField::FrictionDynamic, BrushField::Hardness}) {
    Brush b = valid_brush();
    b.field = f;
    b.value = 65504;
    EXPECT_EQ(refusal(b), "");
    b.value = 1e5;
    EXPECT_NE(refusal(b).find("value = 100000: friction and hardness are stored as 16-bit floats"), std::string::npos)
        << refusal(b);
  }
  Brush colour = valid_brush();  // other fields keep the value's full range
  colour.value = 1e5;
  EXPECT_EQ(refusal(colour), "");
}

TEST(BrushRegistry, AnUnregisteredToolEditsNothing) {
  SlabModel m = test::baked_bunny(150, 16);
  EditScratch scratch(m);
  const std::vector<float> before = test::values(m.displacement);
  BrushSweep sw;
  sw.brush.tool = static_cast<BrushTool>(200);
  sw.brush.radius = 0.05 * m.source_diagonal;
  sw.seed_slab = 0;
  sw.seed_bary = Vec3(1 / 3.0, 1 / 3.0, 1 / 3.0);
  sw.from = sw.to = sample_position(m, m.samples.id(0, 0));
  const EditResult r = apply_brush(m, scratch, sw);
  EXPECT_EQ(r.visited, 0);
  EXPECT_EQ(r.changed, 0);
  EXPECT_EQ(test::values(m.displacement), before);
}
