// SPDX-License-Identifier: MIT
// Closed inputs: meshes of the libcgal-demo archive that cross or touch themselves
// (cow.off: two halves that cross and touch at a point) or hold cap slivers (triceratops.off: input
// vertices on another face's edge) bake at default settings with valid, disjoint slabs, within the
// default bound and with the contact test agreeing with the input. Measured against the input as
// read (not the resolved union the bake follows), with Embree, apart from the bake; the checks of
// the union (manifold, no coincident vertices) are brute-force counts.
#include "support/test_models.h"

#include <hdm/analysis/bake_to_tolerance.h>
#include <hdm/analysis/fidelity.h>
#include <hdm/core/error.h>
#include <hdm/io/read_mesh.h>
#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/mesh/flip_slivers.h>
#include <hdm/mesh/orient_mesh.h>
#include <hdm/mesh/self_intersections.h>
#include <hdm/slab/shell_check.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <numeric>
#include <set>

using namespace hdm;
using test::signed_volume;

namespace {

int find(std::vector<int>& p, int a) { return p[a] == a ? a : p[a] = find(p, p[p[a]]); }

// Vertices whose faces form more than one edge-connected fan (pinches).
int pinched_vertices(const TriangleMesh& m) {
  std::vector<std::vector<int>> star(m.vertices.size());
  for (size_t f = 0; f < m.faces.size(); ++f)
    for (int32_t v : m.faces[f]) star[v].push_back(int(f));
  int pinched = 0;
  for (size_t v = 0; v < star.size(); ++v) {
    const auto& s = star[v];
    std::vector<int> p(s.size());
    std::iota(p.begin(), p.end(), 0);
    for (size_t i = 0; i < s.size(); ++i)
      for (size_t j = i + 1; j < s.size(); ++j) {
        int shared = 0;
        for (int32_t a : m.faces[s[i]])
          for (int32_t b : m.faces[s[j]]) shared += a == b;
        if (shared >= 2) p[find(p, int(i))] = find(p, int(j));
      }
    int fans = 0;
    for (size_t i = 0; i < s.size(); ++i) fans += find(p, int(i)) == int(i);
    pinched += fans > 1;
  }
  return pinched;
}

// Faces whose largest angle exceeds 150 degrees and smallest is below half a degree (caps).
int caps(const TriangleMesh& m) {
  int n = 0;
  for (const Tri& t : m.faces) {
    double lo = 180, hi = 0;
    for (int k = 0; k < 3; ++k) {
      const Vec3 u = m.vertices[t[(k + 1) % 3]] - m.vertices[t[k]], w = m.vertices[t[(k + 2) % 3]] - m.vertices[t[k]];
      const double a = std::atan2(u.cross(w).norm(), u.dot(w)) * 180 / std::numbers::pi;
      lo = std::min(lo, a), hi = std::max(hi, a);
    }
    n += hi > 150 && lo < 0.5;
  }
  return n;
}

// Bakes @p file as `hdm bake` does at defaults (orient, resolve a crossing, bake to the default
// bound) and checks the model against the input as read.
void expect_default_bake_passes(const std::string& file) {
  TriangleMesh input = read_mesh(test::data_path(file));
  orient_outward(input);
  const bool crosses = count_self_intersections(input) > 0;
  const TriangleMesh resolved = crosses ? resolve_self_intersections(input) : input;
  const ExactMeshQuery reference(resolved);
  // The points of the material's surface on the input as read, as the check below measures them.
  const ExactMeshQuery exact(input);
  std::vector<uint8_t> interior;
  if (crosses) interior = interior_faces(exact);
  const std::vector<Vec3> points = surface_points(exact, crosses ? &interior : nullptr);
  Tolerance t;  // hdm bake's default bound
  t.max_pct = 0.2;
  t.rms_pct = 0.02;
  t.input_points = &points;
  std::vector<ToleranceRound> rounds;
  const SlabModel m = bake_to_tolerance(reference, file, BakeOptions{}, t, &rounds);
  EXPECT_EQ(count_invalid_slabs(m), 0) << file;
  EXPECT_EQ(count_overlapping_pairs(m), 0) << file;
  const Fidelity f = measure_fidelity(m, exact, &points);
  EXPECT_LE(std::max(f.max_pct, f.max_back_pct), 0.2) << file;
  EXPECT_LE(std::max(f.rms_pct, f.rms_back_pct), 0.02) << file;
  EXPECT_GE(measure_contact(m, exact, 20000, 1, 1.0).agreement, 0.995) << file;
}

}  // namespace

