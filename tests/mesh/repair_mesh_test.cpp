// SPDX-License-Identifier: MIT
// Dirty-scan repair: each defect is made on a clean real or analytic mesh, so the clean mesh is the
// independent reference (positions, volume, exact distance with Embree).
#include "support/test_models.h"

#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/core/error.h>
#include <hdm/io/read_mesh.h>
#include <hdm/mesh/repair_mesh.h>
#include <hdm/mesh/self_intersections.h>
#include <hdm/slab/bake.h>

#include <gtest/gtest.h>

#include <numbers>
#include <random>
#include <set>

using namespace hdm;
using test::signed_volume;

namespace {

void expect_clean_and_closed(const TriangleMesh& m) {
  const MeshTopology t = analyze_topology(m);
  EXPECT_EQ(t.boundary_edges, 0);
  EXPECT_EQ(t.non_manifold_edges, 0);
  EXPECT_EQ(t.inconsistent_edges, 0);
  EXPECT_EQ(t.degenerate_faces, 0);
  EXPECT_NO_THROW(validate_for_bake(m, "repaired"));
}

}  // namespace

TEST(RepairMesh, TriangleSoupIsWeldedBackToTheScan) {
  const TriangleMesh& bunny = test::bunny();
  TriangleMesh soup;  // every face with its own three vertices, plus a duplicated face
  for (const Tri& t : bunny.faces) {
    const auto k = static_cast<int32_t>(soup.vertices.size());
    for (int32_t v : t) soup.vertices.push_back(bunny.vertices[v]);
    soup.faces.push_back({k, k + 1, k + 2});
  }
  soup.faces.push_back(soup.faces[7]);
  ASSERT_TRUE(needs_repair(soup));
  RepairReport r;
  const TriangleMesh out = repair_mesh(soup, "soup", {}, &r);
  EXPECT_EQ(out.vertices.size(), bunny.vertices.size());
  EXPECT_EQ(out.faces.size(), bunny.faces.size());
  EXPECT_EQ(r.removed_faces, 1);
  EXPECT_EQ(r.merged_vertices, int64_t(soup.vertices.size() - bunny.vertices.size()));
  expect_clean_and_closed(out);
  EXPECT_NEAR(signed_volume(out), signed_volume(bunny), 1e-9 * std::abs(signed_volume(bunny)));
}

TEST(RepairMesh, FlippedFacesAreOrientedOutward) {
  TriangleMesh m = test::bunny();
  std::mt19937 rng(3);
  int flipped = 0;
  for (Tri& t : m.faces)
    if (rng() % 10 == 0) std::swap(t[1], t[2]), ++flipped;
  ASSERT_GT(analyze_topology(m).inconsistent_edges, 0);
  EXPECT_THROW(validate_for_bake(m, "flipped.off"), InvalidInput) << "without repair the defect is refused";
  RepairReport r;
  const TriangleMesh out = repair_mesh(m, "flipped", {}, &r);
  expect_clean_and_closed(out);
  EXPECT_EQ(r.flipped_faces, flipped);
  EXPECT_NEAR(signed_volume(out), signed_volume(test::bunny()), 1e-9 * std::abs(signed_volume(test::bunny())));
}

TEST(RepairMesh, InsideOutClosedMeshIsTurnedOutward) {
  TriangleMesh m = test::icosphere(3, 1.0);
  for (Tri& t : m.faces) std::swap(t[1], t[2]);
  ASSERT_LT(signed_volume(m), 0);
  const TriangleMesh out = repair_mesh(m, "inside-out");
  EXPECT_GT(signed_volume(out), 0);
  expect_clean_and_closed(out);
}

TEST(RepairMesh, ZeroAreaAndRepeatedVertexFacesAreRemoved) {
  TriangleMesh m = test::icosphere(3, 1.0);
  // Split edge (a, b) of face (a, b, c) at its midpoint x: (a, x, c), (x, b, c), and the sliver
  // (a, b, x) of zero area closes the gap against the neighbour (b, a, d). Plus a face (a, a, b).
  const Tri f = m.faces[0];
  const auto x = static_cast<int32_t>(m.vertices.size());
  m.vertices.push_back(0.5 * (m.vertices[f[0]] + m.vertices[f[1]]));
  m.faces[0] = {f[0], x, f[2]};
  m.faces.push_back({x, f[1], f[2]});
  m.faces.push_back({f[0], f[1], x});
  m.faces.push_back({f[0], f[0], f[1]});
  ASSERT_GE(analyze_topology(m).degenerate_faces, 2);
  RepairReport r;
  const TriangleMesh out = repair_mesh(m, "slivers", {}, &r);
  EXPECT_GE(r.removed_faces, 2);
  expect_clean_and_closed(out);
  EXPECT_NEAR(signed_volume(out), signed_volume(test::icosphere(3, 1.0)), 1e-9);
}

