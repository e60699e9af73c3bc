// SPDX-License-Identifier: MIT
// Polygons of the mesh readers, against references computed here: the triangles of a polygon sum
// to its shoelace area, each centroid lies inside it by a ray-crossing test, each normal keeps the
// polygon's winding; a polygon with a hole written as one outline keeps its hole; repeated corners
// and cycles, short faces and self-crossing polygons are skipped or read once, with a warning.
#include "io/mesh_test_util.h"

#include <hdm/core/error.h>
#include <hdm/io/read_mesh.h>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace hdm {
namespace {

using test::canonical;
using test::error_of;
using test::has;
using test::inside;
using test::polygon_obj;
using test::shoelace;

// An OBJ of @p vertices and one face through the 1-based @p ids (corners may repeat a vertex).
std::string face_obj(const std::vector<Vec3>& vertices, const std::vector<int>& ids) {
  std::ostringstream s;
  s.precision(17);
  for (const Vec3& v : vertices) s << "v " << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
  s << 'f';
  for (int i : ids) s << ' ' << i;
  s << '\n';
  return s.str();
}

// Checks that @p m tiles the polygon @p outline of the z = 0 plane (its corners in order, with
// repeats where the outline runs along an edge twice): @p triangles triangles, each wound as the
// outline (the sign of its shoelace area), each centroid inside by the even-odd rule, their areas
// summing to @p area (the shoelace area unless given).
void expect_tiles(const TriangleMesh& m, const std::vector<Vec3>& outline, size_t triangles, const std::string& what,
                  double area = std::nan("")) {
  if (std::isnan(area)) area = shoelace(outline);
  EXPECT_EQ(m.faces.size(), triangles) << what;
  double sum = 0;
  for (const Tri& f : m.faces) {
    const Vec3 a = m.vertices[f[0]], b = m.vertices[f[1]], c = m.vertices[f[2]];
    const double z = (b - a).cross(c - a).z();
    EXPECT_GT(z * area, 0) << what << ": a triangle is flipped or flat";
    sum += 0.5 * z;
    EXPECT_TRUE(inside(outline, (a + b + c) / 3)) << what << ": a triangle lies outside the polygon";
  }
  // The readers round coordinates to float, so the tiles' area may differ from the exact
  // outline's by float rounding (~1e-8 relative here); a missing or doubled tile is far more.
  EXPECT_NEAR(sum, area, 1e-6 * std::abs(area)) << what;
}

void expect_tiles(const std::vector<Vec3>& poly, const std::string& what) {
  expect_tiles(read_mesh_from_memory(polygon_obj(poly), what + ".obj"), poly, poly.size() - 2, what);
}

std::vector<Vec3> star(int corners, double inner, double outer, std::mt19937* jitter = nullptr) {
  std::uniform_real_distribution<double> r(0.5, 1.0);
  std::vector<Vec3> p;
  for (int k = 0; k < corners; ++k) {
    const double a = 2 * std::numbers::pi * k / corners, radius = (k % 2 ? inner : outer) * (jitter ? r(*jitter) : 1.0);
    p.emplace_back(radius * std::cos(a), radius * std::sin(a), 0);
  }
  return p;
}

TEST(MeshReaders, TriangulatesConcavePolygonsInsideTheirOutline) {
  // An arrowhead quad (reflex corner at index 2; a fan from corner 0 would cover the notch).
  expect_tiles({Vec3(0, 0, 0), Vec3(2, 1, 0), Vec3(0.5, 1, 0), Vec3(0, 2, 0)}, "dart");
  expect_tiles({Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 2, 0), Vec3(0.5, 1, 0), Vec3(0, 2, 0)}, "notch");
  // A U of 8 corners and a 12-pointed star (24 corners, 12 reflex).
  expect_tiles({Vec3(0, 0, 0), Vec3(3, 0, 0), Vec3(3, 3, 0), Vec3(2, 3, 0), Vec3(2, 1, 0), Vec3(1, 1, 0), Vec3(1, 3, 0),
                Vec3(0, 3, 0)},
               "u");
  expect_tiles(star(24, 0.4, 1.0), "star");
  // A convex 1000-gon is fanned in linear time.
  std::vector<Vec3> circle;
  for (int k = 0; k < 1000; ++k)
    circle.emplace_back(std::cos(2 * std::numbers::pi * k / 1000), std::sin(2 * std::numbers::pi * k / 1000), 0);
  expect_tiles(circle, "circle");
  // Concave polygons of any size: 66 corners (the size of assimp's concave_polygon.obj), and
  // 4,000 corners with random radii.
  expect_tiles(star(66, 0.4, 1.0), "star66");
  std::mt19937 rng(7);
  expect_tiles(star(4000, 0.3, 1.0, &rng), "star4000");
  // Collinear corners along the edges of a concave outline (each is a corner of the tiles).
  expect_tiles({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(3, 0, 0), Vec3(3, 3, 0), Vec3(2, 3, 0), Vec3(2, 2, 0),
                Vec3(1, 2, 0), Vec3(1, 3, 0), Vec3(0, 3, 0), Vec3(0, 2, 0), Vec3(0, 1, 0)},
               "collinear");
}

