// SPDX-License-Identifier: MIT
// Error-bounded baking: the returned model meets the bound by a brute-force measurement of its own,
// the slab count only grows, and an unreachable bound stops at the cap and says so.
#include "support/test_models.h"

#include <hdm/analysis/bake_to_tolerance.h>
#include <hdm/core/error.h>

#include <gtest/gtest.h>

#include <cmath>

using namespace hdm;

namespace {

// An ellipsoid with bumps: coarse slabs miss the bumps, finer ones follow them.
TriangleMesh bumpy_ellipsoid() {
  TriangleMesh m = test::icosphere(4, 1.0);
  for (Vec3& v : m.vertices) {
    const Vec3 u = v.normalized();
    v = u * (1 + 0.05 * std::sin(5 * u.x()) * std::sin(5 * u.y()) * std::sin(5 * u.z()));
    v.x() *= 1.5;
  }
  return m;
}

double brute_distance(const Vec3& p, const TriangleMesh& m) {
  double best = 1e300;
  for (const Tri& t : m.faces)
    best = std::min(best, (closest_point_on_triangle(p, m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]) - p).norm());
  return best;
}

// Largest distance both ways (samples of the reconstruction to the input, input vertices to the
// reconstruction), % of the diagonal, by brute force.
double brute_max_pct(const SlabModel& m, const TriangleMesh& input) {
  TriangleMesh recon;
  displaced_surface(m, recon.vertices, recon.faces);
  double mx = 0;
  for (const Vec3& p : recon.vertices) mx = std::max(mx, brute_distance(p, input));
  for (const Vec3& p : input.vertices) mx = std::max(mx, brute_distance(p, recon));
  return 100 * mx / bounds(input).diagonal();
}

}  // namespace

TEST(BakeToToleranceTest, refines_until_the_bound_holds_by_brute_force) {
  const TriangleMesh input = bumpy_ellipsoid();
  const ExactMeshQuery exact(input);
  BakeOptions o;
  o.slabs = 20;
  o.grid_n = 4;
  Tolerance t;
  t.max_pct = 0.3;
  std::vector<ToleranceRound> rounds;
  const SlabModel m = bake_to_tolerance(exact, "bumpy", o, t, &rounds);
  ASSERT_GE(rounds.size(), 2u);  // 20 slabs cannot hold the bumps
  EXPECT_FALSE(rounds.front().met);
  EXPECT_TRUE(rounds.back().met);
  for (size_t k = 1; k < rounds.size(); ++k) EXPECT_GT(rounds[k].slabs, rounds[k - 1].slabs);
  EXPECT_EQ(m.slab_count(), rounds.back().slabs);
  EXPECT_LE(brute_max_pct(m, input), 0.3 + 1e-4);  // vertices: a subset of the points the bound covers
  EXPECT_GT(brute_max_pct(bake_slabs(input, "bumpy", o), input), 0.3);
}

TEST(BakeToToleranceTest, an_unreachable_bound_stops_at_the_cap) {
  const TriangleMesh input = bumpy_ellipsoid();
  BakeOptions o;
  o.slabs = 20;
  o.grid_n = 4;
  Tolerance t;
  t.rms_pct = 1e-9;
  t.max_slabs = 120;
  std::vector<ToleranceRound> rounds;
  const SlabModel m = bake_to_tolerance(ExactMeshQuery(input), "bumpy", o, t, &rounds);
  EXPECT_FALSE(rounds.back().met);
  EXPECT_LE(m.slab_count(), 120);
  EXPECT_LE(int(rounds.size()), t.max_rounds);
}

TEST(BakeToToleranceTest, refuses_bounds_that_are_not_positive) {
  const TriangleMesh input = test::icosphere(2, 1.0);
  Tolerance t;
  t.max_pct = 0;
  EXPECT_THROW(bake_to_tolerance(ExactMeshQuery(input), "sphere", BakeOptions{}, t), InvalidInput);
  t.max_pct = NAN;
  EXPECT_THROW(bake_to_tolerance(ExactMeshQuery(input), "sphere", BakeOptions{}, t), InvalidInput);
}
