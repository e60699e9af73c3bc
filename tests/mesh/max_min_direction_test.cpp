// SPDX-License-Identifier: MIT
// The max-min direction search of the decimation's fold test and the bake's ray directions
// (improve_max_min()), against the plain scan of its candidates (every normal, every pair's
// bisector and every triple's circumcentre, each checked against every normal) and brute force;
// and the nearest point of a hull to the origin (nearest_hull_point()) that it rests on.
#include "../../src/mesh/max_min_direction.h"
#include "support/brute_force.h"

#include <gtest/gtest.h>

#include <numbers>
#include <random>

namespace hdm {
namespace {

double min_dot(const Vec3& d, const std::vector<Vec3>& normals) {
  double m = 2;
  for (const Vec3& n : normals) m = std::min(m, d.dot(n));
  return m;
}

// The plain scan: each candidate normalised and checked against every normal in input order.
void plain_scan(const std::vector<Vec3>& n, double& best, Vec3& best_d, bool triples) {
  auto consider = [&](Vec3 d) {
    const double len = d.norm();
    if (!(len > 1e-12)) return;
    d /= len;
    const double w = min_dot(d, n);
    if (w > best) best = w, best_d = d;
  };
  for (size_t a = 0; a < n.size(); ++a) {
    consider(n[a]);
    for (size_t b = a + 1; b < n.size(); ++b) {
      consider(n[a] + n[b]);
      if (!triples) continue;
      for (size_t c = b + 1; c < n.size(); ++c) {
        Vec3 d = (n[a] - n[b]).cross(n[a] - n[c]);
        consider(d.dot(n[a]) < 0 ? Vec3(-d) : d);
      }
    }
  }
}

// k unit vectors within @p half_angle of a random axis (beyond π/2: no open hemisphere may hold them).
std::vector<Vec3> normals_in_cap(std::mt19937& rng, int k, double half_angle) {
  std::normal_distribution<double> g(0, 1);
  std::uniform_real_distribution<double> u(0, 1);
  const Vec3 axis = Vec3(g(rng), g(rng), g(rng)).normalized();
  const Vec3 e1 = axis.unitOrthogonal(), e2 = axis.cross(e1);
  std::vector<Vec3> n(static_cast<size_t>(k));
  for (Vec3& x : n) {
    const double t = half_angle * std::sqrt(u(rng)), phi = 2 * std::numbers::pi * u(rng);
    x = (std::cos(t) * axis + std::sin(t) * (std::cos(phi) * e1 + std::sin(phi) * e2)).normalized();
  }
  return n;
}

TEST(MaxMinDirection, GivesThePlainScansFigureAndDirectionBitForBit) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(0.02, 2.8);  // stars seen well, barely, or not at all
  for (int k : {1, 2, 3, 5, 12, 24, 25, 60, 200})
    for (int trial = 0; trial < 30; ++trial) {
      const std::vector<Vec3> n = normals_in_cap(rng, k, angle(rng));
      // From the figure the decimation's quick estimate leaves: the plain scan's start.
      const double start = min_dot(n[0], n) - 0.1;
      double value = start, expected = start;
      Vec3 d = Vec3::Zero(), expected_d = Vec3::Zero();
      mesh::detail::improve_max_min(n, value, &d);
      plain_scan(n, expected, expected_d, k <= 24);
      ASSERT_EQ(value, expected) << k << " normals, trial " << trial;
      ASSERT_EQ(d, expected_d) << k << " normals, trial " << trial;
      // The figure alone: the same where no direction sees every normal (their hull holds the origin).
      Vec3 x;
      if (mesh::detail::hull_origin(n, x) == mesh::detail::HullOrigin::Holds) {
        double figure = start, given = start;
        mesh::detail::improve_max_min_figure(n, figure);
        mesh::detail::improve_max_min_figure(n, given, mesh::detail::HullOrigin::Holds, x);
        ASSERT_EQ(figure, expected) << k << " normals, trial " << trial;
        ASSERT_EQ(given, expected) << k << " normals, trial " << trial;
      }
    }
}

// Where a direction sees up to 24 normals, the figure alone (improve_max_min_figure()) is that of
// the nearest point of their hull to the origin, normalised: the plain scan's optimum (fixed by
// one, two or three normals), to rounding. Above 24 it is the plain scan's of normals and pairs,
// bit for bit.
TEST(MaxMinDirection, TheFigureWhereADirectionSeesEveryNormalIsThePlainScans) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> angle(0.02, 1.55);
  for (int k : {1, 2, 3, 5, 12, 24, 25, 60})
    for (int trial = 0; trial < 30; ++trial) {
      const std::vector<Vec3> n = normals_in_cap(rng, k, angle(rng));
      double value = -2, given = -2, expected = -2;
      Vec3 expected_d = Vec3::Zero(), x;
      mesh::detail::improve_max_min_figure(n, value);
      // The same figure from a verdict on the hull the caller already has.
      ASSERT_EQ(mesh::detail::hull_origin(n, x), mesh::detail::HullOrigin::Outside) << k << " normals, trial " << trial;
      mesh::detail::improve_max_min_figure(n, given, mesh::detail::HullOrigin::Outside, x);
      plain_scan(n, expected, expected_d, k <= 24);
      ASSERT_GT(expected, 0);
      for (double figure : {value, given})
        if (k <= 24)
          ASSERT_NEAR(figure, expected, 1e-9) << k << " normals, trial " << trial;
        else
          ASSERT_EQ(figure, expected) << k << " normals, trial " << trial;
    }
}

