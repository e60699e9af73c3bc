// SPDX-License-Identifier: MIT
// split_faces(): four faces per face on the same surface (every new vertex on its edge, the area
// and the enclosed volume unchanged), closed and manifold where the input is, per-vertex values
// carried as the smaller of the edge's two ends.
#include "support/test_models.h"

#include <hdm/mesh/split_faces.h>

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <utility>

using namespace hdm;

namespace {

void area_and_volume(const TriangleMesh& m, double& area, double& volume) {
  area = volume = 0;
  for (const Tri& t : m.faces) {
    const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
    area += (b - a).cross(c - a).norm() / 2;
    volume += a.dot(b.cross(c)) / 6;
  }
}

}  // namespace

TEST(SplitFaces, FourFacesPerFaceOnTheSameSurface) {
  const TriangleMesh in = test::icosphere(2, 1.0);
  std::vector<double> caps(in.vertices.size());
  for (size_t v = 0; v < caps.size(); ++v) caps[v] = in.vertices[v].z() > 0 ? 0.1 : INFINITY;
  const TriangleMesh out = split_faces(in, &caps);
  ASSERT_EQ(out.faces.size(), 4 * in.faces.size());
  // Closed surface: Euler's formula gives V' = V + E = V + 3F/2.
  ASSERT_EQ(out.vertices.size(), in.vertices.size() + 3 * in.faces.size() / 2);
  ASSERT_EQ(caps.size(), out.vertices.size());
  for (size_t v = 0; v < in.vertices.size(); ++v) EXPECT_EQ(out.vertices[v], in.vertices[v]);
  // Each face's four lie in its plane, within it, and cover its area.
  for (size_t f = 0; f < in.faces.size(); ++f) {
    const Tri& t = in.faces[f];
    const Vec3 a = in.vertices[t[0]], b = in.vertices[t[1]], c = in.vertices[t[2]];
    const Vec3 n = (b - a).cross(c - a);
    double area = 0;
    for (int k = 0; k < 4; ++k) {
      const Tri& s = out.faces[4 * f + k];
      const Vec3 p = out.vertices[s[0]], q = out.vertices[s[1]], r = out.vertices[s[2]];
      for (const Vec3& x : {p, q, r}) EXPECT_NEAR((x - a).dot(n) / n.norm(), 0, 1e-15);
      EXPECT_GT((q - p).cross(r - p).dot(n), 0);  // wound as the face
      area += (q - p).cross(r - p).norm() / 2;
    }
    EXPECT_NEAR(area, n.norm() / 2, 1e-15);
  }
  double a0, v0, a1, v1;
  area_and_volume(in, a0, v0);
  area_and_volume(out, a1, v1);
  EXPECT_NEAR(a1, a0, 1e-12);
  EXPECT_NEAR(v1, v0, 1e-12);
  // Every edge of the result has two faces, one each way: closed and consistently oriented.
  std::map<std::pair<int32_t, int32_t>, int> directed;
  for (const Tri& t : out.faces)
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  for (const auto& [e, count] : directed) {
    EXPECT_EQ(count, 1);
    EXPECT_EQ(directed.count({e.second, e.first}), 1u);
  }
  // A new vertex is the midpoint of an edge and carries the smaller of its ends' values.
  for (const Tri& t : in.faces)
    for (int k = 0; k < 3; ++k) {
      const Vec3 m = 0.5 * (in.vertices[t[k]] + in.vertices[t[(k + 1) % 3]]);
      const double want = std::min(caps[t[k]], caps[t[(k + 1) % 3]]);
      int found = 0;
      for (size_t v = in.vertices.size(); v < out.vertices.size(); ++v)
        if ((out.vertices[v] - m).norm() < 1e-15) {
          ++found;
          EXPECT_EQ(caps[v], want);
        }
      EXPECT_EQ(found, 1);
    }
}
