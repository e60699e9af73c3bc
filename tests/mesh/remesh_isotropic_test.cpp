// SPDX-License-Identifier: MIT
// Isotropic remeshing of a CAD tessellation: the same surface (Embree distances both ways, the
// enclosed volume), closed and consistently oriented, its sharp rims kept, and no needle left.
#include <hdm/core/error.h>
#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/mesh/remesh_isotropic.h>

#include "support/test_models.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

using namespace hdm;

namespace {

// The smallest interior angle of any face [degrees].
double smallest_angle(const TriangleMesh& m) {
  double worst = 180;
  for (const Tri& t : m.faces)
    for (int k = 0; k < 3; ++k) {
      const Vec3 a = m.vertices[t[(k + 1) % 3]] - m.vertices[t[k]], b = m.vertices[t[(k + 2) % 3]] - m.vertices[t[k]];
      worst = std::min(worst, std::atan2(a.cross(b).norm(), a.dot(b)) * 180 / M_PI);
    }
  return worst;
}

}  // namespace

TEST(RemeshIsotropic, NeedleFansBecomeWellShapedTrianglesOfTheSameSurface) {
  const TriangleMesh in = test::fan_capped_disk(128);
  ASSERT_LT(smallest_angle(in), 1.5);  // 180 / 128 degrees at the fans' apex
  const double length = 0.05;
  const TriangleMesh out = remesh_isotropic(in, length);
  const MeshTopology t = analyze_topology(out);
  EXPECT_EQ(t.boundary_edges, 0);
  EXPECT_EQ(t.non_manifold_edges, 0);
  EXPECT_EQ(t.inconsistent_edges, 0);
  EXPECT_EQ(t.degenerate_faces, 0);
  EXPECT_GT(smallest_angle(out), 10.0);
  // The same surface: every remeshed vertex on the input, every input vertex (the rims, kept as
  // sharp polylines) on the remesh, and the volume of the 128-gon prism less at most what chords
  // of 4/3 of the target cut off its curved side: (2/3)·sagitta·perimeter over its area,
  // sagitta c²/8 for c = 4/3 · 0.05: 7.5e-4.
  const double diagonal = bounds(in).diagonal();
  const ExactMeshQuery input(in), remeshed(out);
  double out_to_in = 0, in_to_out = 0;
  for (const Vec3& p : out.vertices) out_to_in = std::max(out_to_in, input.closest_point(p).distance);
  for (const Vec3& p : in.vertices) in_to_out = std::max(in_to_out, remeshed.closest_point(p).distance);
  EXPECT_LT(out_to_in, 1e-9 * diagonal);
  EXPECT_LT(in_to_out, 1e-9 * diagonal);
  EXPECT_NEAR(test::signed_volume(out) / test::signed_volume(in), 1.0, 1e-3);
  // Edges near the target: the median within a quarter of it.
  std::vector<double> lengths;
  for (const Tri& f : out.faces)
    for (int k = 0; k < 3; ++k) lengths.push_back((out.vertices[f[k]] - out.vertices[f[(k + 1) % 3]]).norm());
  std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
  EXPECT_NEAR(lengths[lengths.size() / 2] / length, 1.0, 0.25);
}

TEST(RemeshIsotropic, RefusesANonPositiveLengthAndAMeshTheBakeRefuses) {
  EXPECT_THROW(remesh_isotropic(test::fan_capped_disk(16), 0.0), InvalidInput);
  TriangleMesh fin;  // three triangles on one edge
  fin.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  fin.faces = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  EXPECT_THROW(remesh_isotropic(fin, 0.1), InvalidInput);
}
