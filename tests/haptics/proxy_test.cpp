// SPDX-License-Identifier: MIT
// Proxy tests on an analytic sphere: the reference is the sphere itself (radius 1, normal = the
// radial direction), never the slab code's own output.
#include "haptics/haptics_fixtures.h"

#include <hdm/core/error.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace hdm {
namespace {

using test::angle_deg;

using test::sphere;
using test::sphere_params;

// Device point [m] for a model point on the unit sphere's frame (workspace scale 10/m).
Vec3 dev(const Vec3& model) { return sphere().ws.to_device(model); }

// The proxy stays on the displaced surface (exactly, through evaluate_surface at its own
// coordinates) and on the analytic sphere (within the bake's fidelity), and the frictionless force
// is radial, while the HIP slides 1 mm deep along a quarter great circle crossing many slab edges.
// Both alpha-plane solvers (the paper's 15-step bisection resolves α to 2^-15 of the shell).
void slide_on_sphere(AlphaSolver solver) {
  const auto& S = sphere();
  ProxyParams p = sphere_params();
  p.solver = solver;
  ProxyState st;
  const int n = 4000;
  std::vector<double> angles;
  int crossings = 0, prev_slab = -1, contact = 0;
  for (int k = 0; k < n; ++k) {
    const double a = 0.5 * std::numbers::pi * k / n;
    const double r = k < 100 ? 1.02 - 0.03 * k / 100.0 : 0.99;  // approach, then 1 mm device deep
    const Vec3 hip(r * std::sin(a), 0.3 * r * std::sin(2 * a), r * std::cos(a));
    const Vec3 hip_m = hip.normalized() * r;
    const ProxyOutput out = proxy_step(S.model, *S.locator, S.ws, dev(hip_m), Vec3::Zero(), p, st);
    if (!st.contact) continue;
    ++contact;
    Contact e;
    evaluate_surface(S.model, st.slab, st.coords, e);
    ASSERT_LT((e.surface_point - st.position).norm(), 1e-6 * S.diag) << "tick " << k;
    // Analytic sphere: the bake reproduces radius 1 to well within 1 % of the diagonal.
    EXPECT_LT(std::abs(st.position.norm() - 1.0), 0.01 * S.diag) << "tick " << k;
    if (out.force.norm() > 0.1) angles.push_back(angle_deg(out.force, st.position));
    if (st.slab != prev_slab && prev_slab >= 0) ++crossings;
    prev_slab = st.slab;
  }
  EXPECT_GT(contact, n - 200);
  EXPECT_GE(crossings, 5) << "the path should cross several slab edges";
  ASSERT_FALSE(angles.empty());
  std::sort(angles.begin(), angles.end());
  EXPECT_LT(angles[angles.size() * 95 / 100], 3.0) << "p95 force direction vs the analytic normal [deg]";
  EXPECT_LT(angles.back(), 6.0);
}

TEST(Proxy, StaysOnSurfaceAndForceIsRadialWhileSliding) { slide_on_sphere(AlphaSolver::Newton); }
TEST(Proxy, StaysOnSurfaceAndForceIsRadialWhileSlidingWithBisection) { slide_on_sphere(AlphaSolver::Bisection); }

// Force continuity across slab edges: the HIP slides 1 mm (device) deep round a great circle in
// 10 µm steps (10 cm/s at 10 kHz), crossing many slab edges and corners. On the analytic sphere
// the force k·depth turns with the HIP, by F·(step / radius) per tick; any extra change between
// ticks is a discontinuity of the rendered surface or of its normal field (a jump between
// slabs, a stall of the proxy followed by a snap).
TEST(Proxy, ForceIsContinuousAcrossSlabEdges) {
  const auto& S = sphere();
  const ProxyParams p = sphere_params();
  ProxyState st;
  const double r = 0.99, step_m = 1e-5, radius_m = r / S.ws.scale;
  const int n = static_cast<int>(std::numbers::pi * radius_m / step_m);  // half a great circle
  const Vec3 axis = Vec3(0.3, 1.0, 0.2).normalized(), u = axis.unitOrthogonal(), w = axis.cross(u);
  Vec3 f_prev = Vec3::Zero();
  int crossings = 0, prev_slab = -1, compared = 0;
  double worst = 0;
  for (int k = 0; k < n; ++k) {
    const double a = step_m / radius_m * k;
    const Vec3 hip = r * (std::cos(a) * u + std::sin(a) * w);
    const ProxyOutput out = proxy_step(S.model, *S.locator, S.ws, dev(hip), Vec3::Zero(), p, st);
    ASSERT_TRUE(st.contact) << "tick " << k;
    if (k > 0) {
      // Analytic change: rotation by step/radius of a force of about |F|.
      const double analytic = out.force.norm() * step_m / radius_m;
      worst = std::max(worst, ((out.force - f_prev).norm() - analytic) / p.force.max_force);
      ++compared;
    }
    if (prev_slab >= 0 && st.slab != prev_slab) ++crossings;
    prev_slab = st.slab;
    f_prev = out.force;
  }
  EXPECT_GE(crossings, 10) << "the circle should cross many slab edges";
  ASSERT_GT(compared, 1000);
  // 0.5 % of max force: the bake's facets (grid 8 on a unit sphere) turn the normal a little faster
  // than the sphere does, never by a step.
  EXPECT_LT(worst, 0.005) << "largest force change beyond the analytic rotation, fraction of max force";
}

TEST(Proxy, ParsesSolverNames) {
  EXPECT_EQ(parse_alpha_solver("newton"), AlphaSolver::Newton);
  EXPECT_EQ(parse_alpha_solver("bisection"), AlphaSolver::Bisection);
  EXPECT_THROW(parse_alpha_solver("secant"), InvalidInput);
}

TEST(Proxy, ParsesRenderModeNames) {
  EXPECT_EQ(parse_render_mode("proxy"), RenderMode::Proxy);
  EXPECT_EQ(parse_render_mode("penalty"), RenderMode::Penalty);
  EXPECT_EQ(parse_render_mode("sphere"), RenderMode::Sphere);
  EXPECT_EQ(parse_render_mode("rigid"), RenderMode::RigidTool);
  try {
    parse_render_mode("Rigid");
    ADD_FAILURE() << "a mode's name is case-sensitive";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("'Rigid'"), std::string::npos) << e.what();
  }
}