TEST(MeshReaders, ClockwisePolygonsStayClockwise) {
  std::vector<Vec3> cw = star(30, 0.5, 1.0);
  std::reverse(cw.begin(), cw.end());
  ASSERT_LT(shoelace(cw), 0);
  expect_tiles(cw, "clockwise_star");
}

// A square with a square hole written as one outline: round the outer square, along a bridge to
// the hole, round the hole the other way, back along the bridge (as LightWave writes such faces).
// Eight vertices around one hole: 8 triangles (n + 2h - 2), area 10² - 4².
TEST(MeshReaders, APolygonWithAHoleWrittenAsOneOutlineKeepsTheHole) {
  const std::vector<Vec3> v = {Vec3(0, 0, 0), Vec3(10, 0, 0), Vec3(10, 10, 0), Vec3(0, 10, 0),
                               Vec3(3, 3, 0), Vec3(3, 7, 0),  Vec3(7, 7, 0),   Vec3(7, 3, 0)};
  auto outline = [&](const std::vector<int>& ids) {
    std::vector<Vec3> p;
    for (int i : ids) p.push_back(v[i - 1]);
    return p;
  };
  const std::vector<int> keyhole = {1, 2, 3, 4, 1, 5, 6, 7, 8, 5};
  const TriangleMesh m = read_mesh_from_memory(face_obj(v, keyhole), "keyhole.obj");
  ASSERT_NEAR(shoelace(outline(keyhole)), 84.0, 1e-12) << "the test's outline";
  expect_tiles(m, outline(keyhole), 8, "keyhole");
  // The hole run the same way as the outer square: inside is odd nesting, so still a hole
  // (the shoelace formula would count it twice instead: 100 + 16).
  const std::vector<int> same_way = {1, 2, 3, 4, 1, 5, 8, 7, 6, 5};
  expect_tiles(read_mesh_from_memory(face_obj(v, same_way), "same_way.obj"), outline(same_way), 8, "same_way", 84.0);
  // The bridge's ends written as other vertices at the same positions: the same tiles.
  std::vector<Vec3> copies = v;
  copies.push_back(v[0]);
  copies.push_back(v[4]);
  const TriangleMesh c = read_mesh_from_memory(face_obj(copies, {1, 2, 3, 4, 9, 5, 6, 7, 8, 10}), "copies.obj");
  EXPECT_EQ(canonical(c), canonical(m));
}

// A concave polygon in a plane through no axis, both ways round: every triangle's normal points
// along the polygon's own normal (winding kept), and in the plane's coordinates the tiles are
// those of the planar polygon.
TEST(MeshReaders, TriangulationKeepsTheWindingInAnyPlane) {
  std::mt19937 rng(11);
  const std::vector<Vec3> flat = star(40, 0.35, 1.0, &rng);
  const Vec3 u = Vec3(1, 2, 2).normalized(), w = Vec3(2, -2, 1).normalized();  // orthonormal
  const Vec3 normal = u.cross(w), origin(0.25, -0.5, 3);
  for (bool reversed : {false, true}) {
    std::vector<Vec3> plane2d = flat;
    if (reversed) std::reverse(plane2d.begin(), plane2d.end());
    std::vector<Vec3> in3d;
    for (const Vec3& p : plane2d) in3d.push_back(origin + p.x() * u + p.y() * w);
    const TriangleMesh m = read_mesh_from_memory(polygon_obj(in3d), "tilted.obj");
    TriangleMesh back = m;  // the mesh in the plane's coordinates
    for (Vec3& p : back.vertices) p = Vec3((p - origin).dot(u), (p - origin).dot(w), 0);
    expect_tiles(back, plane2d, plane2d.size() - 2, reversed ? "tilted_clockwise" : "tilted");
    for (const Tri& f : m.faces) {
      const Vec3 n = (m.vertices[f[1]] - m.vertices[f[0]]).cross(m.vertices[f[2]] - m.vertices[f[0]]);
      EXPECT_GT(n.dot(normal) * shoelace(plane2d), 0);
    }
  }
}

