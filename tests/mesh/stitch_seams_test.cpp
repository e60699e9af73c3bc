// SPDX-License-Identifier: MIT
// Seams of separate patches whose vertices nearly coincide (CAD patch soups written with rounded
// coordinates: ALSTOM_TEST4.off): checked by counting (boundary, non-manifold and inconsistent
// edges, vertices merged) and against the analytic volume and area of the shape.
#include <hdm/mesh/stitch_seams.h>

#include "support/test_models.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace hdm;

namespace {

// An n x n grid of the parallelogram origin + s u + t v, faces counter-clockwise seen from u x v,
// every vertex moved by a pseudo-random offset of at most @p jitter per coordinate.
void add_patch(TriangleMesh& m, const Vec3& origin, const Vec3& u, const Vec3& v, int n, double jitter) {
  const auto base = static_cast<int32_t>(m.vertices.size());
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const int32_t k = static_cast<int32_t>(m.vertices.size());
      const Vec3 wobble(std::sin(12.9898 * k + 1), std::sin(78.233 * k + 2), std::sin(37.719 * k + 3));
      m.vertices.push_back(origin + u * (double(i) / n) + v * (double(j) / n) + jitter * wobble);
    }
  auto id = [&](int i, int j) { return base + j * (n + 1) + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      m.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
}

// The unit cube [0,1]^3 as six separate n x n patches, outward, every vertex off its place by up
// to @p jitter: no two patches share a position.
TriangleMesh jittered_cube(int n, double jitter) {
  TriangleMesh m;
  const Vec3 o = Vec3::Zero(), x = Vec3::UnitX(), y = Vec3::UnitY(), z = Vec3::UnitZ();
  add_patch(m, o, z, y, n, jitter);
  add_patch(m, x, y, z, n, jitter);
  add_patch(m, o, x, z, n, jitter);
  add_patch(m, y, z, x, n, jitter);
  add_patch(m, o, y, x, n, jitter);
  add_patch(m, z, x, y, n, jitter);
  return m;
}

}  // namespace

TEST(StitchSeams, NearlyCoincidentSeamVerticesAreMerged) {
  const int n = 3;
  const double jitter = 1e-3;  // 0.3 % of an edge (1/3): far below the 5 % merge distance
  const TriangleMesh in = jittered_cube(n, jitter);
  SeamReport rep;
  const TriangleMesh out = stitch_seams(in, &rep);
  // Each of the 12 cube edges has n edges on each of its two sides.
  EXPECT_EQ(rep.boundary_edges_before, 12 * 2 * n);
  // Boundary vertex copies (4n per patch) minus distinct seam points (8 corners, n - 1 per edge).
  EXPECT_EQ(rep.snapped, 6 * 4 * n - (8 + 12 * (n - 1)));
  EXPECT_EQ(rep.inserted, 0);
  EXPECT_EQ(rep.boundary_edges_after, 0);
  const MeshTopology topo = analyze_topology(out);
  EXPECT_EQ(topo.boundary_edges, 0);
  EXPECT_EQ(topo.non_manifold_edges, 0);
  EXPECT_EQ(topo.inconsistent_edges, 0);
  EXPECT_EQ(out.faces.size(), in.faces.size());
  EXPECT_EQ(out.vertices.size(), 6 * size_t(n + 1) * (n + 1) - size_t(rep.snapped));
  // No vertex moves by more than the jitter: the volume is the cube's up to the jitter's effect.
  EXPECT_NEAR(test::signed_volume(out), 1.0, 6 * 3 * jitter);
}

TEST(StitchSeams, SeamsFartherThanTheMergeDistanceStayOpen) {
  // The same cube with every vertex off by up to 2.5 % of the unit, 7.5 % of an edge: corners of
  // different patches are up to 15 % of an edge apart, beyond the 5 % rule for most of them.
  const int n = 3;
  const TriangleMesh in = jittered_cube(n, 0.025);
  SeamReport rep;
  stitch_seams(in, &rep);
  EXPECT_LT(rep.snapped, (6 * 4 * n - (8 + 12 * (n - 1))) / 2);
  EXPECT_GT(rep.boundary_edges_after, 0);
}

TEST(StitchSeams, NeverMergesTwoVerticesOfOneSheet) {
  // One patch folded so that its two far edges nearly meet (a slit tube): the same sheet, so
  // nothing is merged and no face collapses.
  TriangleMesh in;
  const int n = 8;
  const auto base = static_cast<int32_t>(in.vertices.size());
  for (int j = 0; j <= 2; ++j)
    for (int i = 0; i <= n; ++i) {
      const double phi = (2 * std::numbers::pi - 1e-4) * i / n;
      in.vertices.push_back(Vec3(std::cos(phi), std::sin(phi), 0.5 * j));
    }
  auto id = [&](int i, int j) { return base + j * (n + 1) + i; };
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < n; ++i) {
      in.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      in.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  SeamReport rep;
  const TriangleMesh out = stitch_seams(in, &rep);
  EXPECT_EQ(rep.snapped, 0);
  EXPECT_EQ(out.faces.size(), in.faces.size());
  EXPECT_EQ(rep.boundary_edges_after, rep.boundary_edges_before);
}
