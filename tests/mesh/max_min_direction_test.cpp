// SPDX-License-Identifier: MIT
// The max-min direction search of the decimation's fold test and the bake's ray directions
// (improve_max_min()): its figure and direction are those of the plain scan of its candidates
// (every normal, every pair's bisector and, up to 24 normals, every triple's circumcentre, each
// checked against every normal), bit for bit, whatever order it checks the normals in; and where
// the optimum is one of them, it is the optimum, found by brute force.
#include "../../src/mesh/max_min_direction.h"

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
    }
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