// Pushing far past the shell's inner face keeps the contact (the HIP's own query finds no slab
// there); the penalty force of the paper drops to zero at the same point.
TEST(Proxy, HoldsPastTheInnerFaceWherePenaltyPopsThrough) {
  const auto& S = sphere();
  const ProxyParams p = sphere_params();
  const Vec3 d = Vec3(0.3, -0.5, 0.8).normalized();
  ProxyState st, pen;
  ProxyOutput out, out_pen;
  for (int k = 0; k <= 2000; ++k) {
    const double r = 1.05 - 0.55 * k / 2000.0;  // from outside down to radius 0.5
    out = proxy_step(S.model, *S.locator, S.ws, dev(d * r), Vec3::Zero(), p, st);
    out_pen = penalty_step(S.model, *S.locator, S.ws, dev(d * r), Vec3::Zero(), p, pen);
    if (r < 0.995) {
      ASSERT_TRUE(st.contact) << "r " << r;
      EXPECT_GT(out.force.dot(d), 0) << "r " << r;
    }
  }
  SlabCoordinates c;
  EXPECT_LT(S.locator->find(d * 0.5, -1, AlphaSolver::Newton, c), 0) << "radius 0.5 should be below the shell";
  EXPECT_NEAR(out.force.norm(), p.force.max_force, 1e-9) << "clamped at max force";
  EXPECT_LT(angle_deg(out.force, d), 3.0);
  EXPECT_EQ(out_pen.force.norm(), 0.0) << "the paper's penalty force has no memory";
}

