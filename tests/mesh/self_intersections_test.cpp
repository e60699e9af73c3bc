// SPDX-License-Identifier: MIT
// Self-crossing closed meshes resolved into the boundary of their union: checked against the
// analytic union (volume), by counting (closed, manifold, no crossing left) and with Embree on the
// input (every face of the result lies on an input face).
#include "support/test_models.h"

#include <hdm/analysis/fidelity.h>
#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/mesh/self_intersections.h>
#include <hdm/mesh/winding_number.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

using namespace hdm;
using test::signed_volume;

namespace {

// Axis-aligned box [lo, hi], faces counter-clockwise seen from outside.
void add_box(TriangleMesh& m, const Vec3& lo, const Vec3& hi) {
  const auto base = static_cast<int32_t>(m.vertices.size());
  for (int k = 0; k < 8; ++k)
    m.vertices.emplace_back(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(), k & 4 ? hi.z() : lo.z());
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.faces.push_back({base + q[0], base + q[1], base + q[2]});
    m.faces.push_back({base + q[0], base + q[2], base + q[3]});
  }
}

// The properties every resolved union must have: closed, manifold, consistently oriented, crossing
// no more, enclosing the analytic union's volume, and made of pieces of the input's faces (crack
// fills aside, which the cases here do not need).
// resolve_self_intersections() of a crossing @p input, checked closed, manifold, consistently
// oriented and crossing no more.
TriangleMesh resolved_closed(const TriangleMesh& input, SelfIntersectionReport& rep) {
  EXPECT_GT(count_self_intersections(input), 0);
  TriangleMesh out = resolve_self_intersections(input, &rep);
  EXPECT_TRUE(rep.resolved);
  const MeshTopology t = analyze_topology(out);
  EXPECT_EQ(t.boundary_edges, 0);
  EXPECT_EQ(t.non_manifold_edges, 0);
  EXPECT_EQ(t.inconsistent_edges, 0);
  EXPECT_EQ(count_self_intersections(out), 0);
  return out;
}

void expect_union(const TriangleMesh& input, double union_volume) {
  SelfIntersectionReport rep;
  const TriangleMesh out = resolved_closed(input, rep);
  EXPECT_EQ(rep.pairs_after, 0);
  EXPECT_GT(rep.interior_faces, 0);
  EXPECT_NEAR(signed_volume(out), union_volume, 1e-9 * union_volume);
  const ExactMeshQuery on_input(input);
  const double diag = bounds(input).diagonal();
  if (rep.closed_cracks == 0)
    for (const Tri& f : out.faces) {
      const Vec3 c = (out.vertices[f[0]] + out.vertices[f[1]] + out.vertices[f[2]]) / 3;
      EXPECT_LT(on_input.closest_point(c).distance, 1e-9 * diag);
    }
}

}  // namespace

TEST(SelfIntersections, ABoxPushedThroughAnotherBecomesTheirUnion) {
  TriangleMesh m;
  add_box(m, Vec3(0, 0, 0), Vec3(2, 2, 2));
  add_box(m, Vec3(1, 0.5, 0.5), Vec3(3, 1.5, 1.5));  // pokes 1 out of the face x = 2
  expect_union(m, 8 + 1);
}

TEST(SelfIntersections, AMeshThatDoesNotCrossItselfIsKept) {
  TriangleMesh m;
  add_box(m, Vec3(0, 0, 0), Vec3(1, 1, 1));
  add_box(m, Vec3(2, 0, 0), Vec3(3, 1, 1));
  SelfIntersectionReport rep;
  const TriangleMesh out = resolve_self_intersections(m, &rep);
  EXPECT_FALSE(rep.resolved);
  EXPECT_EQ(rep.pairs_before, 0);
  EXPECT_EQ(out.faces, m.faces);
}

