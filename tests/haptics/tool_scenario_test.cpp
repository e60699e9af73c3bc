// SPDX-License-Identifier: MIT
// The tool scenarios of `hdm feel` against the analytic geometry they build: the block
// [-1,1]² × [-1,0] (with a slot |x| < 0.2, 0.4 deep, for Slot). The traced ball centres are judged
// by their exact distance to that solid, computed here from its boxes, and the forces by the
// analytic contact normal of a ball on a face or round an edge; not by the harness's own scores.
#include <hdm/core/error.h>
#include <hdm/harness/tool_scenarios.h>

#include "haptics/haptics_fixtures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <utility>

namespace hdm {
namespace {

using test::angle_deg;

constexpr double kR = 0.3;

// Distance from (x, z) to the box [x0, x1] × [z0, z1] (0 inside).
double box_distance(double x, double z, double x0, double x1, double z0, double z1) {
  const double dx = std::max({x0 - x, 0.0, x - x1}), dz = std::max({z0 - z, 0.0, z - z1});
  return std::hypot(dx, dz);
}

// Distance from a point over the middle of the block (|y| well inside) to the solid: the block,
// less the slot when @p slot.
double block_distance(const Vec3& c, bool slot) {
  if (!slot) return box_distance(c.x(), c.z(), -1, 1, -1, 0);
  return std::min({box_distance(c.x(), c.z(), -1, -0.2, -1, 0), box_distance(c.x(), c.z(), 0.2, 1, -1, 0),
                   box_distance(c.x(), c.z(), -0.2, 0.2, -1, -0.4)});
}

ToolScenarioReport run(ToolScenario s, double speed = 0.1) {
  ToolScenarioOptions o;
  o.scenario = s;
  o.proxy.force.stiffness = 1000;
  o.proxy.force.max_force = 3.3;
  o.speed_m_s = speed;
  o.keep_trace = true;
  return run_tool_scenario(o);
}

// Pressed with 1 N over a slot narrower than the ball, the ball rests on the two rims: its centre
// sqrt(r² − 0.2²) above the top and over the slot's middle, never closer to the solid than r less
// 2 % of r.
TEST(ToolScenario, SlotHoldsTheBallOnItsRims) {
  const ToolScenarioReport r = run(ToolScenario::Slot);
  ASSERT_EQ(r.centre.size(), size_t(r.ticks));
  double worst = 0;
  for (size_t k = 0; k < r.centre.size(); ++k)
    if (r.force[k].norm() > 0) worst = std::max(worst, kR - block_distance(r.centre[k], true));
  const Vec3 rest = r.centre.back();
  std::printf("slot: max penetration %.4f %% of r (analytic), %.4f %% (harness); rest height %.5f (analytic %.5f)\n",
              100 * worst / kR, r.max_penetration_pct_r, rest.z(), std::sqrt(kR * kR - 0.04));
  EXPECT_LE(worst, 0.02 * kR);
  EXPECT_NEAR(rest.z(), std::sqrt(kR * kR - 0.2 * 0.2), 0.02 * kR);
  EXPECT_NEAR(rest.x(), 0.0, 0.02 * kR);
  EXPECT_NEAR(r.max_penetration_pct_r, 100 * std::max(0.0, worst) / kR, 0.5);
  EXPECT_FALSE(r.entered);
  EXPECT_NEAR(r.force.back().z(), 1.0, 0.05) << "the hand's 1 N, straight up from the two rims";
  // Passive: the walls return no more work to the hand than they absorbed (0: nothing measured).
  EXPECT_GT(r.energy_ratio, 0);
  EXPECT_LE(r.energy_ratio, 1.0);
}

// Rolled over the convex edge, the force follows the analytic contact normal: +z on the top, from
// the edge to the centre round it, +x on the side face; it turns through 90° with no jump.
TEST(ToolScenario, RollEdgeTurnsTheForceContinuously) {
  const ToolScenarioReport r = run(ToolScenario::RollEdge);
  double worst_angle = 0, worst_pen = 0, worst_turn = 0;
  Vec3 prev = Vec3::Zero();
  int scored = 0;
  for (size_t k = 0; k < r.centre.size(); ++k) {
    const Vec3& c = r.centre[k];
    const Vec3& f = r.force[k];
    if (f.norm() < 0.05) {
      prev = Vec3::Zero();
      continue;
    }
    worst_pen = std::max(worst_pen, kR - block_distance(c, false));
    const Vec3 n = c.x() <= 1 ? Vec3::UnitZ() : c.z() >= 0 ? Vec3(c.x() - 1, 0, c.z()) : Vec3::UnitX();
    worst_angle = std::max(worst_angle, angle_deg(f, n));
    if (prev.norm() > 0) worst_turn = std::max(worst_turn, angle_deg(f, prev));
    prev = f;
    ++scored;
  }
  std::printf(
      "roll_edge: max angle to the analytic normal %.3f deg, turn per tick %.3f deg, penetration %.4f %% of "
      "r; harness: step %.3f %%, normal error max %.3f deg\n",
      worst_angle, worst_turn, 100 * worst_pen / kR, r.max_force_step_pct, r.normal_error_max_deg);
  ASSERT_GT(scored, 1000);
  EXPECT_LT(angle_deg(r.force.back(), Vec3::UnitX()), 1.0) << "on the side face";
  EXPECT_LE(worst_pen, 0.02 * kR);
  // The bake rounds the edge over about one grid cell (0.05 here): there the rendered normal
  // leads the analytic one by a few degrees.
  EXPECT_LT(worst_angle, 8.0);
  // Analytic turn per tick round the edge: v·dt / r = 0.1 m/s × 1 ms / 3 cm = 0.19°.
  EXPECT_LT(worst_turn, 1.0);
  EXPECT_LT(r.max_force_step_pct, 2.0);
  EXPECT_GT(r.energy_ratio, 0);
  EXPECT_LE(r.energy_ratio, 1.0) << "passive round the edge";
}

// The burr held leaning on the pit's edge: its head rests on the floor (the tip r above it) and its
// shaft on the edge, two contacts; the edge, up and to the side of the tip, pushes the shaft up and
// away from the block, so the torque about the tip turns the tool upright (+y), in the tool's plane.
TEST(ToolScenario, ShaftEdgeRestsOnTheFloorAndTheEdge) {
  ToolScenarioOptions o;
  o.scenario = ToolScenario::ShaftEdge;
  const ToolScenarioReport r = run_tool_scenario(o);
  const double head = 0.1, floor = -0.4;
  std::printf(
      "shaft_edge: tip (%.4f, %.4f, %.4f), torque (%.5f, %.5f, %.5f) N m, %.2f %% from the lever-arm "
      "reference\n",
      r.tool_tip.x(), r.tool_tip.y(), r.tool_tip.z(), r.tool_torque.x(), r.tool_torque.y(), r.tool_torque.z(),
      r.torque_error_pct);
  EXPECT_GE(r.head_contacts, 1);
  EXPECT_GE(r.shaft_contacts, 1);
  EXPECT_NEAR(r.tool_tip.z(), floor + head, 0.02 * head) << "the head rests on the floor";
  EXPECT_GT(r.tool_tip.x(), head) << "clear of the pit's wall";
  const Vec3 lever = Vec3(0, r.tool_tip.y(), 0) - r.tool_tip;  // to the edge point in the tool's plane
  EXPECT_GT(lever.z(), 0);
  EXPECT_LT(lever.x(), 0);
  EXPECT_GT(r.tool_torque.y(), 0) << "the edge's push turns the tool upright";
  EXPECT_LT(std::hypot(r.tool_torque.x(), r.tool_torque.z()), 0.1 * r.tool_torque.y()) << "in the tool's plane";
  EXPECT_TRUE(r.torque_sense_ok);
  EXPECT_GT(r.energy_ratio, 0);
  EXPECT_LE(r.energy_ratio, 1.0) << "passive with force and torque, the wrist yielding";
}

// The torque about the tip is the lever-arm moment of the two frictionless contacts, computed here
// from the held tip, axis and force: the floor's force is along +z straight below the tip (no
// moment), the edge's along the shaft's normal at the edge point c in the tool's plane, so its
// size is F.x / n.x and the torque is (c − tip) × F_edge; within 5 % at 1 and 10 kHz, whether the
// hand's wrist yields to the torque (the default) or holds the handle's attitude rigidly.
TEST(ToolScenario, ShaftEdgeTorqueIsTheEdgeContactsLeverArmMoment) {
  for (const auto& [rate, wrist] : {std::pair{1000.0, 1.0}, {10000.0, 1.0}, {1000.0, INFINITY}}) {
    ToolScenarioOptions o;
    o.scenario = ToolScenario::ShaftEdge;
    o.rate_hz = rate;
    o.device.wrist_stiffness = wrist;
    const ToolScenarioReport r = run_tool_scenario(o);
    const Vec3 c(0, r.tool_tip.y(), 0), axis = r.tool_axis.normalized();
    const Vec3 n = (r.tool_tip + (c - r.tool_tip).dot(axis) * axis - c).normalized();  // edge → shaft axis
    const Vec3 edge_force = (r.tool_force.x() / n.x()) * n;
    const Vec3 reference = ((c - r.tool_tip) / 10.0).cross(edge_force);  // 10 model units per metre [N·m]
    const double error = (r.tool_torque - reference).norm() / reference.norm();
    std::printf(
        "shaft_edge at %.0f Hz, wrist %g N m/rad: torque (%.5f, %.5f, %.5f), lever arm (%.5f, %.5f, %.5f) N m: %.2f "
        "%%\n",
        rate, wrist, r.tool_torque.x(), r.tool_torque.y(), r.tool_torque.z(), reference.x(), reference.y(),
        reference.z(), 100 * error);
    EXPECT_LT(error, 0.05) << rate << " Hz";
    EXPECT_LT(std::abs(r.tool_force.y()), 0.01 * r.tool_force.norm()) << "no force along the edge";
    EXPECT_GT(r.tool_force.x(), 0) << "the edge pushes the shaft away from the block";
  }
}

// Drilling at equal force, enamel and dentin each lose Archard's K·v_s/H per N·s of the head's
// contact force (computed here: a 1 mm burr at 200,000 rpm, K = 0.01), so their removal rates stand
// in the inverse ratio of their hardnesses, 300 / 55.
TEST(ToolScenario, DrillLayersRemovesByArchardOnEachLayer) {
  ToolScenarioOptions o;
  o.scenario = ToolScenario::DrillLayers;
  const ToolScenarioReport r = run_tool_scenario(o);
  const double speed = 2 * std::numbers::pi * 200000 / 60 * 1e-3;                   // ω·r [m/s]
  auto archard = [&](double hv) { return 0.01 * speed / (hv * 9.80665e6) * 1e9; };  // [mm³/(N·s)]
  std::printf("drill_layers: enamel %.5f (Archard %.5f), dentin %.5f (Archard %.5f) mm3/(N s), ratio %.4f\n",
              r.enamel_rate, archard(300), r.dentin_rate, archard(55), r.dentin_rate / r.enamel_rate);
  EXPECT_NEAR(r.enamel_rate / archard(300), 1.0, 0.05);
  EXPECT_NEAR(r.dentin_rate / archard(55), 1.0, 0.05);
  EXPECT_NEAR(r.dentin_rate / r.enamel_rate / (300.0 / 55.0), 1.0, 0.10);
}

TEST(ToolScenario, BadOptionsAndNamesAreRefused) {
  EXPECT_EQ(parse_tool_scenario("roll_edge"), ToolScenario::RollEdge);
  EXPECT_EQ(parse_tool_scenario("drill_layers"), ToolScenario::DrillLayers);
  EXPECT_TRUE(is_tool_scenario("slot"));
  EXPECT_FALSE(is_tool_scenario("slide"));
  EXPECT_THROW(parse_tool_scenario("groove"), InvalidInput);
  ToolScenarioOptions o;
  o.rate_hz = 10;
  EXPECT_THROW(run_tool_scenario(o), InvalidInput);
  o = {};
  o.press_force_n = NAN;
  EXPECT_THROW(run_tool_scenario(o), InvalidInput);
}

}  // namespace
}  // namespace hdm