// Through the whole sphere and out of the far side: the force keeps pointing out of the entry
// side (a thin part seen from one side), it never flips. Past the centre the far side is the closer
// surface, so a frictionless god-object would slide round to it; with μs = 0.5 it holds, as a
// finger pressed into a real surface does.
TEST(Proxy, NeverFlipsSideWhenPushedThrough) {
  const auto& S = sphere();
  SlabModel model = test::sphere_with_friction();
  const SlabLocator locator(model);
  const ProxyParams p = sphere_params(true);
  const Vec3 d = Vec3(-0.6, 0.2, 0.4).normalized();
  ProxyState st;
  for (int k = 0; k <= 4000; ++k) {
    const double r = 1.05 - 2.3 * k / 4000.0;  // to radius -1.25: out of the far side
    const ProxyOutput out = proxy_step(model, locator, S.ws, dev(d * r), Vec3::Zero(), p, st);
    if (r < 0.99) {
      ASSERT_TRUE(st.contact) << "r " << r;
      ASSERT_GT(out.force.dot(d), 0.99 * out.force.norm()) << "r " << r;
    }
  }
}

// Friction cone with μs = 0.5, μd = 0.3: the proxy sticks while |Ft| <= μs·Fn, then slides with
// |Ft| = μd·Fn. Forces are decomposed with the analytic normal.
TEST(Proxy, FrictionSticksBelowMuStaticAndSlidesAtMuDynamic) {
  const auto& S = sphere();
  SlabModel model = test::sphere_with_friction();  // own copy with friction fields
  const SlabLocator locator(model);
  const ProxyParams p = sphere_params(true);
  ProxyState st;
  const Vec3 pole = Vec3(0.2, 0.3, 1).normalized(), t = pole.cross(Vec3::UnitX()).normalized();
  const double depth = 0.01;  // 1 mm at the device: 1 N
  auto ratio = [&](const ProxyOutput& o) {
    const Vec3 n = st.position.normalized();
    const double fn = o.force.dot(n);
    return (o.force - fn * n).norm() / fn;
  };
  for (int k = 0; k <= 100; ++k)  // press straight in
    proxy_step(model, locator, S.ws, dev(pole * (1.01 - (0.01 + depth) * k / 100.0)), Vec3::Zero(), p, st);
  ASSERT_TRUE(st.contact);
  const Vec3 anchor = st.position;
  // Pull tangentially in small steps: the proxy holds still until |Ft|/Fn reaches μs = 0.5, then
  // breaks away and slides with |Ft|/Fn = μd = 0.3 (forces split with the analytic normal).
  ProxyOutput o;
  double last_stuck_ratio = 0;
  int sliding = 0;
  for (int k = 1; k <= 1200; ++k) {
    o = proxy_step(model, locator, S.ws, dev(pole * (1 - depth) + t * (0.002 * depth * k)), Vec3::Zero(), p, st);
    if (o.status == ProxyStatus::Stuck) {
      ASSERT_EQ(sliding, 0) << "no sticking again while the hand keeps moving, tick " << k;
      EXPECT_LT((st.position - anchor).norm(), 1e-12);
      last_stuck_ratio = ratio(o);
      EXPECT_LE(last_stuck_ratio, 0.5 + 0.01) << k;
    } else {
      ASSERT_EQ(o.status, ProxyStatus::Sliding) << k;
      if (sliding++ > 0) {  // the breakaway tick itself jumps from μs to μd
        EXPECT_NEAR(ratio(o), 0.3, 0.02) << k;
      }
    }
  }
  EXPECT_NEAR(last_stuck_ratio, 0.5, 0.01) << "breakaway at μs";
  EXPECT_GT(sliding, 500);
  EXPECT_GT((st.position - anchor).norm(), depth);
  // Hand stops: the proxy sticks again.
  const Vec3 held = st.position;
  for (int k = 0; k < 20; ++k) o = proxy_step(model, locator, S.ws, st.last_hip / S.ws.scale, Vec3::Zero(), p, st);
  EXPECT_EQ(o.status, ProxyStatus::Stuck);
  EXPECT_LT((st.position - held).norm(), 1e-9);
}

