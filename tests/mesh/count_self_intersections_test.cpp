// SPDX-License-Identifier: MIT
// count_self_intersections(): crossing face pairs of a triangle soup, checked against CGAL's
// halfedge-mesh self-intersection test where the two rules coincide (manifold meshes without
// pinched vertices), against an all-pairs loop of CGAL's triangle test, and on configurations whose
// answer is known by construction (hinges, folds, fans, pinches, degenerate faces).
#include "support/test_models.h"

#include <hdm/mesh/self_intersections.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <gtest/gtest.h>

#include <random>

using namespace hdm;

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;

Point point(const TriangleMesh& m, int32_t v) { return {m.vertices[v].x(), m.vertices[v].y(), m.vertices[v].z()}; }

// CGAL's count on a halfedge copy of @p m (the reference for meshes that are manifold, without
// pinched vertices: there CGAL's "shared vertex" is the same as a shared vertex index).
int64_t cgal_count(const TriangleMesh& m) {
  namespace PMP = CGAL::Polygon_mesh_processing;
  std::vector<Point> points;
  for (size_t v = 0; v < m.vertices.size(); ++v) points.push_back(point(m, static_cast<int32_t>(v)));
  std::vector<std::vector<size_t>> polygons;
  for (const Tri& t : m.faces) polygons.push_back({size_t(t[0]), size_t(t[1]), size_t(t[2])});
  PMP::orient_polygon_soup(points, polygons);
  CGAL::Surface_mesh<Point> sm;
  PMP::polygon_soup_to_polygon_mesh(points, polygons, sm);
  std::vector<std::pair<CGAL::Surface_mesh<Point>::Face_index, CGAL::Surface_mesh<Point>::Face_index>> pairs;
  PMP::self_intersections(sm, std::back_inserter(pairs));
  return static_cast<int64_t>(pairs.size());
}

TriangleMesh triangles(std::vector<Vec3> vertices, std::vector<Tri> faces) {
  TriangleMesh m;
  m.vertices = std::move(vertices);
  m.faces = std::move(faces);
  return m;
}

}  // namespace

TEST(CountSelfIntersectionsTest, MatchesCgalOnManifoldMeshes) {
  TriangleMesh spheres = test::icosphere(3, 1.0);
  test::append(spheres,
               test::icosphere(3, 0.8, Vec3(1.2, 0.1, 0.05)));  // two closed spheres passing through each other
  const TriangleMesh crumpled = test::crumpled_icosphere(3, 0.05, 170);
  for (const TriangleMesh* m : std::initializer_list<const TriangleMesh*>{&spheres, &crumpled, &test::bunny()}) {
    const int64_t reference = cgal_count(*m);
    EXPECT_EQ(count_self_intersections(*m), reference);
  }
  EXPECT_GT(cgal_count(spheres), 0);
  EXPECT_GT(cgal_count(crumpled), 0);
}

TEST(CountSelfIntersectionsTest, MatchesAllPairsOnARandomSoup) {
  // 1,500 small triangles with their own vertices in the unit cube: every pair is tested by
  // CGAL's exact triangle-triangle predicate, without boxes or threads.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1), d(-0.04, 0.04);
  TriangleMesh soup;
  for (int32_t f = 0; f < 1500; ++f) {
    const Vec3 c(u(rng), u(rng), u(rng));
    for (int k = 0; k < 3; ++k) soup.vertices.push_back(c + Vec3(d(rng), d(rng), d(rng)));
    soup.faces.push_back({3 * f, 3 * f + 1, 3 * f + 2});
  }
  int64_t reference = 0;
  for (size_t a = 0; a < soup.faces.size(); ++a) {
    const Tri& s = soup.faces[a];
    const Kernel::Triangle_3 ta(point(soup, s[0]), point(soup, s[1]), point(soup, s[2]));
    for (size_t b = a + 1; b < soup.faces.size(); ++b) {
      const Tri& t = soup.faces[b];
      reference += CGAL::do_intersect(ta, Kernel::Triangle_3(point(soup, t[0]), point(soup, t[1]), point(soup, t[2])));
    }
  }
  EXPECT_GT(reference, 10);
  EXPECT_EQ(count_self_intersections(soup), reference);
}

TEST(CountSelfIntersectionsTest, SharedVerticesAndEdgesAreNotCrossings) {
  // A flat fan of six faces around vertex 0, and a hinge of two faces at a right angle.
  std::vector<Vec3> ring{Vec3::Zero()};
  std::vector<Tri> fan;
  for (int k = 0; k < 6; ++k) {
    ring.emplace_back(std::cos(k * M_PI / 3), std::sin(k * M_PI / 3), 0);
    fan.push_back({0, 1 + k, 1 + (k + 1) % 6});
  }
  EXPECT_EQ(count_self_intersections(triangles(ring, fan)), 0);
  const std::vector<Vec3> hinge{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  EXPECT_EQ(count_self_intersections(triangles(hinge, {{0, 1, 2}, {1, 0, 3}})), 0);
  // Two tetrahedra touching at one tip, a pinched vertex shared by index: no crossing. With the
  // tip given twice (two indices, one point), the faces meet at a point they do not share.
  std::vector<Vec3> tips{{0, 0, 0},      {1, 0.1, 0.1},   {1, -0.1, 0.1}, {1, 0, -0.1},
                         {-1, 0.1, 0.1}, {-1, -0.1, 0.1}, {-1, 0, -0.1}};
  const std::vector<Tri> shared{{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}, {0, 5, 4}, {0, 6, 5}, {0, 4, 6}, {4, 5, 6}};
  EXPECT_EQ(count_self_intersections(triangles(tips, shared)), 0);
  tips.push_back(tips[0]);
  std::vector<Tri> apart = shared;
  for (size_t f = 4; f < 7; ++f)
    for (int32_t& v : apart[f])
      if (v == 0) v = 7;
  EXPECT_EQ(count_self_intersections(triangles(tips, apart)), 9);  // each of 3 faces meets each of 3
}

TEST(CountSelfIntersectionsTest, FoldsCrossingsAndDegenerateFacesCount) {
  // Two faces on one edge folded onto the same side in one plane overlap: one pair.
  const std::vector<Vec3> fold{{0, 0, 0}, {1, 0, 0}, {0.3, 1, 0}, {0.6, 0.8, 0}};
  EXPECT_EQ(count_self_intersections(triangles(fold, {{0, 1, 2}, {1, 0, 3}})), 1);
  // Two faces sharing vertex 0, the second passing through the first: one pair.
  const std::vector<Vec3> through{{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0.5, 0.5, -1}, {0.5, 0.5, 1}};
  EXPECT_EQ(count_self_intersections(triangles(through, {{0, 1, 2}, {0, 3, 4}})), 1);
  // A face with collinear corners counts once, paired with itself.
  const std::vector<Vec3> line{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}};
  EXPECT_EQ(count_self_intersections(triangles(line, {{0, 1, 2}, {0, 1, 3}})), 1);
}