TEST(RepairMesh, SmallHolesAreFilledOnTheSurfaceAndOpenBoundariesKept) {
  // Remove the one-rings of a few bunny vertices: holes of about six edges.
  const TriangleMesh& bunny = test::bunny();
  std::set<int32_t> centres = {100, 20000, 31000};
  TriangleMesh m;
  m.vertices = bunny.vertices;
  for (const Tri& t : bunny.faces)
    if (!centres.count(t[0]) && !centres.count(t[1]) && !centres.count(t[2])) m.faces.push_back(t);
  RepairReport r;
  const TriangleMesh out = repair_mesh(m, "holes", {}, &r);
  EXPECT_EQ(r.filled_holes, 3);
  EXPECT_EQ(r.open_boundaries, 0);
  expect_clean_and_closed(out);
  // The patches lie close to the removed surface (exact distance on the clean scan).
  const ExactMeshQuery exact(bunny);
  const double diag = bounds(bunny).diagonal();
  for (const Vec3& v : out.vertices) EXPECT_LT(exact.closest_point(v).distance, 2e-3 * diag);

  // A bust's neck cut is a boundary, not a hole: lion-head.off keeps it.
  RepairReport lr;
  const TriangleMesh lion = repair_mesh(read_mesh(test::data_path("lion-head.off")), "lion-head.off", {}, &lr);
  EXPECT_EQ(lr.filled_holes, 0);
  EXPECT_EQ(lr.open_boundaries, 1);
  EXPECT_GT(analyze_topology(lion).boundary_edges, 0);
}

TEST(RepairMesh, APatchWithNoInteriorVertexStaysOpenAndHolesAreStillFilled) {
  // Four parts far apart (CAD debris as in b9_mesh.off): a sphere with a face missing (a hole), a
  // lone triangle and a strip of three triangles (no interior vertex: their boundary is their
  // outline, its fill would be a back-to-back copy enclosing nothing), and a hexagonal pyramid
  // without its base (the apex is interior: the base is a hole, filled into a closed pyramid).
  TriangleMesh m = test::icosphere(3, 1.0);
  const size_t sphere_faces = m.faces.size() - 1;
  m.faces.erase(m.faces.begin());
  auto add = [&](const Vec3& p) {
    m.vertices.push_back(p);
    return static_cast<int32_t>(m.vertices.size() - 1);
  };
  const int32_t a = add({5, 0, 0}), b = add({5.3, 0, 0}), c = add({5, 0.3, 0.1});
  m.faces.push_back({a, b, c});
  const int32_t s0 = add({10, 0, 0}), s1 = add({10, 0.2, 0}), s2 = add({10.2, 0, 0.05}), s3 = add({10.2, 0.2, 0}),
                s4 = add({10.4, 0, 0});
  m.faces.push_back({s0, s2, s1});
  m.faces.push_back({s1, s2, s3});
  m.faces.push_back({s2, s4, s3});
  const double r = 0.3, h = 0.2;
  const int32_t apex = add({15, 0, h});
  int32_t ring[6];
  for (int k = 0; k < 6; ++k)
    ring[k] = add({15 + r * std::cos(k * std::numbers::pi / 3), r * std::sin(k * std::numbers::pi / 3), 0});
  for (int k = 0; k < 6; ++k) m.faces.push_back({apex, ring[k], ring[(k + 1) % 6]});
  ASSERT_EQ(analyze_topology(m).boundary_edges, 3 + 3 + 5 + 6);

  RepairReport rep;
  const TriangleMesh out = repair_mesh(m, "debris", {}, &rep);
  EXPECT_EQ(rep.filled_holes, 2);     // the sphere's hole and the pyramid's base
  EXPECT_EQ(rep.open_boundaries, 2);  // the triangle's and the strip's outlines
  const MeshTopology t = analyze_topology(out);
  EXPECT_EQ(t.boundary_edges, 3 + 5);
  EXPECT_EQ(t.non_manifold_edges, 0);
  EXPECT_EQ(t.inconsistent_edges, 0);
  EXPECT_EQ(count_self_intersections(out), 0) << "no face back to back with another";
  // Faces per part, by position: the triangle and the strip as they were.
  size_t sphere = 0, lone = 0, strip = 0, pyramid = 0;
  double pyramid_volume = 0;
  for (const Tri& f : out.faces) {
    const double x = out.vertices[f[0]].x();
    if (x < 2)
      ++sphere;
    else if (x < 7)
      ++lone;
    else if (x < 12)
      ++strip;
    else {
      ++pyramid;
      const Vec3 o(15, 0, 0);  // divergence theorem about a point of the part
      pyramid_volume += (out.vertices[f[0]] - o).dot((out.vertices[f[1]] - o).cross(out.vertices[f[2]] - o)) / 6;
    }
  }
  EXPECT_GT(sphere, sphere_faces);
  EXPECT_EQ(lone, 1u);
  EXPECT_EQ(strip, 3u);
  EXPECT_GE(pyramid, 10u);
  // Closed and outward: (1/3) base area * height, base a regular hexagon of circumradius r.
  EXPECT_NEAR(std::abs(pyramid_volume), (3 * std::sqrt(3.0) / 2 * r * r) * h / 3, 1e-9);
}

