// SPDX-License-Identifier: MIT
// The analyzers behind `hdm check` against brute force on a small mesh.
#include "support/test_models.h"

#include <hdm/analysis/fidelity.h>
#include <hdm/slab/bake.h>

#include <gtest/gtest.h>

using namespace hdm;

namespace {

double brute_distance(const Vec3& p, const TriangleMesh& m) {
  double best = 1e300;
  for (const Tri& t : m.faces)
    best =
        std::min(best, (closest_point_on_triangle(p, m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]) - p).norm());
  return best;
}

}  // namespace

TEST(FidelityTest, matches_brute_force_on_a_small_mesh) {
  TriangleMesh input = test::icosphere(2, 1.0);
  for (Vec3& v : input.vertices) v.x() *= 1.6;  // an ellipsoid: the coarse shell must bend
  BakeOptions o;
  o.slabs = 40;
  o.grid_n = 4;
  const SlabModel m = bake_slabs(input, "ellipsoid", o);
  const Fidelity f = measure_fidelity(m, ExactMeshQuery(input));

  TriangleMesh recon;
  displaced_surface(m, recon.vertices, recon.faces);
  const double diag = bounds(input).diagonal();
  auto centroid = [](const TriangleMesh& mesh, const Tri& t) {
    return Vec3((mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3);
  };
  double sq = 0, mx = 0, sq_back = 0, mx_back = 0;
  std::vector<Vec3> fwd = recon.vertices, back = input.vertices;
  for (const Tri& t : recon.faces) fwd.push_back(centroid(recon, t));
  for (const Tri& t : input.faces) back.push_back(centroid(input, t));
  for (const Vec3& p : fwd) {
    const double d = brute_distance(p, input);
    sq += d * d, mx = std::max(mx, d);
  }
  for (const Vec3& p : back) {
    const double d = brute_distance(p, recon);
    sq_back += d * d, mx_back = std::max(mx_back, d);
  }
  EXPECT_NEAR(f.rms_pct, 100 * std::sqrt(sq / fwd.size()) / diag, 1e-6);
  EXPECT_NEAR(f.max_pct, 100 * mx / diag, 1e-6);
  EXPECT_NEAR(f.rms_back_pct, 100 * std::sqrt(sq_back / back.size()) / diag, 1e-6);
  EXPECT_NEAR(f.max_back_pct, 100 * mx_back / diag, 1e-6);
  EXPECT_GT(f.max_pct, 0.0);
}
