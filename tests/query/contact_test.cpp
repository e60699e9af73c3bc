// SPDX-License-Identifier: MIT
// Contact against the exact input: inside/outside and penetration depth versus Embree on the mesh.
#include "support/test_models.h"

#include <algorithm>
#include <hdm/analysis/fidelity.h>
#include <hdm/query/slab_query.h>

#include <gtest/gtest.h>

using namespace hdm;

TEST(ContactTest, InsideOutsideAndDepthAgreeWithTheExactInput) {
  const SlabModel& m = test::baked_bunny(1200, 8);
  const ExactMeshQuery exact(test::bunny());
  const Fidelity f = measure_fidelity(m, exact);
  // Points within ±0.5% of the diagonal of the input surface (inside the shell's thickness).
  const ContactAccuracy c = measure_contact(m, exact, 20000, 42, 0.5);
  EXPECT_GE(c.agreement, 0.99);
  EXPECT_LE(c.depth_rms_pct, std::max(f.max_pct, f.max_back_pct));
}

TEST(ContactTest, NonFinitePointsGiveNoContact) {
  const SlabModel& m = test::baked_bunny(0, 16);
  const SlabLocator loc(m);
  QueryCache cache;
  for (const Vec3& p : {Vec3(std::nan(""), 0, 0), Vec3(INFINITY, 0, 0), Vec3(1e300, -1e300, 0)}) {
    const Contact c = query(m, loc, p, cache);
    EXPECT_FALSE(c.in_shell());
    EXPECT_TRUE(std::isfinite(c.depth));
  }
}

TEST(ContactTest, SurfacePointLiesOnTheProjectionLineAndIsNotPenetrating) {
  const SlabModel& m = test::baked_bunny(0, 16);
  const SlabLocator loc(m);
  QueryCache cache;
  int hits = 0;
  for (int s = 0; s < m.samples.count; s += 37) {
    // Just below the sample's surface point along its projection line.
    Vec3 p0, p1;
    projection_line(m, m.samples.home(s).slab, m.samples.home(s).index, p0, p1);
    const double d = m.displacement[s];
    if (d < 0.05) continue;
    const Contact c = query(m, loc, p0 + (d - 0.02) * (p1 - p0), cache);
    ASSERT_TRUE(c.penetrating());
    // Depth is the distance to the surface's tangent plane at the surface point: 0.02·|D| along
    // the line, projected on the normal (floored at 0.1 of the line, see Contact::depth).
    const Vec3 ray = p1 - p0;
    EXPECT_NEAR(c.depth, 0.02 * std::max(ray.dot(c.normal), 0.1 * ray.norm()), 1e-6 * m.source_diagonal);
    EXPECT_LE(c.depth, 0.02 * ray.norm() * (1 + 1e-9));
    const Contact on = query(m, loc, c.surface_point, cache);
    EXPECT_NEAR(on.depth, 0.0, 1e-9 * m.source_diagonal);
    ++hits;
  }
  EXPECT_GT(hits, 500);
}