TEST(RepairMesh, BadInputIsRefusedWithTheNameAndReason) {
  TriangleMesh m = test::icosphere(1, 1.0);
  m.vertices[3].x() = NAN;
  try {
    repair_mesh(m, "nan.off");
    FAIL() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("nan.off"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("non-finite"), std::string::npos);
  }
  TriangleMesh only_slivers;
  only_slivers.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)};
  only_slivers.faces = {{0, 1, 2}, {0, 0, 1}};
  EXPECT_THROW(repair_mesh(only_slivers, "slivers.off"), InvalidInput);
}

namespace {

// @p m without the faces that use a vertex of @p removed.
TriangleMesh without_faces_at(const TriangleMesh& m, const std::set<int32_t>& removed) {
  TriangleMesh out;
  out.vertices = m.vertices;
  for (const Tri& t : m.faces)
    if (!removed.count(t[0]) && !removed.count(t[1]) && !removed.count(t[2])) out.faces.push_back(t);
  return out;
}

// The one-ring neighbours of vertex @p v.
std::set<int32_t> ring(const TriangleMesh& m, int32_t v) {
  std::set<int32_t> r;
  for (const Tri& t : m.faces)
    if (t[0] == v || t[1] == v || t[2] == v)
      for (int32_t w : t)
        if (w != v) r.insert(w);
  return r;
}

}  // namespace

TEST(RepairMesh, HolesThatTouchAtAVertexAreFilledIntoOneManifoldVertex) {
  // Two faces of one star removed, on either side of its centre: two triangular holes that share
  // that vertex (a pinch, as where elephant-with-holes.off's holes meet). Filled, the sphere is
  // whole again: the same vertices, closed, nothing crossing.
  const TriangleMesh sphere = test::icosphere(3, 1.0);
  std::vector<size_t> star;
  for (size_t f = 0; f < sphere.faces.size(); ++f)
    for (int32_t w : sphere.faces[f])
      if (w == 0) star.push_back(f);
  ASSERT_GE(star.size(), 5u);
  // Two faces of the star that share only vertex 0.
  size_t a = star[0], b = star[0];
  for (size_t f : star) {
    int shared = 0;
    for (int32_t x : sphere.faces[a])
      for (int32_t y : sphere.faces[f]) shared += x == y;
    if (shared == 1) b = f;
  }
  ASSERT_NE(a, b);
  TriangleMesh m;
  m.vertices = sphere.vertices;
  for (size_t f = 0; f < sphere.faces.size(); ++f)
    if (f != a && f != b) m.faces.push_back(sphere.faces[f]);
  RepairReport r;
  const TriangleMesh out = repair_mesh(m, "pinch", {}, &r);
  EXPECT_EQ(r.filled_holes, 2);
  EXPECT_EQ(r.split_vertices, 0);
  EXPECT_EQ(out.vertices.size(), sphere.vertices.size());
  expect_clean_and_closed(out);
  EXPECT_EQ(count_self_intersections(out), 0);
  // Each triangular hole has one fill, the removed face itself.
  EXPECT_NEAR(signed_volume(out), signed_volume(sphere), 1e-12);
}

