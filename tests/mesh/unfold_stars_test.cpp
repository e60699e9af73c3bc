// SPDX-License-Identifier: MIT
// unfold_stars() on a crumpled icosphere: every star seen after it (brute-force direction search
// written in the test support), connectivity unchanged, only the crumple's neighbourhood moved.
#include "support/test_models.h"

#include <hdm/core/error.h>
#include <hdm/mesh/unfold_stars.h>

#include <gtest/gtest.h>

using namespace hdm;

namespace {

TEST(UnfoldStarsTest, ATwistedRingIsUnfoldedAndTheRestStays) {
  // Ring of vertex 0 shrunk to 1 % of the edge length and turned by 150 degrees.
  const TriangleMesh in = test::crumpled_icosphere(3, 0.1, 150);
  ASSERT_GT(test::count_folded_stars(in), 0);
  TriangleMesh out = in;
  const UnfoldReport r = unfold_stars(out);
  EXPECT_GT(r.folded_before, 0);
  EXPECT_EQ(r.folded_after, 0);
  EXPECT_EQ(test::count_folded_stars(out), 0);
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

TEST(UnfoldStarsTest, AMeshWithEveryStarSeenIsLeftAlone) {
  TriangleMesh m = test::icosphere(2, 1.0);
  const TriangleMesh before = m;
  const UnfoldReport r = unfold_stars(m);
  EXPECT_EQ(r.folded_before, 0);
  EXPECT_EQ(r.moved, 0);
  EXPECT_EQ(m.vertices, before.vertices);
}

TEST(UnfoldStarsTest, RefusesBadArguments) {
  TriangleMesh m = test::icosphere(1, 1.0);
  EXPECT_THROW(unfold_stars(m, 1.0), InvalidInput);
  EXPECT_THROW(unfold_stars(m, 0.02, 0), InvalidInput);
  TriangleMesh empty;
  EXPECT_THROW(unfold_stars(empty), InvalidInput);
}

}  // namespace
