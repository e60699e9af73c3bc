// SPDX-License-Identifier: MIT
// √3 subdivision: face counts from the rule (each step triples a closed mesh's faces), topology
// from the Euler characteristic, and positions against the input with Embree's exact closest
// point and the convex-hull property of the subdivision masks.
#include "support/test_models.h"

#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/core/error.h>
#include <hdm/mesh/subdivide_mesh.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace hdm;
using test::signed_volume;

namespace {

// Faces after the fewest tripling steps that reach `wanted` (the closed-mesh rule of √3).
int64_t tripled_until(int64_t faces, int64_t wanted, int* steps) {
  *steps = 0;
  while (faces < wanted) faces *= 3, ++*steps;
  return faces;
}

double longest_edge(const TriangleMesh& m) {
  double l = 0;
  for (const Tri& t : m.faces)
    for (int k = 0; k < 3; ++k) l = std::max(l, (m.vertices[t[(k + 1) % 3]] - m.vertices[t[k]]).norm());
  return l;
}

double mean_edge(const TriangleMesh& m) {
  double l = 0;
  for (const Tri& t : m.faces)
    for (int k = 0; k < 3; ++k) l += (m.vertices[t[(k + 1) % 3]] - m.vertices[t[k]]).norm();
  return l / (3.0 * m.faces.size());
}

// Manifold, consistently oriented, no degenerate face, one component; closed or with a boundary.
void expect_manifold(const TriangleMesh& m, bool closed = true) {
  const MeshTopology t = analyze_topology(m);
  if (closed)
    EXPECT_EQ(t.boundary_edges, 0);
  else
    EXPECT_GT(t.boundary_edges, 0);
  EXPECT_EQ(t.non_manifold_edges, 0);
  EXPECT_EQ(t.inconsistent_edges, 0);
  EXPECT_EQ(t.degenerate_faces, 0);
  EXPECT_EQ(t.components, 1);
}

// Euler characteristic V − E + F of a closed triangle mesh (E = 3F/2).
int64_t euler_closed(const TriangleMesh& m) {
  return int64_t(m.vertices.size()) - int64_t(3 * m.faces.size() / 2) + int64_t(m.faces.size());
}

// Largest and RMS distance from the vertices of `from` to the surface of `to` (Embree).
std::pair<double, double> vertex_distances(const TriangleMesh& from, const TriangleMesh& to) {
  const ExactMeshQuery q(to);
  double mx = 0, sq = 0;
  for (const Vec3& p : from.vertices) {
    const double d = q.closest_point(p).distance;
    mx = std::max(mx, d);
    sq += d * d;
  }
  return {mx, std::sqrt(sq / double(from.vertices.size()))};
}

}  // namespace

TEST(SubdivideMesh, SphereFacesTriplePerStepAndStayInTheConvexHull) {
  const double r = 2.0;
  const TriangleMesh in = test::icosphere(2, r, Vec3(0.5, -1, 3));  // 320 faces on a sphere
  int want_steps = 0;
  const int64_t want = tripled_until(int64_t(in.faces.size()), 5000, &want_steps);
  int steps = -1;
  const TriangleMesh out = subdivide_mesh(in, 5000, &steps);
  EXPECT_EQ(int64_t(out.faces.size()), want);
  EXPECT_EQ(steps, want_steps);
  expect_manifold(out);
  EXPECT_EQ(euler_closed(out), 2);  // still a sphere
  // Every √3 position is a convex combination of input vertices, which lie on the sphere: inside
  // the ball, and inside the (convex) input, so the volume can only shrink.
  for (const Vec3& p : out.vertices) EXPECT_LE((p - Vec3(0.5, -1, 3)).norm(), r * (1 + 1e-12));
  const double v_in = signed_volume(in), v_out = signed_volume(out);
  EXPECT_GT(v_out, 0);  // still outward
  EXPECT_LE(v_out, v_in * (1 + 1e-12));
  EXPECT_GT(v_out, 0.95 * v_in);
}

TEST(SubdivideMesh, BunnyOneStepKeepsTopologyAndStaysOnTheSurface) {
  const TriangleMesh& in = test::bunny();
  ASSERT_EQ(analyze_topology(in).boundary_edges, 0);
  const auto wanted = int64_t(2 * in.faces.size());  // one step (×3) is the fewest that reaches it
  int steps = -1;
  const TriangleMesh out = subdivide_mesh(in, wanted, &steps);
  EXPECT_EQ(steps, 1);
  EXPECT_EQ(out.faces.size(), 3 * in.faces.size());
  EXPECT_EQ(out.vertices.size(), in.vertices.size() + in.faces.size());  // one new vertex per face
  expect_manifold(out);
  EXPECT_EQ(euler_closed(out), euler_closed(in));
  EXPECT_GT(signed_volume(out), 0);
  // Smoothing moves a vertex towards its one-ring, so every point stays within an edge length of
  // the input surface, and on average far closer (the move across the surface is second order).
  const double longest = longest_edge(in), mean = mean_edge(in);
  const auto [out_max, out_rms] = vertex_distances(out, in);
  EXPECT_LT(out_max, 0.5 * longest);
  EXPECT_LT(out_rms, 0.1 * mean);
  const auto [in_max, in_rms] = vertex_distances(in, out);
  EXPECT_LT(in_max, 0.5 * longest);
  EXPECT_LT(in_rms, 0.1 * mean);
}

TEST(SubdivideMesh, OpenMeshReachesTheCountAndKeepsOneBoundary) {
  TriangleMesh in = test::icosphere(2, 1.0);
  in.faces.erase(in.faces.begin());  // one triangular hole
  int steps = -1;
  const TriangleMesh out = subdivide_mesh(in, 3000, &steps);
  EXPECT_GE(out.faces.size(), 3000u);
  EXPECT_GE(steps, 2);
  expect_manifold(out, false);
  for (const Vec3& p : out.vertices) EXPECT_LE(p.norm(), 1 + 1e-12);
}

TEST(SubdivideMesh, EnoughTrianglesReturnsTheInput) {
  const TriangleMesh in = test::icosphere(1, 1.0);
  int steps = -1;
  const TriangleMesh out = subdivide_mesh(in, int64_t(in.faces.size()), &steps);
  EXPECT_EQ(steps, 0);
  EXPECT_EQ(out.faces, in.faces);
  EXPECT_EQ(out.vertices, in.vertices);
}

TEST(SubdivideMesh, BadInputIsRefused) {
  const TriangleMesh sphere = test::icosphere(1, 1.0);
  EXPECT_THROW(subdivide_mesh(sphere, -1), InvalidInput);
  EXPECT_THROW(subdivide_mesh(TriangleMesh{}, 10), InvalidInput);
  TriangleMesh fin = sphere;  // a third face on an edge: non-manifold
  const Tri& t = fin.faces[0];
  fin.vertices.push_back(Vec3(5, 5, 5));
  fin.faces.push_back({t[0], t[1], int32_t(fin.vertices.size() - 1)});
  EXPECT_THROW(subdivide_mesh(fin, 1000), InvalidInput);
}