TEST(ClosedSelfIntersection, AUnionTouchingItselfAtAPointIsSplitIntoAManifold) {
  TriangleMesh input = read_mesh(test::data_path("cow.off"));
  orient_outward(input);
  ASSERT_GT(count_self_intersections(input), 0) << "cow.off's halves cross";
  SelfIntersectionReport rep;
  const TriangleMesh u = resolve_self_intersections(input, &rep);
  ASSERT_TRUE(rep.resolved);
  EXPECT_EQ(pinched_vertices(u), 0) << "every vertex of the union is a single fan";
  const MeshTopology t = analyze_topology(u);
  EXPECT_EQ(t.boundary_edges, 0);
  EXPECT_EQ(t.non_manifold_edges, 0);
  EXPECT_EQ(count_self_intersections(u), 0);
  // No two vertices coincide (the copies of a pinch were moved apart).
  std::set<std::tuple<double, double, double>> points;
  for (const Vec3& p : u.vertices) points.emplace(p.x(), p.y(), p.z());
  EXPECT_EQ(points.size(), u.vertices.size());
}

TEST(ClosedSelfIntersection, FlippingCapsKeepsTheSurfaceAndItsTopology) {
  // A cap on a plane: apex (1, 1e-5) on edge (0,0)-(2,0), its neighbour below; both face +z.
  TriangleMesh flat;
  flat.vertices = {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(1, 1e-5, 0), Vec3(1, -1, 0)};
  flat.faces = {{0, 1, 2}, {1, 0, 3}};
  ASSERT_EQ(caps(flat), 1);
  EXPECT_EQ(flip_slivers(flat, 0.5), 1);
  EXPECT_EQ(caps(flat), 0);
  for (const Tri& f : flat.faces) {
    const Vec3 n = (flat.vertices[f[1]] - flat.vertices[f[0]]).cross(flat.vertices[f[2]] - flat.vertices[f[0]]);
    EXPECT_GT(n.z(), 0) << "orientation kept";
  }
  // A real closed mesh with two caps: both go, the volume and the topology stay.
  TriangleMesh tri = read_mesh(test::data_path("triceratops.off"));
  const int before = caps(tri);
  ASSERT_GE(before, 1) << "triceratops.off holds cap slivers";
  const double volume = signed_volume(tri);
  const MeshTopology t0 = analyze_topology(tri);
  EXPECT_GE(flip_slivers(tri, 0.5), before);
  EXPECT_EQ(caps(tri), 0);
  const MeshTopology t1 = analyze_topology(tri);
  EXPECT_EQ(t1.boundary_edges, t0.boundary_edges);
  EXPECT_EQ(t1.non_manifold_edges, 0);
  EXPECT_EQ(t1.inconsistent_edges, 0);
  EXPECT_NEAR(signed_volume(tri), volume, 1e-6 * std::abs(volume));
  EXPECT_THROW(flip_slivers(tri, 0), InvalidInput);
}

TEST(ClosedSelfIntersection, CowBakesAtDefaultSettings) { expect_default_bake_passes("cow.off"); }

TEST(ClosedSelfIntersection, TriceratopsBakesAtDefaultSettings) { expect_default_bake_passes("triceratops.off"); }
