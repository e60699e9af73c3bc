// SPDX-License-Identifier: MIT
// The generalized winding number against independent references: Embree's ray parity on a closed
// sphere, the analytic solid angle of a flat disc, and the jump of exactly one across any face.
#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/mesh/winding_number.h>

#include "../support/test_models.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

using namespace hdm;
using hdm::test::icosphere;

TEST(WindingNumber, ClosedSphereIsOneInsideZeroOutsideAsRayParity) {
  const TriangleMesh sphere = icosphere(3, 1.0);
  const WindingNumber w(sphere);
  const ExactMeshQuery exact(sphere);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.6, 1.6);
  int checked = 0;
  for (int k = 0; k < 2000; ++k) {
    const Vec3 p(u(rng), u(rng), u(rng));
    if (std::abs(p.norm() - 1) < 0.05) continue;  // the tessellation is within 1.2% of the unit sphere
    const double expected = exact.inside(p) ? 1.0 : 0.0;
    EXPECT_NEAR(w(p), expected, 0.02) << p.transpose();
    EXPECT_EQ(w.inside(p), expected == 1.0);
    ++checked;
  }
  EXPECT_GT(checked, 1500);
  EXPECT_TRUE(std::isnan(w(Vec3(NAN, 0, 0))));
}

TEST(WindingNumber, FlatDiscIsItsSolidAngleOverFourPi) {
  // A disc of radius R in z = 0 (a fine fan, normal +z) seen from (0, 0, h): the solid angle of a
  // disc on its axis is 2π(1 − h/√(h² + R²)); the front (+z) counts negative.
  TriangleMesh disc;
  const int n = 256;
  const double R = 1;
  disc.vertices.push_back(Vec3::Zero());
  for (int i = 0; i < n; ++i)
    disc.vertices.emplace_back(R * std::cos(2 * std::numbers::pi * i / n), R * std::sin(2 * std::numbers::pi * i / n), 0);
  for (int i = 0; i < n; ++i) disc.faces.push_back({0, 1 + i, 1 + (i + 1) % n});
  const WindingNumber w(disc);
  for (double h : {0.01, 0.3, 1.0, 3.0}) {
    const double expected = 0.5 * (1 - h / std::sqrt(h * h + R * R));
    EXPECT_NEAR(-w(Vec3(0, 0, h)), expected, 5e-3) << h;  // the 256-gon is 0.01% smaller than the disc
    EXPECT_NEAR(w(Vec3(0, 0, -h)), expected, 5e-3) << h;
  }
}

TEST(WindingNumber, JumpsByOneAcrossEveryFaceOfAnOpenSheet) {
  // A hemisphere (open): w in front of a face and behind it differ by exactly one.
  TriangleMesh sphere = icosphere(3, 1.0), cap;
  cap.vertices = sphere.vertices;
  for (const Tri& t : sphere.faces)
    if (sphere.vertices[t[0]].z() + sphere.vertices[t[1]].z() + sphere.vertices[t[2]].z() > 0) cap.faces.push_back(t);
  const WindingNumber w(cap);
  for (size_t f = 0; f < cap.faces.size(); f += 7) {
    const Tri& t = cap.faces[f];
    const Vec3 a = cap.vertices[t[0]], b = cap.vertices[t[1]], c = cap.vertices[t[2]];
    const Vec3 n = (b - a).cross(c - a).normalized(), g = (a + b + c) / 3;
    EXPECT_NEAR(w(g - 1e-6 * n) - w(g + 1e-6 * n), 1.0, 1e-3) << f;
  }
}
