// SPDX-License-Identifier: MIT
// Open inputs made of sheets that cross or meet each other, resolved into the surface a user
// touches, and the interior faces hdm check leaves out: checked by counting (no crossing left, CGAL's count; boundary,
// non-manifold and inconsistent edges), against analytic areas and volumes, and with Embree on the input (every face of
// the result lies on an input face).
#include <hdm/analysis/fidelity.h>
#include <hdm/mesh/open_self_intersections.h>
#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/mesh/stitch_seams.h>

#include "support/test_models.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <set>

using namespace hdm;
using test::signed_volume;

namespace {

// An n x n grid of the parallelogram origin + s u + t v, faces counter-clockwise seen from u x v.
void add_patch(TriangleMesh& m, const Vec3& origin, const Vec3& u, const Vec3& v, int n) {
  const auto base = static_cast<int32_t>(m.vertices.size());
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.vertices.push_back(origin + u * (double(i) / n) + v * (double(j) / n));
  auto id = [&](int i, int j) { return base + j * (n + 1) + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      m.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
}

// The unit cube [0,1]^3 as six separate patches (no shared vertex ids), outward, faces normal to
// x split 2 x 2, to y 4 x 4, to z 8 x 8: every cube edge is a T-junction seam.
TriangleMesh patch_cube() {
  TriangleMesh m;
  const Vec3 o = Vec3::Zero(), x = Vec3::UnitX(), y = Vec3::UnitY(), z = Vec3::UnitZ();
  add_patch(m, o, z, y, 2);
  add_patch(m, x, y, z, 2);
  add_patch(m, o, x, z, 4);
  add_patch(m, y, z, x, 4);
  add_patch(m, o, y, x, 8);
  add_patch(m, z, x, y, 8);
  return m;
}

// An open tube of radius r around the segment a -> b (n sides, one ring of quads per unit of
// length), faces outward.
void add_tube(TriangleMesh& m, const Vec3& a, const Vec3& b, double r, int n) {
  const Vec3 axis = (b - a).normalized();
  const Vec3 e1 = axis.unitOrthogonal(), e2 = axis.cross(e1);
  const int rings = std::max(1, int(std::ceil((b - a).norm() * 4)));
  const auto base = static_cast<int32_t>(m.vertices.size());
  for (int j = 0; j <= rings; ++j)
    for (int i = 0; i < n; ++i) {
      const double phi = 2 * std::numbers::pi * i / n;
      m.vertices.push_back(a + (b - a) * (double(j) / rings) + r * (std::cos(phi) * e1 + std::sin(phi) * e2));
    }
  auto id = [&](int i, int j) { return base + j * n + (i % n); };
  for (int j = 0; j < rings; ++j)
    for (int i = 0; i < n; ++i) {
      m.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
}

double area(const TriangleMesh& m) {
  double a = 0;
  for (const Tri& t : m.faces)
    a += 0.5 * (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).norm();
  return a;
}

// Every face of @p out lies on a face of @p in (its centroid and corners, exactly up to rounding).
void expect_on_input(const TriangleMesh& out, const TriangleMesh& in) {
  const ExactMeshQuery exact(in);
  const double tol = 1e-9 * bounds(in).diagonal();
  for (const Tri& t : out.faces) {
    const Vec3 c = (out.vertices[t[0]] + out.vertices[t[1]] + out.vertices[t[2]]) / 3;
    ASSERT_LT(exact.closest_point(c).distance, tol);
  }
}

// Closed, manifold, consistently oriented, enclosing the unit cube's volume.
void expect_unit_cube(const TriangleMesh& out) {
  const MeshTopology topo = analyze_topology(out);
  EXPECT_EQ(topo.boundary_edges, 0);
  EXPECT_EQ(topo.non_manifold_edges, 0);
  EXPECT_EQ(topo.inconsistent_edges, 0);
  EXPECT_NEAR(signed_volume(out), 1.0, 1e-12);
}

}  // namespace

TEST(StitchSeams, PatchCubeClosesAtItsTJunctions) {
  const TriangleMesh in = patch_cube();
  SeamReport rep;
  const TriangleMesh out = stitch_seams(in, &rep);
  // Boundary edges welded by position: each of the 12 cube edges has both sides' edges, 4 of
  // x-y (2 + 4 edges), 4 of x-z (2 + 8), 4 of y-z (4 + 8).
  EXPECT_EQ(rep.boundary_edges_before, 4 * (2 + 4) + 4 * (2 + 8) + 4 * (4 + 8));
  // The fine side's vertices not on the coarse side: 4 x (4 - 2) + 4 x (8 - 2) + 4 x (8 - 4).
  EXPECT_EQ(rep.inserted, 4 * 2 + 4 * 6 + 4 * 4);
  EXPECT_EQ(rep.boundary_edges_after, 0);
  expect_unit_cube(out);
  EXPECT_NEAR(area(out), 6.0, 1e-12);
  // No vertex moved: one per distinct input position, plus the centroid of each face with hanging
  // vertices on two of its edges (the corner triangles (1,0) and (0,1) of the two 2 x 2 patches).
  std::set<std::array<double, 3>> positions;
  for (const Vec3& p : in.vertices) positions.insert({p.x(), p.y(), p.z()});
  EXPECT_EQ(out.vertices.size(), positions.size() + 4);
}

TEST(StitchSeams, LeavesSeparateSheetsAlone) {
  TriangleMesh in;
  add_patch(in, Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY(), 3);
  add_patch(in, Vec3(0, 0, 0.5), Vec3::UnitX(), Vec3::UnitY(), 4);  // parallel, half a unit above
  SeamReport rep;
  const TriangleMesh out = stitch_seams(in, &rep);
  EXPECT_EQ(rep.inserted, 0);
  EXPECT_EQ(out.faces.size(), in.faces.size());
  EXPECT_EQ(rep.boundary_edges_after, 4 * 3 + 4 * 4);
}

TEST(OpenSelfIntersections, PatchCubeWithTJunctionsBecomesOneClosedSurface) {
  // The hanging vertices lie on the coarse patches' edges: CGAL counts the touching faces of
  // different patches as intersecting face pairs.
  const TriangleMesh in = patch_cube();
  SelfIntersectionReport rep;
  const TriangleMesh out = resolve_open_self_intersections(in, &rep);
  EXPECT_GT(rep.pairs_before, 0);
  ASSERT_TRUE(rep.resolved);
  EXPECT_EQ(rep.pairs_after, 0);
  EXPECT_EQ(rep.seam_vertices, 48);
  expect_unit_cube(out);
}

TEST(OpenSelfIntersections, TwoOpenTubesPushedIntoABoxLeaveTheBoxWhereTheyEnter) {
  // Box [-1,1]^3 (closed, a patch of 4 x 4 per side) and two open tubes, each with one end inside
  // the box and the other outside: the result is the box with two holes, the tubes outside it.
  TriangleMesh in;
  const Vec3 o(-1, -1, -1);
  const Vec3 x(2, 0, 0), y(0, 2, 0), z(0, 0, 2);
  add_patch(in, o, z, y, 4);
  add_patch(in, o + x, y, z, 4);
  add_patch(in, o, x, z, 4);
  add_patch(in, o + y, z, x, 4);
  add_patch(in, o, y, x, 4);
  add_patch(in, o + z, x, y, 4);
  const int n = 16;
  const double r = 0.3;
  add_tube(in, Vec3(0.2, 0.1, 0.05), Vec3(2.2, 0.1, 0.05), r, n);  // along +x, out through x = 1
  add_tube(in, Vec3(-0.5, 0.1, 0.4), Vec3(-0.5, 0.1, 2.4), r, n);  // along +z, out through z = 1
  // hdm check's rule for the input's own faces (interior_faces(), the winding number in front of a
  // face): a tube face wholly inside the box is interior, a face wholly outside every part is not.
  const std::vector<uint8_t> interior = interior_faces(ExactMeshQuery(in));
  const size_t box_faces = 6 * 2 * 16;
  auto in_box = [](const Vec3& p) { return p.cwiseAbs().maxCoeff() < 1 - 1e-9; };
  // Near a tube: within its radius plus a box triangle's circumradius (0.36) of its axis.
  auto near_tube = [&](const Vec3& p) {
    return (std::hypot(p.y() - 0.1, p.z() - 0.05) < r + 0.36 && p.x() > 0.2 - 0.36) ||
           (std::hypot(p.x() + 0.5, p.y() - 0.1) < r + 0.36 && p.z() > 0.4 - 0.36);
  };
  int inside = 0, outside = 0;
  for (size_t f = 0; f < in.faces.size(); ++f) {
    const Tri& t = in.faces[f];
    const bool all_in = in_box(in.vertices[t[0]]) && in_box(in.vertices[t[1]]) && in_box(in.vertices[t[2]]);
    const bool none_in = !in_box(in.vertices[t[0]]) && !in_box(in.vertices[t[1]]) && !in_box(in.vertices[t[2]]);
    if (f >= box_faces && all_in) {
      EXPECT_TRUE(interior[f]) << f;
      ++inside;
    }
    if (f >= box_faces && none_in) {
      EXPECT_FALSE(interior[f]) << f;
      ++outside;
    }
    if (f < box_faces && !near_tube(in.vertices[t[0]]) && !near_tube(in.vertices[t[1]]) &&
        !near_tube(in.vertices[t[2]])) {
      EXPECT_FALSE(interior[f]) << f;
      ++outside;
    }
  }
  EXPECT_GT(inside, 100);
  EXPECT_GT(outside, 300);
  SelfIntersectionReport rep;
  const TriangleMesh out = resolve_open_self_intersections(in, &rep);
  ASSERT_TRUE(rep.resolved);
  EXPECT_EQ(rep.pairs_after, 0);
  const MeshTopology topo = analyze_topology(out);
  EXPECT_EQ(topo.non_manifold_edges, 0);
  EXPECT_EQ(topo.inconsistent_edges, 0);
  // The tubes' outer rims stay open; the inner ends are inside the box.
  EXPECT_EQ(topo.boundary_edges, 2 * n);
  // Analytic area: the box less the two n-gon holes, plus the tubes' 1.2 and 1.4 units outside it.
  const double ngon = n / 2.0 * r * r * std::sin(2 * std::numbers::pi / n),
               perimeter = n * 2 * r * std::sin(std::numbers::pi / n);
  EXPECT_NEAR(area(out), 24 - 2 * ngon + (1.2 + 1.4) * perimeter, 1e-9);
  expect_on_input(out, in);
}

TEST(OpenSelfIntersections, TwoCrossingFlatSheetsHaveNoInsideAndAreKept) {
  // A "+" of two open squares: in front of every face is outside, so all four half-sheets stay
  // and would meet four to an edge: the input is kept, as documented.
  TriangleMesh in;
  add_patch(in, Vec3(-1, -1, 0), Vec3(2, 0, 0), Vec3(0, 2, 0), 5);
  add_patch(in, Vec3(-1, 0, -1), Vec3(0, 0, 2), Vec3(2, 0, 0), 5);
  SelfIntersectionReport rep;
  const TriangleMesh out = resolve_open_self_intersections(in, &rep);
  EXPECT_GT(rep.pairs_before, 0);
  EXPECT_FALSE(rep.resolved);
  EXPECT_EQ(rep.pairs_after, rep.pairs_before);
  EXPECT_EQ(out.faces.size(), in.faces.size());
  EXPECT_EQ(out.vertices, in.vertices);
}

TEST(OpenSelfIntersections, CrumpledFlatSheetIsTriangulatedAgain) {
  // An 8 x 8 grid of the unit square (one open sheet) with one inner vertex dragged in the plane
  // past its right-hand neighbour: its faces fold over their neighbours (a crumpled
  // triangulation). The surface is still the flat square: the crumpled spot is cut out and
  // triangulated again, so nothing crosses, the square's border is kept, the area is exactly 1,
  // and every face faces +z.
  const int n = 8;
  TriangleMesh in;
  add_patch(in, Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY(), n);
  in.vertices[4 * (n + 1) + 4] = Vec3(5.5 / n, 4.4 / n, 0);
  ASSERT_GT(count_self_intersections(in), 0);
  SelfIntersectionReport rep;
  const TriangleMesh out = resolve_open_self_intersections(in, &rep);
  ASSERT_TRUE(rep.resolved);
  EXPECT_GT(rep.retriangulated_faces, 0);
  EXPECT_EQ(count_self_intersections(out), 0);
  const MeshTopology topo = analyze_topology(out);
  EXPECT_EQ(topo.non_manifold_edges, 0);
  EXPECT_EQ(topo.inconsistent_edges, 0);
  EXPECT_EQ(topo.boundary_edges, 4 * n);
  EXPECT_NEAR(area(out), 1.0, 1e-12);
  for (const Tri& t : out.faces) {
    const Vec3 normal = (out.vertices[t[1]] - out.vertices[t[0]]).cross(out.vertices[t[2]] - out.vertices[t[0]]);
    EXPECT_GT(normal.z(), 0);
    EXPECT_NEAR(normal.x(), 0, 1e-15);
    EXPECT_NEAR(normal.y(), 0, 1e-15);
  }
  expect_on_input(out, in);
}

TEST(OpenSelfIntersections, SheetPassingThroughItselfIsKept) {
  // The "+" of two open squares above, joined into one sheet by a strip from the edge y = 1 of
  // the horizontal square to the edge z = 1 of the vertical one: a part of the sheet passes
  // through another along the whole x axis. Cutting the crossing out would move the surface far
  // more than 0.1 % of the diagonal, so the input is kept.
  const int n = 6;
  TriangleMesh in;
  add_patch(in, Vec3(-1, -1, 0), Vec3(2, 0, 0), Vec3(0, 2, 0), n);
  const auto second = static_cast<int32_t>(in.vertices.size());
  add_patch(in, Vec3(-1, 0, -1), Vec3(0, 0, 2), Vec3(2, 0, 0), n);
  auto a = [&](int k) { return n * (n + 1) + k; };           // (x = -1 + 2k/n, 1, 0)
  auto b = [&](int k) { return second + k * (n + 1) + n; };  // (x = -1 + 2k/n, 0, 1)
  for (int k = 0; k < n; ++k) {
    in.faces.push_back({a(k), b(k + 1), a(k + 1)});
    in.faces.push_back({a(k), b(k), b(k + 1)});
  }
  ASSERT_EQ(analyze_topology(in).non_manifold_edges, 0);
  const int64_t before = count_self_intersections(in);
  ASSERT_GT(before, 0);
  SelfIntersectionReport rep;
  const TriangleMesh out = resolve_open_self_intersections(in, &rep);
  EXPECT_FALSE(rep.resolved);
  EXPECT_EQ(rep.pairs_after, before);
  EXPECT_EQ(out.faces.size(), in.faces.size());
  EXPECT_EQ(out.vertices, in.vertices);
}

TEST(OpenSelfIntersections, ACrossingThatRoundsToZeroAreaFacesIsNotCorefinedFurther) {
  // Three sheets on a ground plane y = 0: a quad, a triangle that dips 7.8e-5 below it (its
  // crossing with the quad is so short that the corefined quad's new faces round to zero area)
  // and a decal quad lying on the quad over that crossing. Corefining the decal with the quad's
  // zero-area faces dereferences the crossing of two edge lines that do not cross (CGAL 5.5,
  // Intersect_coplanar_faces_3): the resolution must stop before it and keep a valid surface.
  TriangleMesh in;
  in.vertices = {
      Vec3(1.0 / 150, 0, 149.0 / 150), Vec3(0.995, 0, 0.995), Vec3(149.0 / 150, 0, 1.0 / 150), Vec3(0.005, 0, 0.005),
      // the dipping triangle, at the single-precision coordinates that round as above
      Vec3(0.63258302211761475, 0.074843399226665497, 0.36741697788238525), Vec3(0.5, 0.074843399226665497, 0.3125),
      Vec3(0.63258302211761475, -7.8000128269195557e-05, 0.36741697788238525), Vec3(0.55, 0, 0.3), Vec3(0.55, 0, 0.45),
      Vec3(0.7, 0, 0.45), Vec3(0.7, 0, 0.3)};
  in.faces = {{0, 1, 2}, {0, 2, 3}, {6, 5, 4}, {7, 8, 9}, {7, 9, 10}};
  ASSERT_GT(count_self_intersections(in), 0);
  SelfIntersectionReport rep;
  const TriangleMesh out = resolve_open_self_intersections(in, &rep);
  const MeshTopology t = analyze_topology(out);
  EXPECT_EQ(t.non_manifold_edges, 0);
  EXPECT_EQ(t.degenerate_faces, 0);
  if (rep.resolved)
    EXPECT_EQ(count_self_intersections(out), 0);
  else
    EXPECT_EQ(out.faces.size(), in.faces.size());
}
