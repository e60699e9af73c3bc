// SPDX-License-Identifier: MIT
// The CGAL closest-point baseline against brute force over every triangle.
#include "support/brute_force.h"
#include "support/test_models.h"

#include <hdm/analysis/cgal_closest_point.h>
#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/core/error.h>

#include <gtest/gtest.h>

#include <random>

using namespace hdm;

TEST(CgalClosestPointTest, MatchesBruteForce) {
  TriangleMesh m = test::icosphere(3, 1.0);
  for (Vec3& v : m.vertices) v.x() *= 1.7;  // an ellipsoid, so closest points are not radial
  const CgalClosestPoint cgal(m);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-2, 2);
  for (int k = 0; k < 500; ++k) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const double best = test::brute_distance(p, m);
    EXPECT_NEAR((cgal.closest_point(p) - p).norm(), best, 1e-9) << p.transpose();
  }
}

TEST(CgalClosestPointTest, RefusesAnEmptyMesh) { EXPECT_THROW(CgalClosestPoint(TriangleMesh{}), InvalidInput); }