// Three thin tetrahedra whose faces cross nearly in one plane near a shared corner point: rounded
// intersection points there move an input vertex (CGAL 5.5's own refinement crashed on them).
// With exact constructions the result is their union: inside exactly where a point is inside one
// of the tetrahedra (barycentric signs), at random points in their box.
TEST(SelfIntersections, ThinPartsCrossingNearlyInOnePlaneBecomeTheirUnion) {
  TriangleMesh m;
  m.vertices = {{0, 0.50486699999999995, -0.181284},
                {-0.173069, 0.53349100000000005, -0.171989},
                {0, 0.51147299999999996, -0.002516},
                {-0.060912867897161105, 0.49688523058723283, -0.11786743314571173},
                {0.0059170309456769666, 0.45227267958092493, -0.011504539414968587},
                {-0.0012945481143054626, 0.51149085529106475, -0.0038356585504748615},
                {0.17147413313639495, 0.53416586600685889, -0.17263320275450955},
                {0.072685197449291722, 0.49916175705349364, -0.048362319019500943},
                {-0.17147413313639495, 0.53416586600685889, -0.17263320275450955},
                {0.0012945481143054626, 0.51149085529106475, -0.0038356585504748615},
                {-0.0059170309456769666, 0.45227267958092493, -0.011504539414968587},
                {-0.072685197449291736, 0.49916175705349364, -0.048362319019500943}};
  for (int32_t b : {0, 4, 8})  // a tetrahedron: base (b, b+1, b+2), apex b+3
    for (const Tri& t : {Tri{0, 1, 2}, Tri{0, 3, 1}, Tri{1, 3, 2}, Tri{2, 3, 0}})
      m.faces.push_back({b + t[0], b + t[1], b + t[2]});
  ASSERT_EQ(analyze_topology(m).boundary_edges, 0);
  SelfIntersectionReport rep;
  const ExactMeshQuery result(resolved_closed(m, rep));
  // Inside tetrahedron b, and farther than 1e-9 from each of its face planes.
  auto in_tetrahedron = [&](const Vec3& p, int32_t b, bool& near) {
    const Vec3* v = &m.vertices[size_t(b)];
    const int faces[4][4] = {{0, 1, 2, 3}, {0, 3, 1, 2}, {1, 3, 2, 0}, {2, 3, 0, 1}};  // plane, opposite
    bool in = true;
    for (const auto& f : faces) {
      const Vec3 n = (v[f[1]] - v[f[0]]).cross(v[f[2]] - v[f[0]]).normalized();
      const double d = n.dot(p - v[f[0]]), opposite = n.dot(v[f[3]] - v[f[0]]);
      near |= std::abs(d) < 1e-9;
      in &= (d < 0) == (opposite < 0);
    }
    return in;
  };
  const Aabb box = bounds(m);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  int inside = 0;
  for (int k = 0; k < 20000; ++k) {
    const Vec3 p = box.min + (box.max - box.min).cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
    bool near = false, in = false;
    for (int32_t b : {0, 4, 8}) in |= in_tetrahedron(p, b, near);
    if (near) continue;
    inside += in;
    EXPECT_EQ(result.inside(p), in) << p.transpose();
  }
  EXPECT_GT(inside, 20);
}

// Parts that share face planes (a box pressed into another's side, flush with two of its faces):
// the overlapping coplanar faces are one face of the union, and where three faces meet in one point
// of an edge the refinement still joins them (CGAL 5.5's refinement refuses both: "non-handled
// triple intersection").
TEST(SelfIntersections, PartsSharingFacePlanesBecomeTheirUnion) {
  TriangleMesh m;
  add_box(m, Vec3(0, 0, 0), Vec3(2, 2, 2));
  add_box(m, Vec3(1, 0, 0.5), Vec3(3, 2, 1.5));  // flush with y = 0 and y = 2
  expect_union(m, 8 + 2);
}

// A small box touching a unit box face to face: the square they share has material on both sides
// and goes; what is left is the boundary of their union (volume 1 + 0.25).
TEST(SelfIntersections, PartsTouchingFaceToFaceBecomeTheirUnion) {
  TriangleMesh m;
  add_box(m, Vec3(0, 0, 0), Vec3(1, 1, 1));
  add_box(m, Vec3(1, 0.25, 0.25), Vec3(2, 0.75, 0.75));
  expect_union(m, 1 + 0.25);
}

// Three boxes where pieces of each lie inside both others (winding number 2 just in front of
// them): ray parity calls those points outside and would keep the pieces; the winding number
// buries them. Union by inclusion-exclusion: 8 + 4.8 + 8.4 - 1.6 - 1.4 - 1.68 + 0.56.
TEST(SelfIntersections, PiecesInsideTwoOtherPartsAreInterior) {
  TriangleMesh m;
  add_box(m, Vec3(0, 0, 0), Vec3(2, 2, 2));
  add_box(m, Vec3(1, -0.5, 0.6), Vec3(3, 2.5, 1.4));
  add_box(m, Vec3(1.5, 0.3, -0.5), Vec3(3.5, 1.7, 2.5));
  expect_union(m, 17.08);
}