// A proxy held still by friction lies on the surface as edited since the last tick: lower every
// displacement under a resting proxy and the next tick puts it on the lowered surface, judged by
// the query at its position (locator and α solve, not the proxy's own evaluation).
TEST(Proxy, ARestingProxyFollowsAnEditUnderIt) {
  const auto& S = sphere();
  SlabModel model = test::sphere_with_friction();
  const SlabLocator locator(model);
  const ProxyParams p = sphere_params(true);
  ProxyState st;
  const Vec3 pole = Vec3(0.2, 0.3, 1).normalized();
  for (int k = 0; k <= 100; ++k)
    proxy_step(model, locator, S.ws, dev(pole * (1.01 - 0.02 * k / 100.0)), Vec3::Zero(), p, st);
  ASSERT_TRUE(st.contact);
  const Vec3 hip = pole * 0.99;
  ProxyOutput o;
  for (int k = 0; k < 5; ++k) o = proxy_step(model, locator, S.ws, dev(hip), Vec3::Zero(), p, st);
  ASSERT_EQ(o.status, ProxyStatus::Stuck);
  const Vec3 before = st.position;
  // A resting tick reports the contact's ray and δ as an evaluation at the proxy's coordinates does.
  Contact e;
  evaluate_surface(model, st.slab, st.coords, e);
  EXPECT_LT((e.ray - o.contact.ray).norm(), 1e-12 * e.ray.norm());
  EXPECT_NEAR(e.delta, o.contact.delta, 1e-12);
  QueryCache cache;
  EXPECT_LT(std::abs(query(model, locator, before, cache).depth), 1e-9 * S.diag);
  const float drop = float(0.003 / o.contact.ray.norm());  // 0.3 mm at the device, in δ
  ASSERT_LT(drop, 0.5f);
  for (Unorm16& d : model.displacement) d = std::max(0.0f, d - drop);
  rebuild_derived(model);
  o = proxy_step(model, locator, S.ws, dev(hip), Vec3::Zero(), p, st);
  ASSERT_TRUE(st.contact);
  EXPECT_LT(std::abs(query(model, locator, st.position, cache).depth), 1e-9 * S.diag) << "on the edited surface";
  EXPECT_LT(st.position.norm(), before.norm() - 0.002) << "the surface went down under the proxy";
}

// NaN, infinite and huge device positions or velocities: zero force, BadInput, state kept.
TEST(Proxy, BadInputGivesZeroForceAndKeepsState) {
  const auto& S = sphere();
  const ProxyParams p = sphere_params();
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (RenderMode mode : {RenderMode::Proxy, RenderMode::Penalty}) {
    ProxyState st;
    const Vec3 d = Vec3::UnitZ();
    for (int k = 0; k <= 50; ++k)
      render_step(mode, S.model, *S.locator, S.ws, dev(d * (1.01 - 0.02 * k / 50)), Vec3::Zero(), p, st);
    ASSERT_TRUE(st.contact);
    const ProxyState before = st;
    for (const Vec3& bad : {Vec3(nan, 0, 0), Vec3(0, inf, 0), Vec3(1e9, 0, 0), Vec3(0, 0, -1e300), Vec3(2, 0, 0)}) {
      const ProxyOutput o = render_step(mode, S.model, *S.locator, S.ws, bad, Vec3::Zero(), p, st);
      EXPECT_EQ(o.status, ProxyStatus::BadInput);
      EXPECT_EQ(o.force, Vec3::Zero());
    }
    const ProxyOutput ov = render_step(mode, S.model, *S.locator, S.ws, dev(d * 0.99), Vec3(nan, 0, 0), p, st);
    EXPECT_EQ(ov.status, ProxyStatus::BadInput);
    EXPECT_EQ(ov.force, Vec3::Zero());
    EXPECT_EQ(st.contact, before.contact);
    EXPECT_EQ(st.position, before.position);
    const ProxyOutput ok = render_step(mode, S.model, *S.locator, S.ws, dev(d * 0.99), Vec3::Zero(), p, st);
    EXPECT_GT(ok.force.dot(d), 0.5) << "contact resumes after bad samples";
  }
}

