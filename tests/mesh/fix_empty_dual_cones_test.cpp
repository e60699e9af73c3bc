// SPDX-License-Identifier: MIT
// fix_empty_dual_cones() on a crumpled icosphere: every star seen after it (brute-force direction search
// written in the test support), connectivity unchanged, only the crumple's neighbourhood moved.
#include "support/test_models.h"

#include <hdm/core/error.h>
#include <hdm/mesh/fix_empty_dual_cones.h>

#include <gtest/gtest.h>

using namespace hdm;

namespace {

TEST(FixEmptyDualConesTest, ATwistedRingGetsNonEmptyDualConesAndTheRestStays) {
  // Ring of vertex 0 shrunk to 1 % of the edge length and turned by 150 degrees.
  const TriangleMesh in = test::crumpled_icosphere(3, 0.1, 150);
  ASSERT_GT(test::count_empty_cones(in), 0);
  TriangleMesh out = in;
  const DualConeReport r = fix_empty_dual_cones(out);
  EXPECT_GT(r.empty_cones_before, 0);
  EXPECT_EQ(r.empty_cones_after, 0);
  EXPECT_EQ(test::count_empty_cones(out), 0);
  ASSERT_EQ(out.faces, in.faces);
  ASSERT_EQ(out.vertices.size(), in.vertices.size());
  // Only vertices near the crumple move (within 4 rings: 0.6 of the radius on this sphere), and
  // by less than the sphere's radius.
  for (size_t v = 0; v < in.vertices.size(); ++v) {
    const double moved = (out.vertices[v] - in.vertices[v]).norm();
    if ((in.vertices[v] - in.vertices[0]).norm() > 0.6) {
      EXPECT_EQ(moved, 0.0) << v;
    }
    EXPECT_LT(moved, 0.5) << v;
  }
}

TEST(FixEmptyDualConesTest, AMeshWithEveryStarSeenIsLeftAlone) {
  TriangleMesh m = test::icosphere(2, 1.0);
  const TriangleMesh before = m;
  const DualConeReport r = fix_empty_dual_cones(m);
  EXPECT_EQ(r.empty_cones_before, 0);
  EXPECT_EQ(r.moved, 0);
  EXPECT_EQ(m.vertices, before.vertices);
}

TEST(FixEmptyDualConesTest, RefusesBadArguments) {
  TriangleMesh m = test::icosphere(1, 1.0);
  EXPECT_THROW(fix_empty_dual_cones(m, 1.0), InvalidInput);
  EXPECT_THROW(fix_empty_dual_cones(m, 0.02, 0), InvalidInput);
  TriangleMesh empty;
  EXPECT_THROW(fix_empty_dual_cones(empty), InvalidInput);
}

}  // namespace
