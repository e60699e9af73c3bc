// SPDX-License-Identifier: MIT
// The slab locator against a brute-force scan of every slab: the same answer for points in the
// shell (a slab that holds the point) and outside it (none), with and without a hint; its inner
// shell enclosure test against Embree's and an analytic sphere.
#include "support/test_models.h"

#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/query/slab_locator.h>
#include <hdm/slab/bake.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

using namespace hdm;

namespace {

void check_against_brute_force(const SlabModel& m, int points) {
  const SlabLocator loc(m);
  std::mt19937 rng(11);
  std::uniform_int_distribution<int32_t> pick(0, m.samples.count - 1);
  // Offsets along the normal up to 3 % of the diagonal: in the shell, above it and below it.
  std::uniform_real_distribution<double> off(-0.03, 0.03);
  int inside = 0, outside = 0;
  for (int k = 0; k < points; ++k) {
    const int32_t s = pick(rng);
    const Vec3 p = sample_position(m, s) + off(rng) * m.source_diagonal * sample_normal(m, s).cast<double>();
    std::vector<int> holders;
    SlabCoordinates c;
    for (int t = 0; t < m.slab_count(); ++t)
      if (locate_in_slab(m.geometry[t], p, AlphaSolver::Newton, c)) holders.push_back(t);
    const int hint = k % 2 ? -1 : int(rng() % m.slab_count());
    const int found = loc.find(p, hint, AlphaSolver::Newton, c);
    if (holders.empty()) {
      ASSERT_EQ(found, -1) << "point " << k;
      ++outside;
    } else {
      ASSERT_NE(std::find(holders.begin(), holders.end(), found), holders.end()) << "point " << k;
      ++inside;
    }
  }
  EXPECT_GT(inside, points / 10);
  EXPECT_GT(outside, points / 10);
}

}  // namespace

TEST(LocatorTest, AgreesWithAScanOfEverySlab) { check_against_brute_force(test::baked_bunny(0, 16), 3000); }

TEST(LocatorTest, AgreesWithAScanOfEverySlabAt3000Slabs) {
  check_against_brute_force(test::baked_bunny(3000, 4), 1500);
}

// SlabLocator::inside_inner_shell against Embree's winding-number test (ExactMeshQuery::inside) on
// the same inner shell: every point of the slab grid's box and around it, in no slab or not, and
// points on the cells' boundaries and on the shell's vertices' coordinates (ties of the ray test).
namespace {

void check_inner_shell_against_embree(const SlabModel& m, int points) {
  const SlabLocator loc(m);
  const ExactMeshQuery core(TriangleMesh{m.inner, m.slabs});
  ASSERT_TRUE(core.closed());
  Aabb box;
  for (const Vec3& v : m.outer) box.extend(v);
  const Vec3 lo = box.min - 0.05 * (box.max - box.min), hi = box.max + 0.05 * (box.max - box.min);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  std::uniform_int_distribution<int> vertex(0, int(m.inner.size()) - 1);
  int enclosed = 0, mismatches = 0;
  for (int k = 0; k < points; ++k) {
    Vec3 p(lo.x() + u(rng) * (hi.x() - lo.x()), lo.y() + u(rng) * (hi.y() - lo.y()),
           lo.z() + u(rng) * (hi.z() - lo.z()));
    if (k % 8 == 0) {  // the ray passes exactly through an inner-shell vertex (a tie for the 2D test)
      const Vec3& v = m.inner[vertex(rng)];
      p.y() = v.y(), p.z() = v.z();
    }
    const bool want = core.inside(p);
    enclosed += want;
    if (loc.inside_inner_shell(p) != want) ++mismatches;
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(enclosed, points / 20);
  EXPECT_LT(enclosed, points - points / 20);
}

}  // namespace

TEST(LocatorTest, InsideInnerShellAgreesWithEmbreeWinding) {
  check_inner_shell_against_embree(test::baked_bunny(0, 16), 20000);
}

TEST(LocatorTest, InsideInnerShellAgreesWithEmbreeWindingAt3000Slabs) {
  check_inner_shell_against_embree(test::baked_bunny(3000, 4), 20000);
}

TEST(LocatorTest, InsideInnerShellOfASphereIsTheBallInsideIt) {
  BakeOptions o;
  o.slabs = 200;
  o.grid_n = 4;
  const SlabModel m = bake_slabs(test::icosphere(3, 1.0), "sphere", o);
  const SlabLocator loc(m);
  // Analytic bounds of the inner shell: the inner corners' radii (the facets lie within a few
  // per cent below them).
  double r_min = INFINITY, r_max = 0;
  for (const Vec3& v : m.inner) r_min = std::min(r_min, v.norm()), r_max = std::max(r_max, v.norm());
  std::mt19937 rng(9);
  std::normal_distribution<double> g(0, 1);
  std::uniform_real_distribution<double> r(0, 1.6);
  int checked = 0;
  for (int k = 0; k < 20000; ++k) {
    const Vec3 d = Vec3(g(rng), g(rng), g(rng)).normalized();
    const double radius = r(rng);
    if (radius > 0.9 * r_min && radius < r_max * 1.0001) continue;  // the facets' band
    EXPECT_EQ(loc.inside_inner_shell(radius * d), radius < r_min) << radius;
    ++checked;
  }
  EXPECT_GT(checked, 10000);
  EXPECT_FALSE(loc.inside_inner_shell(Vec3(NAN, 0, 0)));
}