// A box open at the top (its opening is a sixth of its area: nearly closed) pushed through by
// another box: resolved as the solid it nearly bounds, the opening filled flat and kept filled.
TEST(SelfIntersections, ANearlyClosedBoxPushedThroughAnotherBecomesTheirClosedUnion) {
  TriangleMesh m;
  add_box(m, Vec3(0, 0, 0), Vec3(2, 2, 2));
  m.faces.erase(m.faces.begin() + 2, m.faces.begin() + 4);  // the face z = 2
  add_box(m, Vec3(1, 0.5, 0.5), Vec3(3, 1.5, 1.5));         // pokes 1 out of the face x = 2
  ASSERT_GT(analyze_topology(m).boundary_edges, 0);
  ASSERT_GT(count_self_intersections(m), 0);
  SelfIntersectionReport rep;
  const TriangleMesh out = resolve_self_intersections(m, &rep);
  ASSERT_TRUE(rep.resolved);
  EXPECT_GT(rep.filled_faces, 0);
  const MeshTopology t = analyze_topology(out);
  EXPECT_EQ(t.boundary_edges, 0);
  EXPECT_EQ(t.non_manifold_edges, 0);
  EXPECT_EQ(t.inconsistent_edges, 0);
  EXPECT_EQ(count_self_intersections(out), 0);
  EXPECT_NEAR(signed_volume(out), 8 + 1, 1e-9 * 9);
  // Every face lies on the input or on the opening's square (z = 2, 0 <= x, y <= 2).
  const ExactMeshQuery on_input(m);
  for (const Tri& f : out.faces) {
    const Vec3 c = (out.vertices[f[0]] + out.vertices[f[1]] + out.vertices[f[2]]) / 3;
    const bool on_opening = std::abs(c.z() - 2) < 1e-12 && c.x() > 0 && c.x() < 2 && c.y() > 0 && c.y() < 2;
    EXPECT_TRUE(on_opening || on_input.closest_point(c).distance < 1e-9) << c.transpose();
  }
}

// Two disjoint boxes 10⁻⁷ apart (a slit between two outer layers, as mannequin-devil.off has once
// resolved): no face is inside the material. A point 10⁻⁵ of the diagonal in front of the facing
// sides lies in the other box, so a coarser probe would call both sides interior.
TEST(SelfIntersections, FacesAcrossAThinSlitAreNotInterior) {
  TriangleMesh m;
  add_box(m, Vec3(0, 0, 0), Vec3(1, 1, 1));
  add_box(m, Vec3(1 + 1e-7, 0, 0), Vec3(2, 1, 1));
  ASSERT_EQ(count_self_intersections(m), 0);
  const ExactMeshQuery q(m);
  ASSERT_TRUE(q.closed());
  const std::vector<uint8_t> interior = interior_faces(q);
  ASSERT_EQ(interior.size(), m.faces.size());
  EXPECT_EQ(std::count(interior.begin(), interior.end(), uint8_t(1)), 0);
}

// A box inside two overlapping boxes is inside the material (winding 2); faces of the outer boxes
// are interior exactly where the point just in front of their centroid lies in the other box.
TEST(SelfIntersections, InteriorFacesFollowTheUnionOfTheParts) {
  TriangleMesh m;
  const Vec3 lo[3] = {Vec3(0, 0, 0), Vec3(1, -1, -1), Vec3(1.2, 0.8, 0.8)};
  const Vec3 hi[3] = {Vec3(2, 2, 2), Vec3(3, 3, 3), Vec3(1.6, 1.2, 1.2)};
  for (int b = 0; b < 3; ++b) add_box(m, lo[b], hi[b]);
  const ExactMeshQuery q(m);
  ASSERT_TRUE(q.closed());
  const std::vector<uint8_t> interior = interior_faces(q);
  ASSERT_EQ(interior.size(), m.faces.size());
  for (size_t f = 0; f < m.faces.size(); ++f) {
    const int own = static_cast<int>(f / 12);
    const Tri& t = m.faces[f];
    const Vec3 c = (m.vertices[t[0]] + m.vertices[t[1]] + m.vertices[t[2]]) / 3;
    const Vec3 p = c + 1e-6 * q.face_normal(static_cast<int32_t>(f));
    bool inside = false;
    for (int b = 0; b < 3; ++b)
      if (b != own && (p.array() > lo[b].array()).all() && (p.array() < hi[b].array()).all()) inside = true;
    EXPECT_EQ(interior[f] != 0, inside) << "face " << f << " at " << c.transpose();
  }
  EXPECT_EQ(std::count(interior.begin() + 24, interior.end(), uint8_t(1)), 12);  // the inner box
}

