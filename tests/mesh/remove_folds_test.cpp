// SPDX-License-Identifier: MIT
// remove_folds() on a flat sheet with a flap folded back over its rim, a folded-back wall kept when
// it turns by less, and a crumple in its interior: checked by counting (faces, boundary edges,
// empty-cone vertices by the brute-force search of the test support) and against the plane z = 0.
#include "support/test_models.h"

#include <hdm/core/error.h>
#include <hdm/mesh/remove_folds.h>

#include <gtest/gtest.h>

using namespace hdm;

namespace {

// The unit square in z = 0 as an n x n grid of cells, two faces each, normals +z.
TriangleMesh flat_sheet(int n) {
  TriangleMesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.vertices.emplace_back(double(i) / n, double(j) / n, 0.0);
  auto id = [n](int i, int j) { return int32_t(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      m.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return m;
}

// Adds a face on the rim edge from grid vertex a to b (y = 0) whose free corner sits at @p tip:
// (b, a, tip) keeps the sheet's orientation across the edge.
void add_rim_face(TriangleMesh& m, int32_t a, int32_t b, const Vec3& tip) {
  m.vertices.push_back(tip);
  m.faces.push_back({b, a, int32_t(m.vertices.size() - 1)});
}

double area(const TriangleMesh& m) {
  double a = 0;
  for (const Tri& t : m.faces)
    a += 0.5 * (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).norm();
  return a;
}

TEST(RemoveFoldsTest, AFlapFoldedBackOverTheRimIsRemoved) {
  const int n = 20;  // cells of 1/20: the flap spans 4 % of the sheet's diagonal
  TriangleMesh m = flat_sheet(n);
  // Over the sheet, just above it: the flap turns back by about 172 degrees.
  add_rim_face(m, 3, 4, Vec3(3.5 / n, 0.6 / n, 0.004));
  ASSERT_EQ(test::count_empty_cones(m, 0.1), 2);
  const FoldReport r = remove_folds(m);
  EXPECT_EQ(r.flap_faces, 1);
  EXPECT_NEAR(r.max_deviation, 0.004, 1e-12);  // the flap's tip, 0.004 above the sheet
  EXPECT_EQ(m.faces.size(), size_t(2 * n * n));
  EXPECT_EQ(m.vertices.size(), size_t((n + 1) * (n + 1)));
  EXPECT_EQ(analyze_topology(m).boundary_edges, 4 * n);
  EXPECT_NEAR(area(m), 1.0, 1e-12);
  for (const Vec3& p : m.vertices) EXPECT_EQ(p.z(), 0.0);
  EXPECT_EQ(test::count_empty_cones(m, 0.0), 0);
}

TEST(RemoveFoldsTest, AWallAtTheRimIsKept) {
  const int n = 8;
  TriangleMesh m = flat_sheet(n);
  // A wall standing up from the rim (turns by 90 degrees) and one leaning back over the sheet by
  // 110 degrees: features, not folds.
  add_rim_face(m, 2, 3, Vec3(2.5 / n, 0.0, 1.0 / n));
  add_rim_face(m, 5, 6, Vec3(5.5 / n, 0.34 / n, 1.0 / n));
  const TriangleMesh before = m;
  const FoldReport r = remove_folds(m);
  EXPECT_EQ(r.flap_faces + r.rim_faces, 0);
  EXPECT_EQ(r.max_deviation, 0.0);
  EXPECT_EQ(m.faces, before.faces);
  EXPECT_EQ(m.vertices, before.vertices);
}

TEST(RemoveFoldsTest, ACrumpleInsideTheSheetIsUnfoldedIntoThePlane) {
  const int n = 8;
  TriangleMesh m = flat_sheet(n);
  // Vertex (4, 4) dragged 1.6 cells sideways, past its ring: faces of its star flip over.
  const int32_t v = 4 * (n + 1) + 4;
  m.vertices[v].x() += 1.6 / n;
  ASSERT_GT(test::count_empty_cones(m, 0.0), 0);
  const FoldReport r = remove_folds(m);
  EXPECT_GT(r.empty_cones_before, 0);
  EXPECT_EQ(r.empty_cones_after, 0);
  EXPECT_GT(r.moved, 0);
  EXPECT_LT(r.max_deviation, 1e-12);  // moved within the plane: the surface is the same square
  EXPECT_EQ(m.faces.size(), size_t(2 * n * n));
  EXPECT_EQ(test::count_empty_cones(m, 0.0), 0);
  for (const Vec3& p : m.vertices) EXPECT_EQ(p.z(), 0.0);
  // Unfolded, the faces cover the square once: every normal +z and the area is the square's.
  for (const Tri& t : m.faces)
    EXPECT_GT((m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).z(), 0);
  EXPECT_NEAR(area(m), 1.0, 1e-9);
}

TEST(RemoveFoldsTest, RefusesInvalidMeshData) {
  TriangleMesh empty;
  EXPECT_THROW(remove_folds(empty), InvalidInput);
}

}  // namespace
