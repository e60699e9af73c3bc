// SPDX-License-Identifier: MIT
// Every registered brush through `hdm sculpt`'s script parser and a stroke on the bunny: the
// script names it, the parser gives its brush, and the stroke changes the model as that brush
// should (carve never raises, add never lowers, smooth stays within the former range, paint
// changes only its field and moves it towards the painted value). The expectations are written
// here from docs/editing.md, one per brush name: a brush without one fails the test.
#include "sculpt_script.h"

#include "edit/stroke_fixture.h"

#include <hdm/core/error.h>
#include <hdm/edit/brush_registry.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <string>

namespace hdm::app {
namespace {

using Check = std::function<void(const hdm::test::ModelState& before, const hdm::test::ModelState& after)>;

// The stored fields (not the derived positions and normals) that differ between @p a and @p b.
std::set<std::string> changed_fields(const hdm::test::ModelState& a, const hdm::test::ModelState& b) {
  std::set<std::string> out;
  if (a.displacement != b.displacement) out.insert("displacement");
  if (a.friction_static != b.friction_static) out.insert("friction_static");
  if (a.friction_dynamic != b.friction_dynamic) out.insert("friction_dynamic");
  if (a.stiffness_scale != b.stiffness_scale) out.insert("stiffness_scale");
  if (a.layer_displacement != b.layer_displacement) out.insert("layer_displacement");
  if (a.roughness != b.roughness) out.insert("roughness");
  if (a.colour != b.colour) out.insert("colour");
  return out;
}

// Samples whose displacement went down and up.
std::pair<int, int> moves(const hdm::test::ModelState& before, const hdm::test::ModelState& after) {
  int down = 0, up = 0;
  for (size_t s = 0; s < before.displacement.size(); ++s) {
    down += after.displacement[s] < before.displacement[s];
    up += after.displacement[s] > before.displacement[s];
  }
  return {down, up};
}

const std::set<std::string> kShape = {"displacement"};

// Only displacements changed, some of them, all lowered (carve) or all raised (add).
void one_way(const hdm::test::ModelState& before, const hdm::test::ModelState& after, bool lowers) {
  EXPECT_EQ(changed_fields(before, after), kShape);
  const auto [down, up] = moves(before, after);
  EXPECT_GT(lowers ? down : up, 0);
  EXPECT_EQ(lowers ? up : down, 0) << (lowers ? "carve raised the surface" : "add lowered the surface");
}
constexpr float kPainted = 0.9f;  // the value the script paints into friction_static

const std::map<std::string, Check>& expectations() {
  static const std::map<std::string, Check> e = {
      {"carve", [](const hdm::test::ModelState& b, const hdm::test::ModelState& a) { one_way(b, a, true); }},
      {"add", [](const hdm::test::ModelState& b, const hdm::test::ModelState& a) { one_way(b, a, false); }},
      // Drill removes material only: lowers, never raises (docs/haptics.md, "Drilling").
      {"drill", [](const hdm::test::ModelState& b, const hdm::test::ModelState& a) { one_way(b, a, true); }},
      {"smooth",
       [](const hdm::test::ModelState& b, const hdm::test::ModelState& a) {
         EXPECT_EQ(changed_fields(b, a), kShape);
         // Relaxing towards neighbour means never leaves the range the displacements had.
         const auto [lo, hi] = std::minmax_element(b.displacement.begin(), b.displacement.end());
         for (float d : a.displacement) ASSERT_TRUE(d >= *lo && d <= *hi) << d;
       }},
      {"flatten",
       [](const hdm::test::ModelState& b, const hdm::test::ModelState& a) { EXPECT_EQ(changed_fields(b, a), kShape); }},
      {"paint",
       [](const hdm::test::ModelState& b, const hdm::test::ModelState& a) {
         EXPECT_EQ(changed_fields(b, a), std::set<std::string>{"friction_static"});
         int changed = 0;
         for (size_t s = 0; s < b.friction_static.size(); ++s) {
           if (a.friction_static[s] == b.friction_static[s]) continue;
           ++changed;
           ASSERT_LT(std::abs(a.friction_static[s] - kPainted), std::abs(b.friction_static[s] - kPainted)) << s;
         }
         EXPECT_GT(changed, 0);
       }},
  };
  return e;
}

// One stroke of @p name as a script spells it, with every key a brush may read.
nlohmann::json script_of(const std::string& name) {
  nlohmann::json stroke = {
      {"tool", name},      {"from", {0.55, 0.5, 1.0}}, {"to", {0.62, 0.5, 1.0}},   {"radius_mm", 3.0},
      {"height_mm", 0.5},  {"resilience_mm", 0.1},     {"strength", 1.0},          {"field", "friction_static"},
      {"value", kPainted}, {"pressure_force_n", 1.0},  {"wear_coefficient", 0.05}, {"rpm", 200000.0}};
  return {{"strokes", nlohmann::json::array({stroke})}};
}

TEST(BrushRegistryScript, EveryBrushParsesAndStrokesAsItShould) {
  ASSERT_FALSE(brush_registry().empty());
  hdm::test::BunnyStrokes f;
  const hdm::test::ModelState start(f.model);
  const Vec3 a = f.surface_point(Vec3(0.55, 0.5, 1.0)), b = f.surface_point(Vec3(0.62, 0.5, 1.0));
  std::vector<Vec3> points, normals;
  f.surface_path(a, b, 0.05 * f.mm, points, normals);
  ASSERT_GT(points.size(), 20u);
  for (const BrushInfo& info : brush_registry()) {
    SCOPED_TRACE(info.name);
    const Script script = parse_script(script_of(info.name).dump(), "brushes.json");
    ASSERT_EQ(script.strokes.size(), 1u);
    const Stroke& st = script.strokes[0];
    ASSERT_EQ(st.tool, Tool::Brush);
    ASSERT_EQ(st.brush, info.tool);
    const Brush brush = stroke_brush(st, f.mm);
    EXPECT_EQ(brush.tool, info.tool);
    EXPECT_NEAR(brush.radius, 3.0 * f.mm, 1e-12 * f.mm);
    EXPECT_NO_THROW(check_brush(brush));
    const auto expected = expectations().find(info.name);
    if (expected == expectations().end()) {
      ADD_FAILURE() << "no expectation for the brush '" << info.name << "': add one to this test";
      continue;
    }
    f.model = hdm::test::baked_bunny(0, 16);  // each brush on the unedited model
    StrokeEditor editor(f.model);
    f.stroke(editor, brush, points, normals, 0.5 * f.mm, 1e-3, brush.pressure_force_n);
    expected->second(start, hdm::test::ModelState(f.model));
  }
}

TEST(BrushRegistryScript, AnUnknownToolIsRefusedListingEveryBrush) {
  const nlohmann::json j = script_of("chisel");
  try {
    parse_script(j.dump(), "brushes.json");
    FAIL() << "accepted the tool 'chisel'";
  } catch (const InvalidInput& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("unknown tool 'chisel'"), std::string::npos) << m;
    EXPECT_NE(m.find("probe"), std::string::npos) << m;
    for (const BrushInfo& info : brush_registry()) EXPECT_NE(m.find(info.name), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace hdm::app