// A box open at the top pushed through by another: filled to the solid it nearly bounds (the
// input's faces kept, the opening closed flat); a single sheet is not nearly closed.
TEST(SelfIntersections, ANearlyClosedInputIsFilledAndASheetIsNot) {
  TriangleMesh m;
  add_box(m, Vec3(0, 0, 0), Vec3(2, 2, 2));
  m.faces.erase(m.faces.begin() + 2, m.faces.begin() + 4);  // the face z = 2
  add_box(m, Vec3(1, 0.5, 0.5), Vec3(3, 1.5, 1.5));
  const TriangleMesh filled = fill_nearly_closed(m);
  ASSERT_GT(filled.faces.size(), m.faces.size());
  for (size_t f = 0; f < m.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(filled.vertices[filled.faces[f][k]], m.vertices[m.faces[f][k]]);
  EXPECT_EQ(analyze_topology(filled).boundary_edges, 0);
  EXPECT_NEAR(signed_volume(filled), 8 + 2, 1e-9);  // both boxes whole: the fill is the square z = 2
  TriangleMesh sheet;
  add_box(sheet, Vec3(0, 0, 0), Vec3(1, 1, 1));
  sheet.faces.resize(2);
  EXPECT_TRUE(fill_nearly_closed(sheet).faces.empty());
}

// A box turned inside out half pushed into another (winding 1 in the outer box, 0 in the overlap,
// -1 in the inverted box's part outside): a face is on the material's boundary only where the
// material (analytic winding >= 1/2) is behind it and not in front of it.
TEST(SelfIntersections, FacesWithNoMaterialBehindThemAreInterior) {
  TriangleMesh m;
  add_box(m, Vec3(0, 0, 0), Vec3(2, 2, 2));
  add_box(m, Vec3(1, 0.5, 0.5), Vec3(3, 1.5, 1.5));
  for (size_t f = 12; f < 24; ++f) std::swap(m.faces[f][1], m.faces[f][2]);  // inside out
  auto in = [](const Vec3& p, const Vec3& lo, const Vec3& hi) {
    return (p.array() > lo.array()).all() && (p.array() < hi.array()).all();
  };
  auto material = [&](const Vec3& p) {
    return int(in(p, Vec3(0, 0, 0), Vec3(2, 2, 2))) - int(in(p, Vec3(1, 0.5, 0.5), Vec3(3, 1.5, 1.5))) >= 1;
  };
  const ExactMeshQuery q(m);
  ASSERT_TRUE(q.closed());
  const std::vector<uint8_t> interior = interior_faces(q);
  ASSERT_EQ(interior.size(), m.faces.size());
  int outside_faces = 0;
  for (size_t f = 0; f < m.faces.size(); ++f) {
    const Tri& t = m.faces[f];
    const Vec3 c = (m.vertices[t[0]] + m.vertices[t[1]] + m.vertices[t[2]]) / 3;
    const Vec3 n = q.face_normal(static_cast<int32_t>(f));
    const bool boundary = material(c - 1e-6 * n) && !material(c + 1e-6 * n);
    EXPECT_EQ(interior[f] != 0, !boundary) << "face " << f << " at " << c.transpose();
    outside_faces += f >= 12 && c.x() > 2;
  }
  EXPECT_GT(outside_faces, 0);  // faces of the inverted box outside the other: no material on either side
}

// A soup of five spheres passing through each other, one of them inside two others: the result is
// closed, manifold and crossing no more, and its inside (Embree's ray parity on the result) is the
// input's by its generalized winding number at random points, away from the surfaces (a band of
// 2 % of a radius, the tessellation's chord error), and the union of the analytic balls.
TEST(SelfIntersections, ASoupOfSpheresBecomesTheSolidOfItsWindingNumber) {
  const Vec3 centre[5] = {Vec3(0, 0, 0), Vec3(0.9, 0.1, 0), Vec3(0.3, 0.8, 0.2), Vec3(0.5, 0.3, 0.1),
                          Vec3(-0.7, -0.4, 0.5)};
  const double radius[5] = {1.0, 0.8, 0.7, 0.3, 0.6};
  TriangleMesh m;
  for (int k = 0; k < 5; ++k) {
    const TriangleMesh s = test::icosphere(3, radius[k], centre[k]);
    test::append(m, s);
  }
  SelfIntersectionReport rep;
  const ExactMeshQuery result(resolved_closed(m, rep));
  const WindingNumber winding(m);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-2, 2);
  int tested = 0, inside = 0;
  for (int k = 0; k < 4000; ++k) {
    const Vec3 p(u(rng), u(rng), u(rng));
    bool in_ball = false, near = false;
    for (int b = 0; b < 5; ++b) {
      const double d = (p - centre[b]).norm() - radius[b];
      in_ball |= d < 0;
      near |= std::abs(d) < 0.02 * radius[b];
    }
    if (near) continue;
    ++tested;
    inside += in_ball;
    EXPECT_EQ(result.inside(p), winding.inside(p)) << p.transpose();
    EXPECT_EQ(result.inside(p), in_ball) << p.transpose();
  }
  EXPECT_GT(tested, 3000);
  EXPECT_GT(inside, 300);
}
