// SPDX-License-Identifier: MIT
// Continuity: surface height, depth, force and normal are continuous across slab edges and corners.
#include "support/test_models.h"

#include <hdm/haptics/force.h>
#include <hdm/query/slab_query.h>

#include <gtest/gtest.h>

#include <numbers>
#include <random>

using namespace hdm;

namespace {

struct SweepResult {
  double surface_ratio = 0;  ///< max |Δ surface point| / |Δ point|
  double depth_ratio = 0;    ///< max |Δ depth| / |Δ point|
  double force_step = 0;     ///< max |Δ force| [N] between steps
  double normal_step_deg = 0;
  int slab_changes = 0;
  bool stayed_in_shell = true;
};

SweepResult sweep(const SlabModel& m, const SlabLocator& loc, const Vec3& a, const Vec3& b, int steps) {
  SweepResult r;
  QueryCache cache;
  Contact prev;
  const Workspace ws = fit_workspace([&] {
    Aabb box;
    for (const Vec3& v : m.inner) box.extend(v);
    return box;
  }());
  ForceParams fp;
  fp.max_force = 1e9;  // measure the unclamped force
  Vec3 prev_f = Vec3::Zero();
  const double dp = (b - a).norm() / steps;
  for (int k = 0; k <= steps; ++k) {
    const Contact c = query(m, loc, a + (b - a) * (double(k) / steps), cache);
    if (!c.in_shell()) {
      r.stayed_in_shell = false;
      return r;
    }
    const Vec3 f = penalty_force(c, Vec3::Zero(), fp, ws).force;
    if (k > 0) {
      r.surface_ratio = std::max(r.surface_ratio, (c.surface_point - prev.surface_point).norm() / dp);
      r.depth_ratio = std::max(r.depth_ratio, std::abs(c.depth - prev.depth) / dp);
      r.force_step = std::max(r.force_step, (f - prev_f).norm());
      const double cosang = std::clamp(c.normal.dot(prev.normal), -1.0, 1.0);
      r.normal_step_deg = std::max(r.normal_step_deg, std::acos(cosang) * 180 / std::numbers::pi);
      r.slab_changes += c.slab != prev.slab;
    }
    prev = c;
    prev_f = f;
  }
  return r;
}

void expect_continuous(const SweepResult& r, double step_m_force_bound) {
  // A Lipschitz bound far above the surface's slopes but far below a jump (a jump of even 0.1% of
  // the diagonal over a step of 1e-5 of the diagonal is a ratio of 100).
  EXPECT_LT(r.surface_ratio, 30);
  EXPECT_LT(r.depth_ratio, 30);
  EXPECT_LT(r.normal_step_deg, 10);
  EXPECT_LT(r.force_step, step_m_force_bound);
}

}  // namespace

TEST(ContinuityTest, AcrossSlabEdges) {
  const SlabModel& m = test::baked_bunny(0, 16);
  const SlabLocator loc(m);
  std::mt19937 rng(1);
  int swept = 0, crossings = 0;
  for (int s = 0; s < m.slab_count() && swept < 150; s += 2) {
    const Vec3 centroid(1 / 3.0, 1 / 3.0, 1 / 3.0);
    for (int e = 0; e < 3; ++e) {
      const int nb = m.edge_neighbour[s][e];
      if (nb < 0) continue;
      // A point on edge e (between corners e and e+1) at a random position, at half the depth of
      // the material there, then a segment through it from inside slab s towards the neighbour.
      const double t = std::uniform_real_distribution<double>(0.2, 0.8)(rng);
      Vec3 w_edge = Vec3::Zero();
      w_edge[e] = 1 - t;
      w_edge[(e + 1) % 3] = t;
      SlabCoordinates c{0.5, w_edge};
      Contact at;
      evaluate_surface(m, s, c, at);
      const double alpha = 0.6 * at.delta;
      if (alpha < 0.05) continue;
      const Vec3 on_edge = test::point_from_corners(m, s, w_edge, alpha);
      const Vec3 inside = test::point_from_corners(m, s, w_edge + 0.08 * (centroid - w_edge), alpha);
      const SweepResult r = sweep(m, loc, inside, 2 * on_edge - inside, 2000);
      if (!r.stayed_in_shell) continue;
      ++swept;
      crossings += r.slab_changes;
      expect_continuous(r, 0.05);
    }
  }
  EXPECT_GT(swept, 100);
  EXPECT_GT(crossings, 100);
}

TEST(ContinuityTest, AcrossSlabCorners) {
  const SlabModel& m = test::baked_bunny(0, 16);
  const SlabLocator loc(m);
  int swept = 0;
  for (int s = 0; s < m.slab_count() && swept < 100; s += 3) {
    for (int k = 0; k < 3; ++k) {
      Vec3 w_corner = Vec3::Zero();
      w_corner[k] = 1;
      SlabCoordinates c{0.5, w_corner};
      Contact at;
      evaluate_surface(m, s, c, at);
      const double alpha = 0.6 * at.delta;
      if (alpha < 0.05) continue;
      const Vec3 corner = test::point_from_corners(m, s, w_corner, alpha);
      const Vec3 inside = test::point_from_corners(m, s, 0.9 * w_corner + Vec3::Constant(0.1 / 3), alpha);
      const SweepResult r = sweep(m, loc, inside, 2 * corner - inside, 2000);
      if (!r.stayed_in_shell) continue;
      ++swept;
      EXPECT_GE(r.slab_changes, 1);
      expect_continuous(r, 0.05);
    }
  }
  EXPECT_GT(swept, 50);
}
