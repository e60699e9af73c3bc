// SPDX-License-Identifier: MIT
// decimate_mesh() on a real self-crossing mesh resolved into its union (bones.off of the
// libcgal-demo archive): the refinement's thin faces along the crossing curves leave stars that
// are barely seen from any direction, and the decimation must not empty their cones (an empty-cone vertex has no
// ray direction, so its slabs are invalid at any thickness). Cone margin is measured here by a
// direct search over directions, independent of the decimation's own estimate.
#include "support/test_models.h"

#include <hdm/io/read_mesh.h>
#include <hdm/mesh/decimate_mesh.h>
#include <hdm/mesh/orient_mesh.h>
#include <hdm/mesh/self_intersections.h>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace hdm;

namespace {

// max over unit d of min over the star's face normals of d·n, by a Fibonacci sphere of 2000
// directions refined by a shrinking pattern search around the best one.
std::vector<double> cone_margins(const TriangleMesh& m) {
  std::vector<std::vector<Vec3>> normals(m.vertices.size());
  for (const Tri& t : m.faces) {
    const Vec3 n = (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]);
    if (n.norm() > 0)
      for (int32_t v : t) normals[v].push_back(n.normalized());
  }
  std::vector<Vec3> dirs;
  const int k = 2000;
  for (int i = 0; i < k; ++i) {
    const double z = 1 - (2 * i + 1.0) / k, r = std::sqrt(1 - z * z), a = i * std::numbers::pi * (3 - std::sqrt(5.0));
    dirs.emplace_back(r * std::cos(a), r * std::sin(a), z);
  }
  std::vector<double> out(m.vertices.size(), 1.0);
  for (size_t v = 0; v < m.vertices.size(); ++v) {
    if (normals[v].empty()) continue;
    auto value = [&](const Vec3& d) {
      double w = 2;
      for (const Vec3& n : normals[v]) w = std::min(w, d.dot(n));
      return w;
    };
    Vec3 best = dirs[0];
    for (const Vec3& d : dirs)
      if (value(d) > value(best)) best = d;
    double b = value(best);
    for (double step = 0.06; step > 1e-5; step *= 0.6)
      for (bool improved = true; improved;) {
        improved = false;
        for (int axis = 0; axis < 3; ++axis)
          for (int sign : {-1, 1}) {
            const Vec3 d = (best + sign * step * Vec3::Unit(axis)).normalized();
            if (const double x = value(d); x > b) b = x, best = d, improved = true;
          }
      }
    out[v] = b;
  }
  return out;
}

int empty_cones(const std::vector<double>& margins) {
  int n = 0;
  for (double v : margins) n += v <= 0;
  return n;
}

}  // namespace

TEST(DecimateUnion, BarelySeenStarsOfAResolvedUnionKeepNonEmptyDualCones) {
  TriangleMesh in = read_mesh(test::data_path("bones.off"));
  orient_outward(in);
  SelfIntersectionReport rep;
  const TriangleMesh u = resolve_self_intersections(in, &rep);
  ASSERT_TRUE(rep.resolved) << "bones.off crosses itself; its union is what the bake decimates";
  const std::vector<double> seen = cone_margins(u);
  ASSERT_EQ(empty_cones(seen), 0) << "every star of the union is seen from some direction";
  ASSERT_LT(*std::min_element(seen.begin(), seen.end()), 0.05) << "... some only barely (the case under test)";
  // The first rounds of the bake's error-bounded loop and a target just below the input.
  for (int64_t target :
       {int64_t(u.faces.size()) / 60, int64_t(u.faces.size()) / 2, int64_t(u.faces.size()) * 98 / 100}) {
    DecimateOptions o;
    o.target_faces = target;
    const TriangleMesh out = decimate_mesh(u, o);
    EXPECT_EQ(empty_cones(cone_margins(out)), 0) << "target " << target << ": " << out.faces.size() << " faces";
  }
}
