// SPDX-License-Identifier: MIT
// α and barycentric recovery: points built from the slab corners map back to their coordinates.
#include "support/test_models.h"

#include <hdm/query/alpha_plane.h>
#include <hdm/query/slab_locator.h>

#include <gtest/gtest.h>

#include <random>

using namespace hdm;

namespace {

using test::point_from_corners;

Vec3 random_barycentric(std::mt19937& rng) {
  std::exponential_distribution<double> e(1.0);
  Vec3 w(e(rng), e(rng), e(rng));
  return w / w.sum();
}

void check_recovery(const SlabModel& m, AlphaSolver solver, double alpha_tol, double bary_tol) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  int tested = 0;
  for (int s = 0; s < m.slab_count(); ++s)
    for (int k = 0; k < 30; ++k, ++tested) {
      const Vec3 w = random_barycentric(rng);
      const double alpha = u(rng);
      SlabCoordinates c;
      ASSERT_TRUE(locate_in_slab(m.geometry[s], point_from_corners(m, s, w, alpha), solver, c)) << "slab " << s;
      EXPECT_NEAR(c.alpha, alpha, alpha_tol);
      EXPECT_LT((c.bary - w).cwiseAbs().maxCoeff(), bary_tol);
    }
  EXPECT_GT(tested, 1000);
}

}  // namespace

TEST(AlphaPlaneTest, NewtonRecoversAlphaAndBarycentrics) {
  check_recovery(test::baked_bunny(0, 16), AlphaSolver::Newton, 1e-9, 1e-8);
}

TEST(AlphaPlaneTest, PaperBisectionRecoversWithinItsResolution) {
  // 15 halvings of [0,1]: |Δα| <= 2^-16 at the bracket midpoint. The barycentric error is |Δα|
  // times how fast the alpha-triangle moves with α, so it is checked on the paper's configuration
  // (150 slabs, about as thick as they are wide); thinner-than-wide slabs magnify it.
  check_recovery(test::baked_bunny(150, 16), AlphaSolver::Bisection, std::ldexp(1.0, -15), 1e-3);
}

TEST(AlphaPlaneTest, PointsOutsideTheSlabAreOutside) {
  const SlabModel& m = test::baked_bunny(0, 16);
  std::mt19937 rng(3);
  for (int s = 0; s < m.slab_count(); ++s) {
    const Vec3 w = random_barycentric(rng);
    SlabCoordinates c;
    for (AlphaSolver solver : {AlphaSolver::Newton, AlphaSolver::Bisection}) {
      EXPECT_FALSE(locate_in_slab(m.geometry[s], point_from_corners(m, s, w, -0.05), solver, c));
      EXPECT_FALSE(locate_in_slab(m.geometry[s], point_from_corners(m, s, w, 1.05), solver, c));
      // Outside across an edge: one barycentric negative.
      const Vec3 out(-0.05, 0.5, 0.55);
      EXPECT_FALSE(locate_in_slab(m.geometry[s], point_from_corners(m, s, out, 0.5), solver, c));
      // Far beside the slab, between the planes of its faces (no box test rejects it first).
      const Vec3 far(-4.0, 2.5, 2.5);
      EXPECT_FALSE(locate_in_slab(m.geometry[s], point_from_corners(m, s, far, 0.5), solver, c));
    }
    EXPECT_FALSE(locate_in_slab(m.geometry[s], Vec3::Constant(std::nan("")), AlphaSolver::Newton, c));
    EXPECT_FALSE(locate_in_slab(m.geometry[s], Vec3(INFINITY, 0, 0), AlphaSolver::Newton, c));
  }
}

TEST(AlphaPlaneTest, SlabBoundsHoldEverySlabPointAndAreSpannedByItsCorners) {
  const SlabModel& m = test::baked_bunny(0, 16);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  for (int s = 0; s < m.slab_count(); ++s) {
    const Aabb box = slab_bounds(m, s);
    for (int k = 0; k < 20; ++k) {
      const Vec3 p = point_from_corners(m, s, random_barycentric(rng), u(rng));
      EXPECT_TRUE(box.contains(p)) << "slab " << s;
    }
    // Each side of the box is reached by a corner: the box is the corners' own, not a looser one.
    for (int a = 0; a < 3; ++a) {
      double lo = INFINITY, hi = -INFINITY;
      for (int32_t v : m.slabs[s])
        for (const Vec3& q : {m.inner[v], m.outer[v]}) lo = std::min(lo, q[a]), hi = std::max(hi, q[a]);
      EXPECT_EQ(box.min[a], lo);
      EXPECT_EQ(box.max[a], hi);
    }
  }
}

TEST(AlphaPlaneTest, LocatorFindsTheSlabThatHoldsAPoint) {
  const SlabModel& m = test::baked_bunny(0, 16);
  const SlabLocator loc(m);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.02, 0.98);
  for (int k = 0; k < 2000; ++k) {
    const int s = int(rng() % m.slab_count());
    const Vec3 w = random_barycentric(rng);
    if (w.minCoeff() < 1e-3) continue;
    const double alpha = u(rng);
    SlabCoordinates c;
    const int hint = k % 3 == 0 ? -1 : int(rng() % m.slab_count());  // cold, or a wrong hint
    ASSERT_EQ(loc.find(point_from_corners(m, s, w, alpha), hint, AlphaSolver::Newton, c), s);
    EXPECT_NEAR(c.alpha, alpha, 1e-9);
  }
}
