// SPDX-License-Identifier: MIT
// The reference itself: Embree closest point and inside test against brute force and a sphere.
#include "support/test_models.h"

#include <hdm/mesh/exact_mesh_query.h>

#include <gtest/gtest.h>

#include <random>

using namespace hdm;

TEST(ExactMeshQueryTest, closest_point_matches_brute_force) {
  const TriangleMesh m = test::icosphere(3, 2.0, Vec3(1, -1, 0.5));
  const ExactMeshQuery q(m);
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-4, 4);
  for (int k = 0; k < 300; ++k) {
    const Vec3 p(u(rng), u(rng), u(rng));
    double best = 1e300;
    for (const Tri& t : m.faces)
      best = std::min(best,
                      (closest_point_on_triangle(p, m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]) - p).norm());
    EXPECT_NEAR(q.closest_point(p).distance, best, 1e-9);
    // and close to the analytic sphere distance (chord error of the tessellation)
    EXPECT_NEAR(best, std::abs((p - Vec3(1, -1, 0.5)).norm() - 2.0), 0.02);
  }
}

TEST(ExactMeshQueryTest, inside_matches_the_sphere) {
  const Vec3 c(1, -1, 0.5);
  const ExactMeshQuery q(test::icosphere(3, 2.0, c));
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(-4, 4);
  for (int k = 0; k < 500; ++k) {
    const Vec3 p = c + Vec3(u(rng), u(rng), u(rng));
    const double r = (p - c).norm();
    if (std::abs(r - 2.0) < 0.03) continue;  // tessellation band
    EXPECT_EQ(q.inside(p), r < 2.0) << p.transpose();
  }
}

TEST(ExactMeshQueryTest, closest_point_within_a_radius_matches_brute_force) {
  const TriangleMesh m = test::icosphere(3, 2.0, Vec3(1, -1, 0.5));
  const ExactMeshQuery q(m);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-4, 4), r(0.01, 1.5);
  int found = 0, none = 0;
  for (int k = 0; k < 300; ++k) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const double radius = r(rng);
    double best = 1e300;
    for (const Tri& t : m.faces)
      best = std::min(best,
                      (closest_point_on_triangle(p, m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]) - p).norm());
    const ClosestPoint c = q.closest_point(p, radius);
    if (best < radius) {
      ++found;
      ASSERT_GE(c.face, 0) << "point " << k;
      EXPECT_NEAR(c.distance, best, 1e-9);
      EXPECT_NEAR((c.point - p).norm(), best, 1e-9);
    } else {
      ++none;
      EXPECT_EQ(c.face, -1) << "point " << k;
    }
  }
  EXPECT_GT(found, 20);
  EXPECT_GT(none, 20);
}