// A HIP that jumps across a thin part in one tick (here: into the sphere in a single 5 cm step)
// is still caught at the entry side by the free-space sub-steps.
TEST(Proxy, CatchesAFastEntry) {
  const auto& S = sphere();
  const ProxyParams p = sphere_params();
  ProxyState st;
  const Vec3 d = Vec3(0.1, 0.9, -0.2).normalized();
  proxy_step(S.model, *S.locator, S.ws, dev(d * 1.2), Vec3::Zero(), p, st);
  const ProxyOutput o = proxy_step(S.model, *S.locator, S.ws, dev(d * 0.7), Vec3::Zero(), p, st);
  ASSERT_TRUE(st.contact);
  EXPECT_LT(angle_deg(o.force, d), 3.0);
  EXPECT_NEAR(st.position.norm(), 1.0, 0.01 * S.diag);
}

// The damper never exceeds the spring along the normal: a handle entering fast gets at most twice
// the spring force k·depth (depth from the analytic sphere), so the force starts near zero at the
// surface instead of at b·v; leaving fast, the force never pulls.
TEST(Proxy, DampingIsBoundedByTheSpringAtContactOnset) {
  const auto& S = sphere();
  ProxyParams p = sphere_params();
  p.force.damping = 20.0;  // a strong damper, so b·v alone would dominate k·depth near the surface
  const Vec3 d = Vec3(0.2, 0.3, 0.93).normalized();
  for (double v : {0.05, 0.5}) {  // approach speeds [m/s], into the sphere
    ProxyState st;
    proxy_step(S.model, *S.locator, S.ws, dev(d * 1.01), Vec3::Zero(), p, st);
    const Vec3 hip = d * (1.0 - 0.002 * S.diag);  // just inside the analytic surface
    const ProxyOutput o = proxy_step(S.model, *S.locator, S.ws, dev(hip), -v * d, p, st);
    ASSERT_TRUE(st.contact);
    const double depth_m = (st.position - hip).norm() / S.ws.scale;
    EXPECT_LE(o.force.norm(), 2 * p.force.stiffness * depth_m * (1 + 1e-9) + 1e-12) << "v " << v;
    EXPECT_GT(o.force.dot(d), 0.0) << "pushes outward";
    const ProxyOutput out = proxy_step(S.model, *S.locator, S.ws, dev(hip), 5.0 * d, p, st);  // leaving fast
    EXPECT_GE(out.force.dot(st.normal), -1e-12) << "never pulls";
  }
}

// Hunt & Crossley-style onset: below ProxyParams::damping_force_n of spring force the damping
// coefficient is b·spring/damping_force_n, above it the full b (the spring taken from the proxy's
// own offset to the HIP along its normal, the damping law checked against it).
TEST(Proxy, DampingRampsInWithTheSpringForce) {
  const auto& S = sphere();
  ProxyParams p = sphere_params();
  p.force.damping = 2.0;
  p.damping_force_n = 0.5;
  const double v = 0.05;  // [m/s] into the sphere: b·v = 0.1 N, below every spring force used here
  const Vec3 d = Vec3(0.2, 0.3, 0.93).normalized();
  ProxyState st;
  proxy_step(S.model, *S.locator, S.ws, dev(d * 1.01), Vec3::Zero(), p, st);
  // 0.25 mm and 1.5 mm device deep (k = 1000 N/m, 10 model units per metre): ~0.25 N and ~1.5 N.
  for (double depth_model : {0.0025, 0.015}) {
    const Vec3 hip = d * (1.0 - depth_model);
    const ProxyOutput o = proxy_step(S.model, *S.locator, S.ws, dev(hip), -v * d, p, st);
    ASSERT_TRUE(st.contact);
    const double spring = p.force.stiffness * (st.position - hip).dot(st.normal) / S.ws.scale;
    const double b = p.force.damping * std::min(1.0, spring / p.damping_force_n);
    const double damping = o.force.dot(st.normal) - spring;
    EXPECT_NEAR(damping, b * v * std::abs(d.dot(st.normal)), 1e-9) << "spring " << spring << " N";
    if (depth_model < 0.01) {
      EXPECT_LT(spring, p.damping_force_n) << "the shallow contact is on the ramp";
    } else {
      EXPECT_GT(spring, p.damping_force_n) << "the deep contact has the full damping";
    }
  }
}

}  // namespace
}  // namespace hdm
