// SPDX-License-Identifier: MIT
// orient_outward() on multi-part inputs: each part's orientation after the call is judged by its
// signed volume (divergence theorem, computed here) and by where it sits, not by the report alone.
#include <hdm/mesh/orient_mesh.h>

#include "support/test_models.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace hdm {
namespace {

void invert(TriangleMesh& part) {
  for (Tri& t : part.faces) std::swap(t[1], t[2]);
}

// Signed volume of faces [first, last): Σ a·(b×c)/6 (positive for a closed surface facing out).
double signed_volume(const TriangleMesh& mesh, std::pair<size_t, size_t> range) {
  double v = 0;
  for (size_t f = range.first; f < range.second; ++f) {
    const Vec3 &a = mesh.vertices[mesh.faces[f][0]], &b = mesh.vertices[mesh.faces[f][1]],
               &c = mesh.vertices[mesh.faces[f][2]];
    v += a.dot(b.cross(c)) / 6;
  }
  return v;
}

// The same faces with the same orientation (as index triples up to rotation).
bool same_orientation(const TriangleMesh& a, const TriangleMesh& b, std::pair<size_t, size_t> range) {
  for (size_t f = range.first; f < range.second; ++f) {
    Tri x = a.faces[f], y = b.faces[f];
    std::rotate(x.begin(), std::min_element(x.begin(), x.end()), x.end());
    std::rotate(y.begin(), std::min_element(y.begin(), y.end()), y.end());
    if (x != y) return false;
  }
  return true;
}

// The faces of a sphere about @p centre that @p keep (given the corners' heights above the centre).
template <class Keep>
TriangleMesh sphere_part(double radius, const Vec3& centre, Keep keep) {
  const TriangleMesh s = test::icosphere(3, radius, Vec3::Zero());
  TriangleMesh out;
  out.vertices = s.vertices;
  for (const Tri& t : s.faces)
    if (keep(s.vertices[t[0]].z(), s.vertices[t[1]].z(), s.vertices[t[2]].z())) out.faces.push_back(t);
  for (Vec3& v : out.vertices) v += centre;
  return out;
}

// The upper half (z > 0 at every corner) of a sphere: an open sheet, its opening as large as itself.
TriangleMesh cap(double radius, const Vec3& centre) {
  return sphere_part(radius, centre, [](double a, double b, double c) { return a > 0 && b > 0 && c > 0; });
}

// A sphere with the faces around its top pole removed: an opening far smaller than its area.
TriangleMesh opened_sphere(double radius, const Vec3& centre) {
  const double top = 0.95 * radius;
  return sphere_part(radius, centre, [top](double a, double b, double c) { return a < top || b < top || c < top; });
}

TEST(OrientOutward, MultiPartInputFacesOutAtEvenDepthAndInAtOddDepth) {
  // A shell with a cavity (an outer sphere and a smaller one inside it), both given inside out; a
  // second solid beside them given facing out; a sphere with a small opening given inside out;
  // and an open cap given facing down.
  TriangleMesh outer = test::icosphere(3, 2.0, Vec3::Zero()), cavity = test::icosphere(3, 1.0, Vec3::Zero());
  TriangleMesh beside = test::icosphere(2, 1.0, Vec3(5, 0, 0)), opened = opened_sphere(1.0, Vec3(0, 5, 0));
  TriangleMesh sheet = cap(1.0, Vec3(0, -5, 0));
  invert(outer);
  invert(opened);
  invert(sheet);
  TriangleMesh mesh;
  const auto r_outer = test::append(mesh, outer), r_cavity = test::append(mesh, cavity),
             r_beside = test::append(mesh, beside);
  const auto r_opened = test::append(mesh, opened), r_sheet = test::append(mesh, sheet);
  const TriangleMesh given = mesh;

  const OrientReport rep = orient_outward(mesh);

  // Solids: material outside the faces' backs. The outer wall and the solid beside face out
  // (positive volume); the cavity's wall faces into the cavity (negative volume).
  const double ball = 4.0 / 3.0 * std::numbers::pi;  // unit ball volume; icospheres are within 2 % of it
  EXPECT_NEAR(signed_volume(mesh, r_outer), 8 * ball, 0.05 * 8 * ball);
  EXPECT_NEAR(signed_volume(mesh, r_cavity), -ball, 0.05 * ball);
  EXPECT_NEAR(signed_volume(mesh, r_beside), ball, 0.05 * ball);
  EXPECT_GT(signed_volume(mesh, r_opened), 0) << "a sphere with a small opening is oriented as a solid";
  EXPECT_TRUE(same_orientation(mesh, given, r_beside)) << "a part already facing out is kept";
  EXPECT_TRUE(same_orientation(mesh, given, r_sheet)) << "a sheet keeps the file's orientation";
  EXPECT_EQ(rep.components, 5);
  EXPECT_EQ(rep.closed, 3);
  EXPECT_EQ(rep.nearly_closed, 1);
  EXPECT_EQ(rep.sheets, 1);
  // Turned: the outer wall, the cavity (given facing out, at odd depth) and the opened sphere.
  EXPECT_EQ(rep.flipped, 3);
  EXPECT_EQ(rep.flipped_faces, int64_t(outer.faces.size() + cavity.faces.size() + opened.faces.size()));
}

TEST(OrientOutward, PartsThatPassThroughEachOtherAreNotCavities) {
  // Two overlapping spheres, neither holding the other's box: both solids face out, whichever way
  // they were given (a part is nested only in a part whose box holds its whole box).
  TriangleMesh a = test::icosphere(3, 1.0, Vec3::Zero()), b = test::icosphere(3, 1.0, Vec3(1.2, 0, 0));
  invert(b);
  TriangleMesh mesh;
  const auto ra = test::append(mesh, a), rb = test::append(mesh, b);
  const OrientReport rep = orient_outward(mesh);
  EXPECT_GT(signed_volume(mesh, ra), 0);
  EXPECT_GT(signed_volume(mesh, rb), 0);
  EXPECT_EQ(rep.flipped, 1);
}

TEST(OrientOutward, EmptyMeshReportsNothing) {
  TriangleMesh mesh;
  const OrientReport rep = orient_outward(mesh);
  EXPECT_EQ(rep.components, 0);
  EXPECT_EQ(rep.flipped, 0);
}

}  // namespace
}  // namespace hdm
