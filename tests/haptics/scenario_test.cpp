// SPDX-License-Identifier: MIT
// Scenario pass/fail figures on the paper's bunny configuration (150 slabs, 16 intervals per edge; the thin sheet on
// the default 1,178 slabs), scored against the exact input mesh (Embree), and the stiffness limit against sampled-data
// passivity theory. Energy bounds allow a few per cent above 1 where the hand slides: force
// shading (interpolated normals) is not a conservative field (Ruspini et al. 1997), so a stroke can
// gain a little energy even from an ideal proxy.
#include "haptics/haptics_fixtures.h"
#include "support/test_models.h"

#include <hdm/core/error.h>
#include <hdm/harness/scenarios.h>

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

namespace hdm {
namespace {

const test::BunnyFixture& bunny() { return test::paper_bunny(); }

ScenarioReport run(Scenario s, RenderMode mode, double rate = 1000) {
  ScenarioOptions o;
  o.scenario = s;
  o.mode = mode;
  o.rate_hz = rate;
  return run_scenario(bunny().model, bunny().locator, bunny().reference, o);
}

TEST(Scenario, SlideIsSmoothAndFollowsTheInputNormals) {
  const ScenarioReport r = run(Scenario::Slide, RenderMode::Proxy);
  EXPECT_EQ(r.pop_throughs, 0);
  EXPECT_GT(r.contact_ticks, r.ticks / 2);
  EXPECT_LT(r.max_force_step_pct, 5.0);
  EXPECT_LT(r.normal_error_smooth_p95_deg, 10.0);
  EXPECT_LE(r.energy_ratio, 1.02);
  EXPECT_LT(r.force_cv, 0.1) << "constant hand force over a smooth back";
  EXPECT_LT(r.proxy_surface_error_max, 1e-6);
  // Hand at 1 N: the mean contact force is near it (approach and lift-off included).
  EXPECT_NEAR(r.mean_contact_force_n, 1.0, 0.3);
}

TEST(Scenario, PressReachesMaxForceWithoutPopThrough) {
  const ScenarioReport p = run(Scenario::Press, RenderMode::Proxy);
  EXPECT_EQ(p.pop_throughs, 0);
  EXPECT_NEAR(p.max_force_n, 3.3, 1e-6) << "the hand pushes with 1.2 × max force";
  EXPECT_LE(p.energy_ratio, 1.0);
  const ScenarioReport q = run(Scenario::Press, RenderMode::Penalty);
  EXPECT_LE(p.pop_throughs, q.pop_throughs);
}

// On the default bunny (1,178 slabs): at the paper's 150 slabs the bake does not resolve the
// ear (92 sample rays miss it, 1.9% maximum error, a bound hdm bake never returns), and
// on the thinnest site the rendered ear bulges, so that a frictionless proxy pushed there drifts
// round the rim and lets go, a 2 N step.
TEST(Scenario, ThinSheetHoldsWithProxyOnly) {
  static const test::BakedMesh bunny(test::bunny(), "bunny00.off", 0, 16);
  auto run_thin = [](RenderMode mode) {
    ScenarioOptions o;
    o.scenario = Scenario::Thin;
    o.mode = mode;
    return run_scenario(bunny.model, bunny.locator, bunny.reference, o);
  };
  const ScenarioReport p = run_thin(RenderMode::Proxy);
  const ScenarioReport q = run_thin(RenderMode::Penalty);
  EXPECT_EQ(p.pop_throughs, 0) << p.note;
  EXPECT_LE(p.energy_ratio, 1.01) << "the proxy contact stays (nearly) passive";
  // The paper's memoryless force flips as the hand crosses the sheet's midline: abruptly (a
  // pop-through) or through small forces, and either way returns energy the hand never put in.
  EXPECT_GT(q.energy_ratio, 1.0) << "the penalty force flips in the sheet: " << q.note;
  // A memoryless renderer of the exact input (spring to the HIP's closest input point) flips too,
  // once the hand passes the sheet's midline: the reference step is a pop-through the proxy avoids.
  EXPECT_GT(p.reference_force_step_pct, 30.0) << p.note;
  EXPECT_LT(p.max_force_step_pct, 0.5 * p.reference_force_step_pct) << p.note;
}

TEST(Scenario, EdgesCrossSlabsWithoutSteps) {
  const ScenarioReport r = run(Scenario::Edges, RenderMode::Proxy);
  EXPECT_EQ(r.pop_throughs, 0);
  EXPECT_GE(r.slab_crossings, 5);
  EXPECT_LT(r.max_force_step_pct, 10.0);
  EXPECT_LT(r.normal_error_smooth_p95_deg, 10.0);
  EXPECT_LE(r.energy_ratio, 1.05);
  const ScenarioReport q = run(Scenario::Edges, RenderMode::Penalty);
  EXPECT_LE(r.normal_error_smooth_p95_deg, q.normal_error_smooth_p95_deg + 1.0)
      << "the proxy's force follows the input at least as well as the paper's SCP";
}

// The ball (sphere proxy, r = 1 % of the diagonal) on the default bunny, pressed with 1.2 times
// the force limit: the hand's spring is several r long there, and the ball holds still under it,
// its force along the exact ball's contact normal (from the input's closest point to the centre).
// When shading was gated by r plus the spring, it switched on and off as the ball moved over the
// curved spot, and the ball jumped between two centres on alternate ticks (5.4 % steps).
TEST(Scenario, TheBallHoldsStillUnderADeepPress) {
  static const test::BakedMesh bunny(test::bunny(), "bunny00.off", 0, 16);
  ScenarioOptions o;
  o.scenario = Scenario::Press;
  o.mode = RenderMode::Sphere;
  const ScenarioReport r = run_scenario(bunny.model, bunny.locator, bunny.reference, o);
  EXPECT_EQ(r.mode, "sphere");
  EXPECT_DOUBLE_EQ(r.ball_radius, 0.01 * bunny.model.source_diagonal);
  EXPECT_EQ(r.pop_throughs, 0) << r.note;
  EXPECT_NEAR(r.max_force_n, 3.3, 1e-6) << "the hand pushes with 1.2 × max force";
  EXPECT_LT(r.max_force_step_pct, 2.0) << r.note;
  EXPECT_LT(r.normal_error_smooth_p95_deg, 10.0) << r.note;
  EXPECT_LE(r.energy_ratio, 1.01) << r.note;
  // Sliding, the hand presses the ball's surface (its targets lifted by r) with the set 1 N.
  o.scenario = Scenario::Slide;
  const ScenarioReport sl = run_scenario(bunny.model, bunny.locator, bunny.reference, o);
  EXPECT_EQ(sl.pop_throughs, 0) << sl.note;
  EXPECT_NEAR(sl.mean_contact_force_n, 1.0, 0.3) << sl.note;
  EXPECT_LT(sl.max_force_step_pct, sl.reference_facet_force_step_pct) << sl.note;
  EXPECT_LT(sl.normal_error_smooth_p95_deg, 10.0) << sl.note;
}

TEST(Scenario, RefusesTheRigidToolAndABallRadiusItCannotUse) {
  try {
    run(Scenario::Press, RenderMode::RigidTool);
    FAIL() << "the rigid tool was scored";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("mode rigid"), std::string::npos) << e.what();
  }
  ScenarioOptions o;
  for (double radius : {-1.0, double(NAN), double(INFINITY)}) {
    o.mode = RenderMode::Sphere;
    o.ball_radius = radius;
    try {
      run_scenario(bunny().model, bunny().locator, bunny().reference, o);
      FAIL() << "ball radius " << radius << " was taken";
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find("ball radius"), std::string::npos) << e.what();
    }
  }
  o.mode = RenderMode::Proxy;  // a radius for the point proxy: meant for the ball
  o.ball_radius = 0.01;
  try {
    run_scenario(bunny().model, bunny().locator, bunny().reference, o);
    FAIL() << "a ball radius was taken for the point proxy";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("(mode sphere) only"), std::string::npos) << e.what();
  }
}

// Sampled-data passivity (Colgate & Brown 1994): a virtual wall K with virtual damping b held for
// T is passive iff K < 2b/T. The sweep steps by 10^0.1, so the passive limit found must lie in
// (2b/T / 10^0.1 / 1.3, 2b/T].
TEST(Scenario, PassiveStiffnessMatchesSampledDataTheory) {
  for (double rate : {1000.0, 4000.0}) {
    const ScenarioReport r = run(Scenario::Stiff, RenderMode::Proxy, rate);
    const double theory = 2 * 1.0 * rate;  // b = 1 N·s/m (ForceParams default)
    EXPECT_LE(r.passive_stiffness_n_per_m, theory) << rate;
    EXPECT_GT(r.passive_stiffness_n_per_m, theory / 1.6) << rate;
    EXPECT_GE(r.stable_stiffness_n_per_m, r.passive_stiffness_n_per_m) << rate;
  }
}

}  // namespace
}  // namespace hdm