TEST(RepairMesh, AFillNeverCrossesTheMesh) {
  const TriangleMesh sphere = test::icosphere(4, 1.0);
  const int32_t pole = 0;
  std::set<int32_t> disk = ring(sphere, pole);  // the hole: the faces at the pole and its ring
  disk.insert(pole);
  std::set<int32_t> rim;
  for (int32_t v : disk)
    for (int32_t w : ring(sphere, v))
      if (!disk.count(w)) rim.insert(w);
  Vec3 c = Vec3::Zero();  // centre of the hole's rim; the flat fill passes close to it
  for (int32_t v : rim) c += sphere.vertices[v] / double(rim.size());
  const double sag = 1 - c.norm();  // from the rim's plane to the sphere
  ASSERT_GT(sag, 0);

  // A small ball in the hole, through the flat fill's plane and clear of the sphere: the flat fill
  // would cross it; a faired fill follows the sphere over it.
  {
    TriangleMesh m = without_faces_at(sphere, disk);
    test::append(m, test::icosphere(2, 0.4 * sag, c));
    ASSERT_EQ(count_self_intersections(m), 0);
    RepairReport r;
    const TriangleMesh out = repair_mesh(m, "ball in a hole", {}, &r);
    EXPECT_EQ(r.filled_holes, 1);
    expect_clean_and_closed(out);
    EXPECT_EQ(count_self_intersections(out), 0);
    for (const Vec3& v : out.vertices)  // the fill stays near the sphere, above the ball
      if ((v - c).norm() > 0.41 * sag) {
        EXPECT_GT(v.norm(), 1 - 0.6 * sag);
      }
  }
  // A stick through the hole: every fill would cross it, so the hole stays open.
  {
    TriangleMesh m = without_faces_at(sphere, {pole});
    const Vec3 d = c.normalized();
    const Vec3 u = d.unitOrthogonal() * 0.01, w = d.cross(u);
    TriangleMesh stick;  // a thin closed box from 0.5 d to 1.5 d
    for (double s : {0.5, 1.5})
      for (int i = 0; i < 4; ++i) {
        const double sx = (i == 1 || i == 2) ? 1 : -1, sy = i >= 2 ? 1 : -1;
        stick.vertices.push_back(s * d + sx * u + sy * w);
      }
    for (int i = 0; i < 4; ++i) {  // sides, outward
      const int32_t j = (i + 1) % 4;
      stick.faces.push_back({i, j, j + 4});
      stick.faces.push_back({i, j + 4, i + 4});
    }
    stick.faces.push_back({0, 2, 1});
    stick.faces.push_back({0, 3, 2});
    stick.faces.push_back({4, 5, 6});
    stick.faces.push_back({4, 6, 7});
    test::append(m, stick);
    ASSERT_EQ(count_self_intersections(m), 0);
    RepairReport r;
    const TriangleMesh out = repair_mesh(m, "stick through a hole", {}, &r);
    EXPECT_EQ(r.filled_holes, 0);
    EXPECT_EQ(r.open_boundaries, 1);
    EXPECT_EQ(analyze_topology(out).boundary_edges, static_cast<int>(ring(sphere, pole).size()));
    EXPECT_EQ(count_self_intersections(out), 0);
  }
}

TEST(RepairMesh, AClosedModelWithHolesGetsAllOfThemFilledSmoothly) {
  // Holes longer than max_hole_edges on a closed model (the two-rings of two vertices, well under
  // a quarter of the diagonal): a model with holes cut into it, not an open shell, so all are
  // filled, faired to follow the sphere.
  const TriangleMesh sphere = test::icosphere(4, 1.0);
  std::set<int32_t> gone = ring(sphere, 0);
  gone.insert(0);
  std::set<int32_t> two = gone;
  for (int32_t v : gone)
    for (int32_t w : ring(sphere, v)) two.insert(w);
  const Vec3 far = -sphere.vertices[0];  // a second hole on the other side
  int32_t opposite = 0;
  for (int32_t v = 0; v < int32_t(sphere.vertices.size()); ++v)
    if ((sphere.vertices[v] - far).norm() < (sphere.vertices[opposite] - far).norm()) opposite = v;
  std::set<int32_t> removed = gone;
  removed.insert(opposite);
  const TriangleMesh m = without_faces_at(sphere, removed);
  RepairOptions o;
  o.max_hole_edges = 8;  // the first hole (a two-ring's rim) is longer
  RepairReport r;
  const TriangleMesh out = repair_mesh(m, "holes", o, &r);
  EXPECT_EQ(r.filled_holes, 2);
  EXPECT_EQ(r.open_boundaries, 0);
  expect_clean_and_closed(out);
  EXPECT_EQ(count_self_intersections(out), 0);
  // Faired: the new vertices lie much nearer the sphere than the rim's plane does.
  Vec3 c = Vec3::Zero();
  int n = 0;
  for (int32_t v : two)
    if (!gone.count(v)) c += sphere.vertices[v], ++n;
  const double sag = 1 - (c / n).norm();
  ASSERT_GT(sag, 0.005);
  for (const Vec3& v : out.vertices) EXPECT_LT(std::abs(v.norm() - 1), 0.5 * sag);

  // An open shell (a hemisphere: its rim spans the whole model) keeps its boundary.
  TriangleMesh half;
  half.vertices = sphere.vertices;
  for (const Tri& t : sphere.faces)
    if (sphere.vertices[t[0]].z() + sphere.vertices[t[1]].z() + sphere.vertices[t[2]].z() > 0) half.faces.push_back(t);
  RepairReport hr;
  repair_mesh(half, "hemisphere", o, &hr);
  EXPECT_EQ(hr.filled_holes, 0);
  EXPECT_EQ(hr.open_boundaries, 1);
}