TEST(MeshReaders, RepeatedCornersAndCyclesAreReadOnce) {
  const std::string v = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";
  const auto square = canonical(read_mesh_from_memory(v + "f 1 2 3 4\n", "square.obj"));
  ASSERT_EQ(square.size(), 2u);
  // The cycle written 100 times on one line (as assimp's box_longline.obj).
  std::string cycles = v + "\nf";
  for (int k = 0; k < 100; ++k) cycles += " 1 2 3 4";
  MeshReadReport report;
  EXPECT_EQ(canonical(read_mesh_from_memory(cycles + "\n", "cycles.obj", {}, &report)), square);
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_TRUE(has(report.warnings[0], "cycles.obj:6: a polygon of 400 corners is a cycle of 4 corners written 100 times"))
      << report.warnings[0];
  // Corners repeated in a row, the last one repeating the first.
  report.warnings.clear();
  EXPECT_EQ(canonical(read_mesh_from_memory(v + "f 1 1 2 3 3 3 4 1\n", "repeats.obj", {}, &report)), square);
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_TRUE(has(report.warnings[0], "repeats.obj:5: 1 polygon repeats a corner in a row")) << report.warnings[0];
  // Both: a cycle of repeated corners written twice.
  report.warnings.clear();
  EXPECT_EQ(canonical(read_mesh_from_memory(v + "f 1 1 2 3 4 1 2 2 3 4\n", "both.obj", {}, &report)), square);
  EXPECT_EQ(report.warnings.size(), 2u);
}

TEST(MeshReaders, FacesOfFewerThanThreeCornersAreSkippedWithAWarning) {
  MeshReadReport report;
  const TriangleMesh m = read_mesh_from_memory(
      "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n2 0 1\n1 3\n4 0 3 3 0\n", "short.off", {}, &report);
  EXPECT_EQ(m.faces.size(), 1u);
  ASSERT_EQ(report.warnings.size(), 2u);
  EXPECT_TRUE(has(report.warnings[0], "short.off:8: skipped 3 faces of fewer than three distinct corners (the first here)"))
      << report.warnings[0];
  EXPECT_TRUE(has(report.warnings[1], "short.off:10: 1 polygon repeats a corner in a row")) << report.warnings[1];
  EXPECT_TRUE(has(error_of<InvalidInput>("v 0 0 0\nv 1 0 0\nf 1 2\nf 2 1 2 1\n", "two.obj"),
                  "two.obj: holds no triangles: 2 faces of fewer than three corners (2 vertices)"));
}

TEST(MeshReaders, PolygonsThatCrossThemselvesAreSkippedWithAWarning) {
  // A pentagram (every turn to the left, but twice around), a bowtie quad and an outline whose
  // edge from (3,0) to (2,0) runs along its first edge, beside a triangle.
  std::ostringstream s;
  for (int k = 0; k < 5; ++k)
    s << "v " << std::cos(4 * std::numbers::pi * k / 5) << ' ' << std::sin(4 * std::numbers::pi * k / 5) << " 0\n";
  s << "v 0 0 1\nv 1 1 1\nv 1 0 1\nv 0 1 1\n";
  s << "v 0 0 2\nv 4 0 2\nv 4 2 2\nv 3 0 2\nv 2 0 2\nv 0 2 2\n";
  const std::string v = s.str();
  MeshReadReport report;
  const TriangleMesh m = read_mesh_from_memory(v + "f 1 2 3 4 5\nf 6 7 8 9\nf 10 11 12 13 14 15\nf 6 8 7\n",
                                               "crossing.obj", {}, &report);
  EXPECT_EQ(m.faces.size(), 1u);
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_TRUE(has(report.warnings[0], "crossing.obj:16: skipped 3 polygons whose edges cross or overlap in their "
                                      "best-fit planes (the first here, of 5 corners)"))
      << report.warnings[0];
  EXPECT_TRUE(has(error_of<InvalidInput>(v + "f 1 2 3 4 5\n", "pentagram.obj"),
                  "pentagram.obj: holds no triangles: 1 polygon that crosses itself (15 vertices)"));
  // A corner on another edge is no crossing: two triangles touching at (2,0), 4 + 4 in area.
  const std::vector<Vec3> touching = {Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(4, 4, 0), Vec3(2, 0, 0), Vec3(0, 4, 0)};
  expect_tiles(read_mesh_from_memory(polygon_obj(touching), "touching.obj"), touching, 2, "touching", 8.0);
}

}  // namespace
}  // namespace hdm