// Whether the origin lies in the tetrahedron (a, b, c, d): the four signed volumes with it in
// place of each corner have the sign of the whole.
bool origin_in_tetrahedron(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  auto vol = [](const Vec3& p, const Vec3& q, const Vec3& r, const Vec3& s) { return (q - p).cross(r - p).dot(s - p); };
  const Vec3 o = Vec3::Zero();
  const double whole = vol(a, b, c, d);
  if (whole == 0) return false;
  for (double part : {vol(o, b, c, d), vol(a, o, c, d), vol(a, b, o, d), vol(a, b, c, o)})
    if (part * whole < 0) return false;
  return true;
}

// The hull's nearest point to the origin, against brute force: 0 when the origin lies in a
// tetrahedron of four of the points (Carathéodory), else the nearest point of every triangle of
// three of them (the hull's boundary is made of such triangles, and each lies in the hull), for
// points in general position, not only unit ones.
TEST(MaxMinDirection, NearestHullPointAgreesWithBruteForce) {
  std::mt19937 rng(3);
  int held = 0, outside = 0;
  std::normal_distribution<double> g(0, 1);
  for (int k : {1, 2, 3, 4, 7, 15})
    for (int trial = 0; trial < 40; ++trial) {
      const Vec3 shift = (trial % 2 ? 0.5 : 2.0) * Vec3(g(rng), g(rng), g(rng));
      TriangleMesh all;
      for (int i = 0; i < k; ++i) all.vertices.push_back(shift + Vec3(g(rng), g(rng), g(rng)));
      for (int a = 0; a < k; ++a)
        for (int b = a; b < k; ++b)
          for (int c = b; c < k; ++c) all.faces.push_back({a, b, c});  // repeated corners: edges, points
      Vec3 x;
      ASSERT_TRUE(mesh::detail::nearest_hull_point(all.vertices, x)) << k << " points, trial " << trial;
      bool inside = false;
      const std::vector<Vec3>& p = all.vertices;
      for (int a = 0; a < k; ++a)
        for (int b = a + 1; b < k; ++b)
          for (int c = b + 1; c < k; ++c)
            for (int d = c + 1; d < k; ++d) inside = inside || origin_in_tetrahedron(p[a], p[b], p[c], p[d]);
      const double brute = inside ? 0.0 : test::brute_distance(Vec3::Zero(), all);
      ++(brute < 1e-9 ? held : outside);
      if (brute < 1e-9) {
        EXPECT_LE(x.norm(), mesh::detail::kHullHoldsOrigin * 3) << k << " points, trial " << trial;
        continue;
      }
      EXPECT_NEAR(x.norm(), brute, 1e-9 * (1 + brute)) << k << " points, trial " << trial;
      EXPECT_LE(test::brute_distance(x, all), 1e-9) << "x is a point of the hull";
    }
  EXPECT_GT(held, 20);
  EXPECT_GT(outside, 20);
}

TEST(MaxMinDirection, FindsTheOptimumOfUpTo24NormalsInAHemisphere) {
  // The optimum (the centre of the smallest spherical cap holding the normals) is fixed by one,
  // two or three of them; checked against directions around the answer, which none may beat:
  // the problem is convex inside a hemisphere, so a local optimum is the optimum.
  std::mt19937 rng(11);
  std::normal_distribution<double> g(0, 1);
  for (int trial = 0; trial < 40; ++trial) {
    const std::vector<Vec3> n = normals_in_cap(rng, 3 + trial % 22, 1.2);
    double value = -2;
    Vec3 d = Vec3::Zero();
    mesh::detail::improve_max_min(n, value, &d);
    ASSERT_GT(value, 0);
    for (double step : {1e-2, 1e-4, 1e-6})
      for (int k = 0; k < 100; ++k)
        ASSERT_LE(min_dot((d + step * Vec3(g(rng), g(rng), g(rng))).normalized(), n), value + 1e-12)
            << "trial " << trial << ": a better direction at step " << step;
  }
}

}  // namespace
}  // namespace hdm
