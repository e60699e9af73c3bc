// SPDX-License-Identifier: MIT
// Sphere proxy tests against analytic geometry: the unit sphere, and a block with a slot whose
// walls, floor and edges are planes (Embree's exact distance on the input mesh is the reference).
#include "haptics/haptics_fixtures.h"
#include "support/flat_sheet.h"

#include <hdm/haptics/sphere_proxy.h>
#include <hdm/pipeline/bake_input.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <vector>

namespace hdm {
namespace {

using test::angle_deg;

using test::sphere;
using test::sphere_params;
using test::voxel_surface;

// A block [-1,1]² × [-1,0] with a slot |x| < width/2 of depth 0.4 along y, from cubes of 0.1.
TriangleMesh slot_block(int width_cells) {
  const int nx = 20, half = width_cells / 2;
  return voxel_surface(nx, 20, 10, 0.1, Vec3(-1, -1, -1),
                       [&](int i, int, int k) { return !(k >= 6 && i >= nx / 2 - half && i < nx / 2 + half); });
}

struct Slot {
  explicit Slot(int width_cells) : baked(slot_block(width_cells), "slot block", 500, 8) {
    ws.scale = 10;  // 10 model units per metre: the block is 0.2 m wide at the device
  }
  test::BakedMesh baked;
  Workspace ws;
};

SphereProxyParams ball(double r) {
  SphereProxyParams p;
  p.proxy = sphere_params();
  p.radius = r;
  return p;
}

// The ball's penetration into the input: r minus the exact distance from its centre to the mesh
// (the input's own closest point, Embree), or 0.
double penetration(const ExactMeshQuery& input, const Vec3& centre, double r) {
  return std::max(0.0, r - input.closest_point(centre).distance);
}

// Pressed 0.5 deep into the middle of a slot narrower than the ball (0.4 wide, r = 0.3), the ball
// rests on the slot's two edges: its centre at sqrt(r² − 0.2²) above the top, never in the slot.
TEST(SphereProxy, DoesNotEnterASlotNarrowerThanTheBall) {
  const Slot slot(4);
  const double r = 0.3;
  const SphereProxyParams p = ball(r);
  SphereProxyState st;
  double worst = 0;
  for (int k = 0; k <= 400; ++k) {
    const double z = 0.6 - 1.1 * std::min(1.0, k / 300.0);  // from 0.3 above the ball's rest to 0.5 deep
    const Vec3 hip(0.0, 0.05, z);
    sphere_proxy_step(slot.baked.model, slot.baked.locator, slot.ws, slot.ws.to_device(hip), Vec3::Zero(), p, st);
    worst = std::max(worst, penetration(slot.baked.reference, st.center, r));
  }
  ASSERT_TRUE(st.contact);
  EXPECT_GT(st.center.z(), 0.0) << "the ball entered the slot";
  EXPECT_NEAR(st.center.z(), std::sqrt(r * r - 0.2 * 0.2), 0.02 * r);
  EXPECT_NEAR(st.center.x(), 0.0, 0.02 * r) << "two contacts hold the ball in the middle";
  EXPECT_LT(worst, 0.02 * r) << "penetration into the walls and edges";
}

// The same press into a slot wider than the ball (0.8 wide, r = 0.3): the ball goes down to the
// floor (0.4 deep), its centre r above it.
TEST(SphereProxy, ReachesTheFloorOfASlotWiderThanTheBall) {
  const Slot slot(8);
  const double r = 0.3;
  const SphereProxyParams p = ball(r);
  SphereProxyState st;
  double worst = 0;
  for (int k = 0; k <= 600; ++k) {
    const double z = 0.6 - 1.3 * std::min(1.0, k / 400.0);
    sphere_proxy_step(slot.baked.model, slot.baked.locator, slot.ws, slot.ws.to_device(Vec3(0, 0.05, z)), Vec3::Zero(),
                      p, st);
    worst = std::max(worst, penetration(slot.baked.reference, st.center, r));
  }
  ASSERT_TRUE(st.contact);
  EXPECT_NEAR(st.center.z(), -0.4 + r, 0.02 * r);
  EXPECT_LT(worst, 0.02 * r);
}

// Sliding across a slot narrower than the ball, the hand 0.15 below the top (below the height
// at which the ball rests on the slot's edges): the ball crosses the slot on its two edges and never
// drops in; while it rests on the flat top, the frictionless force is vertical.
TEST(SphereProxy, SlidesAcrossANarrowSlotOnItsEdges) {
  const Slot slot(4);
  const double r = 0.3;
  const SphereProxyParams p = ball(r);
  SphereProxyState st;
  double worst = 0, lowest = INFINITY, worst_flat_angle = 0;
  for (int k = 0; k <= 1200; ++k) {
    const double x = -0.8 + 1.6 * k / 1200.0;
    const double z = k < 100 ? r + 0.2 - 0.35 * k / 100.0 : r - 0.15;  // down, then 0.15 deep
    const ProxyOutput out = sphere_proxy_step(slot.baked.model, slot.baked.locator, slot.ws,
                                              slot.ws.to_device(Vec3(x, 0, z)), Vec3::Zero(), p, st);
    if (k < 100) continue;
    ASSERT_TRUE(st.contact) << "tick " << k;
    worst = std::max(worst, penetration(slot.baked.reference, st.center, r));
    lowest = std::min(lowest, st.center.z());
    if (std::abs(st.center.x()) > 0.2 + r + 0.05 && std::abs(st.center.x()) < 0.7)
      worst_flat_angle = std::max(worst_flat_angle, angle_deg(out.force, Vec3::UnitZ()));
  }
  EXPECT_GT(lowest, std::sqrt(r * r - 0.2 * 0.2) - 0.02 * r) << "the ball dropped into the slot";
  EXPECT_LT(worst, 0.02 * r);
  EXPECT_LT(worst_flat_angle, 2.0) << "force direction on the flat top [deg]";
}

// What a ball of radius r felt rolling over the block's outer edge (x = 1, z = 0) on the path at
// @p y, the hand 0.05 inside the ball's path: down onto the top, along it to above the edge, then
// around the edge from up to sideways; measured from tick 150 on.
struct EdgeRoll {
  double deepest = 0;                              ///< largest penetration into the input
  double widest = 0;                               ///< largest | distance from the centre to the input − r |
  double steepest = 0;                             ///< largest force step between ticks, fraction of the maximum force
  Vec3 first = Vec3::Zero(), last = Vec3::Zero();  ///< the first and last forces
  int lost = -1;                                   ///< the first tick out of contact, or -1
};

EdgeRoll roll_over_edge(const SlabModel& model, const SlabLocator& locator, const Workspace& ws,
                        const ExactMeshQuery& input, double r, double y) {
  const SphereProxyParams p = ball(r);
  SphereProxyState st;
  EdgeRoll e;
  Vec3 prev = Vec3::Zero();
  const double d = r - 0.05;  // the hand's distance from the edge
  const int n = 1500;
  for (int k = 0; k <= n; ++k) {
    Vec3 hip;
    if (k < 100)  // down onto the top
      hip = Vec3(0.8, y, d + 0.2 * (1 - k / 100.0));
    else if (k < 200)  // along the top to above the edge
      hip = Vec3(0.8 + 0.2 * (k - 100) / 100.0, y, d);
    else {  // around the edge, from up to sideways
      const double a = 0.5 * std::numbers::pi * (k - 200) / (n - 200);
      hip = Vec3(1, y, 0) + d * Vec3(std::sin(a), 0, std::cos(a));
    }
    const ProxyOutput out = sphere_proxy_step(model, locator, ws, ws.to_device(hip), Vec3::Zero(), p, st);
    if (k < 150) continue;
    if (!st.contact) {
      e.lost = k;
      return e;
    }
    e.deepest = std::max(e.deepest, penetration(input, st.center, r));
    e.widest = std::max(e.widest, std::abs(input.closest_point(st.center).distance - r));
    if (prev.norm() > 0) e.steepest = std::max(e.steepest, (out.force - prev).norm() / p.proxy.force.max_force);
    if (e.first.norm() == 0) e.first = out.force;
    prev = e.last = out.force;
  }
  return e;
}

// Rolling over the block's outer edge on the path at y = 0.05: the ball turns around the edge
// with its centre r from it, no deeper into the input than 2 % of r, the force turning from up
// (+z) to sideways (+x) without a step above 2 % of the maximum force.
TEST(SphereProxy, RollsOverAConvexEdgeWithAContinuousForce) {
  const Slot slot(4);
  const double r = 0.3;
  const EdgeRoll e = roll_over_edge(slot.baked.model, slot.baked.locator, slot.ws, slot.baked.reference, r, 0.05);
  ASSERT_EQ(e.lost, -1) << "tick " << e.lost;
  EXPECT_LT(e.deepest, 0.02 * r);
  EXPECT_LT(e.widest, 0.05 * r) << "the ball leaves the surface";
  EXPECT_LT(angle_deg(e.first, Vec3::UnitZ()), 10.0);
  EXPECT_LT(angle_deg(e.last, Vec3::UnitX()), 10.0);
  EXPECT_LT(e.steepest, 0.02) << "largest force step between ticks, fraction of max force";
}

// The same roll on paths across the whole edge, on the slot block as `hdm bake` makes it (the
// default bake to the fidelity bound, bake_input()), so the edge meets slab edges and grid
// lines at every place along it. Beside the edge the force-shading normals blend the top and the
// side within a grid spacing; the ball must not follow that blend (it rounds the edge by its own
// radius), nor sink into the top or snap back: on every path, no deeper into the input than 2 % of
// r and no force step above 2 % of the maximum force. (Following the blend stepped 3.4-9.2 %.)
TEST(SphereProxy, RollsOverAConvexEdgeAnywhereAlongIt) {
  const TriangleMesh block = slot_block(4);
  const SlabModel model = bake_input(block, "slot block");
  const SlabLocator locator(model);
  const ExactMeshQuery input(block);
  Workspace ws;
  ws.scale = 10;
  const double r = 0.3;
  double steepest = 0, deepest = 0;
  for (int path = 0; path < 12; ++path) {
    const double y = -0.85 + 0.1537 * path;  // 12 paths at offsets unrelated to the cubes and slabs
    const EdgeRoll e = roll_over_edge(model, locator, ws, input, r, y);
    ASSERT_EQ(e.lost, -1) << "y " << y << ", tick " << e.lost;
    EXPECT_LT(e.deepest, 0.02 * r) << "y " << y;
    EXPECT_LT(e.steepest, 0.02) << "y " << y << ": largest force step between ticks, fraction of max force";
    steepest = std::max(steepest, e.steepest), deepest = std::max(deepest, e.deepest);
  }
  std::printf("%d slabs: largest step %.2f %% of the maximum force, deepest %.2f %% of r\n", model.slab_count(),
              100 * steepest, 100 * deepest / r);
}

// Rolling over the unit sphere 0.02 deep (r = 0.1) across many slabs: the ball stays r from the
// displaced surface (Embree's exact distance to the model's own triangles), the frictionless
// force stays radial (the analytic normal) and it never steps by more than 2 % of the device's
// maximum force from one tick to the next.
TEST(SphereProxy, RollsOnTheSphereWithARadialForce) {
  const auto& S = sphere();
  TriangleMesh displaced;
  displaced_surface(S.model, displaced.vertices, displaced.faces);
  const ExactMeshQuery surface(displaced);
  const double r = 0.1;
  const SphereProxyParams p = ball(r);
  SphereProxyState st;
  double worst_gap = 0, worst_step = 0;
  std::vector<double> angles;
  Vec3 prev = Vec3::Zero();
  const int n = 3000;
  for (int k = 0; k < n; ++k) {
    const double a = 0.5 * std::numbers::pi * k / n;
    const double depth = k < 100 ? -0.05 + 0.07 * k / 100.0 : 0.02;
    const Vec3 hip = Vec3(std::sin(a), 0.3 * std::sin(2 * a), std::cos(a)).normalized() * (1 + r - depth);
    const ProxyOutput out = sphere_proxy_step(S.model, *S.locator, S.ws, S.ws.to_device(hip), Vec3::Zero(), p, st);
    if (k < 100) continue;
    ASSERT_TRUE(st.contact) << "tick " << k;
    worst_gap = std::max(worst_gap, std::abs(surface.closest_point(st.center).distance - r));
    angles.push_back(angle_deg(out.force, st.center));
    if (k > 100) worst_step = std::max(worst_step, (out.force - prev).norm() / p.proxy.force.max_force);
    prev = out.force;
  }
  EXPECT_LT(worst_gap, 0.01 * r) << "distance from the centre to the displaced surface, minus r";
  std::sort(angles.begin(), angles.end());
  EXPECT_LT(angles[angles.size() * 95 / 100], 3.0) << "p95 force direction vs the analytic normal [deg]";
  EXPECT_LT(angles.back(), 6.0);
  EXPECT_LT(worst_step, 0.02) << "largest force step between ticks, fraction of max force";
}

// A hand at rest on the flat top with friction holds the ball (static friction): a sideways pull
// of a fifth of the press (μs = 0.5) leaves it where it was, with a tangential force; a pull of
// twice the press makes it slide.
TEST(SphereProxy, StaticFrictionHoldsTheBall) {
  Slot slot(4);
  slot.baked.model.friction_static.assign(slot.baked.model.friction_static.size(), 0.5f);
  slot.baked.model.friction_dynamic.assign(slot.baked.model.friction_dynamic.size(), 0.3f);
  const double r = 0.3;
  SphereProxyParams p = ball(r);
  p.proxy.friction_scale = 1;
  SphereProxyState st;
  const Vec3 start(0.6, 0, r - 0.02);  // 0.02 deep: 2 N at k = 1000 N/m and 10 model units per metre
  auto tick = [&](const Vec3& hip) {
    return sphere_proxy_step(slot.baked.model, slot.baked.locator, slot.ws, slot.ws.to_device(hip), Vec3::Zero(), p,
                             st);
  };
  for (int k = 0; k < 100; ++k) tick(start + Vec3(0, 0, 0.2 * (1 - k / 99.0)));
  ASSERT_TRUE(st.contact);
  const Vec3 held = st.center;
  const ProxyOutput out = tick(start + Vec3(0.004, 0, 0));
  EXPECT_EQ(out.status, ProxyStatus::Stuck);
  EXPECT_LT((st.center - held).norm(), 1e-9);
  EXPECT_NEAR(out.friction_force / out.normal_force, 0.2, 0.02);
  for (int k = 1; k <= 20; ++k) tick(start + Vec3(0.004 + 0.002 * k, 0, 0));
  EXPECT_EQ(tick(start + Vec3(0.05, 0, 0)).status, ProxyStatus::Sliding);
  EXPECT_GT((st.center - held).norm(), 0.01);
}

// A hand that jumps from 0.5 above the top to 0.5 inside the block in one tick: the free-space
// sweep catches the ball on the top, where it stays (r above it), pushing up.
TEST(SphereProxy, CatchesAFastEntry) {
  const Slot slot(4);
  const double r = 0.3;
  const SphereProxyParams p = ball(r);
  SphereProxyState st;
  auto tick = [&](const Vec3& hip) {
    return sphere_proxy_step(slot.baked.model, slot.baked.locator, slot.ws, slot.ws.to_device(hip), Vec3::Zero(), p,
                             st);
  };
  tick(Vec3(0.6, 0.05, r + 0.5));
  EXPECT_FALSE(st.contact);
  ProxyOutput out;
  for (int k = 0; k < 20; ++k) out = tick(Vec3(0.6, 0.05, -0.5));
  ASSERT_TRUE(st.contact);
  EXPECT_NEAR(st.center.z(), r, 0.02 * r);
  EXPECT_LT(angle_deg(out.force, Vec3::UnitZ()), 2.0);
}

// A flat sheet's normals are exactly +z (its grid lies in z = 0), so a hand pushed straight down
// pulls the ball along the normal with no tangential part at all: static friction must not hold
// the ball where the sweep last found it free, above the surface, or the next tick finds no touch
// and lets it fall through. The ball rests on the sheet, r above it, from the first contact tick.
TEST(SphereProxy, EntersAFlatSheetStraightAlongItsNormal) {
  const SlabModel sheet = test::flat_sheet();
  const SlabLocator locator(sheet);
  Workspace ws;
  ws.scale = test::kSheetUnits;
  const double r = 2;  // [mm]
  SphereProxyParams p = ball(r);
  for (double mu : {0.0, 0.5}) {
    p.proxy.friction_scale = mu > 0 ? 1 : 0;
    SphereProxyState st;
    auto tick = [&](const Vec3& hip) {
      return sphere_proxy_step(sheet, locator, ws, ws.to_device(hip), Vec3::Zero(), p, st);
    };
    tick(Vec3(1.3, 0.7, r + 6));
    ASSERT_FALSE(st.contact);
    for (int k = 0; k < 10; ++k) {
      const ProxyOutput out = tick(Vec3(1.3, 0.7, -0.5));
      ASSERT_TRUE(st.contact) << "tick " << k << ", friction scale " << p.proxy.friction_scale;
      EXPECT_NEAR(st.center.z(), test::sheet_surface_z() + r, 1e-6 * r) << "tick " << k;
      EXPECT_LT(angle_deg(out.force, Vec3::UnitZ()), 1e-3) << "tick " << k;
    }
  }
}

TEST(SphereProxy, BadInputGivesZeroForceAndKeepsState) {
  const auto& S = sphere();
  SphereProxyParams p = ball(0.1);
  SphereProxyState st;
  sphere_proxy_step(S.model, *S.locator, S.ws, S.ws.to_device(Vec3(0, 0, 1.05)), Vec3::Zero(), p, st);
  ASSERT_TRUE(st.contact);
  const Vec3 centre = st.center;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const Vec3& hip : {Vec3(nan, 0, 0), Vec3(0, INFINITY, 0), Vec3(10, 0, 0)}) {
    const ProxyOutput out = sphere_proxy_step(S.model, *S.locator, S.ws, hip, Vec3::Zero(), p, st);
    EXPECT_EQ(out.status, ProxyStatus::BadInput);
    EXPECT_EQ(out.force, Vec3::Zero());
    EXPECT_EQ(st.center, centre);
  }
  p.samples = kMaxBallSamples + 1;
  const ProxyOutput out =
      sphere_proxy_step(S.model, *S.locator, S.ws, S.ws.to_device(Vec3(0, 0, 1.05)), Vec3::Zero(), p, st);
  EXPECT_EQ(out.status, ProxyStatus::BadInput);
  EXPECT_EQ(out.force, Vec3::Zero());
}

}  // namespace
}  // namespace hdm
