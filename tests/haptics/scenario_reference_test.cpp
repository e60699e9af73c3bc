// SPDX-License-Identifier: MIT
// The exact input's reference steps (ScenarioReport::reference_force_step_pct and
// reference_facet_force_step_pct) against their analytic values on a coarse icosphere: inside a
// convex polyhedron the closest boundary point jumps from one face to the next where the HIP
// crosses the bisector of their planes, so a spring to it turns by the angle θ between the two
// face normals in one tick, |ΔF| = 2·|F|·sin(θ/2), at any servo rate; the interpolated normal at
// the closest point barely moves across the same jump (the point moves by about depth·θ).
#include "haptics/haptics_fixtures.h"
#include "support/test_models.h"

#include <hdm/harness/scenarios.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace hdm {
namespace {

Vec3 face_normal(const TriangleMesh& m, int f) {
  const Tri& t = m.faces[f];
  const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
  return (b - a).cross(c - a).normalized();
}

// Smallest angle between the normals of two faces that share an edge, and largest between two
// faces that share a vertex (a path near a vertex may jump between those) [rad].
std::pair<double, double> facet_angle_range(const TriangleMesh& m) {
  std::map<std::pair<int, int>, int> edge_face;
  std::vector<std::vector<int>> vertex_faces(m.vertices.size());
  double lo = 1e9, hi = 0;
  for (int f = 0; f < static_cast<int>(m.faces.size()); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = m.faces[f][k], b = m.faces[f][(k + 1) % 3];
      vertex_faces[a].push_back(f);
      const auto key = std::minmax(a, b);
      const auto it = edge_face.find(key);
      if (it == edge_face.end()) {
        edge_face.emplace(key, f);
      } else {
        lo = std::min(lo, std::acos(std::clamp(face_normal(m, f).dot(face_normal(m, it->second)), -1.0, 1.0)));
      }
    }
  for (const std::vector<int>& fs : vertex_faces)
    for (int f : fs)
      for (int g : fs) hi = std::max(hi, std::acos(std::clamp(face_normal(m, f).dot(face_normal(m, g)), -1.0, 1.0)));
  return {lo, hi};
}

TEST(ScenarioReference, FacetStepIsTheJumpBetweenFaceNormals) {
  const TriangleMesh sphere = test::icosphere(2, 1.0);  // 320 faces; neighbouring normals 7-21° apart
  const test::BakedMesh b(sphere, "icosphere", 80, 8);
  const auto [lo, hi] = facet_angle_range(sphere);
  ASSERT_GT(lo, 0.1);

  ScenarioOptions o;
  o.scenario = Scenario::Slide;
  o.rate_hz = 10000;  // the hand moves 0.01 mm per tick: only a jump makes a large step
  const ScenarioReport r = run_scenario(b.model, b.locator, b.reference, o);
  ASSERT_GT(r.contact_ticks, r.ticks / 2) << r.note;
  const double max_f = o.proxy.force.max_force;
  // The stroke crosses several edges pressing near 1 N: the worst jump is at least the smallest
  // dihedral angle at 0.7 of the mean force, and at most the largest angle round a vertex at the
  // largest force.
  const double expect_lo = 100 * 2 * std::sin(lo / 2) * 0.7 * r.mean_contact_force_n / max_f;
  const double expect_hi = 100 * 2 * std::sin(hi / 2) * r.max_force_n / max_f;
  EXPECT_GT(r.reference_facet_force_step_pct, expect_lo) << r.note;
  EXPECT_LT(r.reference_facet_force_step_pct, expect_hi) << r.note;
  EXPECT_LT(r.reference_force_step_pct, 0.1 * r.reference_facet_force_step_pct)
      << "the interpolated normal does not jump with the closest point";
}

}  // namespace
}  // namespace hdm
