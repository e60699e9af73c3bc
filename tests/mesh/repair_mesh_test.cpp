// SPDX-License-Identifier: MIT
// Dirty-scan repair: each defect is made on a clean real or analytic mesh, so the clean mesh is the
// independent reference (positions, volume, exact distance with Embree).
#include "support/test_models.h"

#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/core/error.h>
#include <hdm/io/read_mesh.h>
#include <hdm/mesh/repair_mesh.h>
#include <hdm/slab/bake.h>

#include <gtest/gtest.h>

#include <random>
#include <set>

using namespace hdm;

namespace {

// Signed volume enclosed by a closed mesh (divergence theorem); > 0 for outward normals.
double signed_volume(const TriangleMesh& m) {
  double v = 0;
  for (const Tri& t : m.faces) v += m.vertices[t[0]].dot(m.vertices[t[1]].cross(m.vertices[t[2]])) / 6;
  return v;
}

void expect_clean_and_closed(const TriangleMesh& m) {
  const MeshTopology t = analyze_topology(m);
  EXPECT_EQ(t.boundary_edges, 0);
  EXPECT_EQ(t.non_manifold_edges, 0);
  EXPECT_EQ(t.inconsistent_edges, 0);
  EXPECT_EQ(t.degenerate_faces, 0);
  EXPECT_NO_THROW(validate_for_bake(m, "repaired"));
}

}  // namespace

TEST(RepairMesh, triangle_soup_is_welded_back_to_the_scan) {
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

TEST(RepairMesh, flipped_faces_are_oriented_outward) {
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

TEST(RepairMesh, inside_out_closed_mesh_is_turned_outward) {
  TriangleMesh m = test::icosphere(3, 1.0);
  for (Tri& t : m.faces) std::swap(t[1], t[2]);
  ASSERT_LT(signed_volume(m), 0);
  const TriangleMesh out = repair_mesh(m, "inside-out");
  EXPECT_GT(signed_volume(out), 0);
  expect_clean_and_closed(out);
}

TEST(RepairMesh, zero_area_and_repeated_vertex_faces_are_removed) {
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

TEST(RepairMesh, small_holes_are_filled_on_the_surface_and_open_boundaries_kept) {
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

TEST(RepairMesh, bad_input_is_refused_with_the_name_and_reason) {
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
