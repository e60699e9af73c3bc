// SPDX-License-Identifier: MIT
// The analyzers behind `hdm check` against brute force on a small mesh.
#include "support/brute_force.h"
#include "support/test_models.h"

#include <hdm/analysis/fidelity.h>
#include <hdm/slab/bake.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace hdm;

TEST(FidelityTest, MatchesBruteForceOnASmallMesh) {
  TriangleMesh input = test::icosphere(2, 1.0);
  for (Vec3& v : input.vertices) v.x() *= 1.6;  // an ellipsoid: the coarse shell must bend
  BakeOptions o;
  o.slabs = 40;
  o.grid_n = 4;
  const SlabModel m = bake_slabs(input, "ellipsoid", o);
  const ExactMeshQuery exact(input);
  const Fidelity f = measure_fidelity(m, exact);
  // One BVH per slab (chunks of 16 grid triangles): each input point's distance is the least over
  // 40 chunks, mostly rejected by their boxes, and must be the same.
  const Fidelity chunked = measure_fidelity(m, exact, nullptr, INFINITY, nullptr, 16);

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
    const double d = test::brute_distance(p, input);
    sq += d * d, mx = std::max(mx, d);
  }
  for (const Vec3& p : back) {
    const double d = test::brute_distance(p, recon);
    sq_back += d * d, mx_back = std::max(mx_back, d);
  }
  EXPECT_NEAR(f.rms_pct, 100 * std::sqrt(sq / fwd.size()) / diag, 1e-6);
  EXPECT_NEAR(f.max_pct, 100 * mx / diag, 1e-6);
  EXPECT_NEAR(f.rms_back_pct, 100 * std::sqrt(sq_back / back.size()) / diag, 1e-6);
  EXPECT_NEAR(f.max_back_pct, 100 * mx_back / diag, 1e-6);
  EXPECT_NEAR(chunked.rms_back_pct, 100 * std::sqrt(sq_back / back.size()) / diag, 1e-6);
  EXPECT_NEAR(chunked.max_back_pct, 100 * mx_back / diag, 1e-6);
  EXPECT_EQ(chunked.rms_pct, f.rms_pct);
  EXPECT_GT(f.max_pct, 0.0);
  // Points farther than 1 % of the diagonal from every chunk take the unbounded second pass.
  std::vector<Vec3> far_set = {Vec3(3, 0.5, 0.2), Vec3(-0.2, 0.1, 0.05), Vec3(0, 0, 1.4)};
  double sq_far = 0, mx_far = 0;
  for (const Vec3& p : far_set) {
    const double d = test::brute_distance(p, recon);
    sq_far += d * d, mx_far = std::max(mx_far, d);
  }
  const Fidelity far = measure_fidelity(m, exact, &far_set, INFINITY, nullptr, 16);
  EXPECT_NEAR(far.rms_back_pct, 100 * std::sqrt(sq_far / far_set.size()) / diag, 1e-9);
  EXPECT_NEAR(far.max_back_pct, 100 * mx_far / diag, 1e-9);
  EXPECT_GT(mx_far, 0.5);
}

namespace {

// An open square sheet over [-1, 1]² at height z = base + tilt·x, facing +z.
void add_sheet(TriangleMesh& m, double base, double tilt) {
  const int k = 16, first = static_cast<int>(m.vertices.size());
  for (int j = 0; j <= k; ++j)
    for (int i = 0; i <= k; ++i) {
      const double x = -1 + 2.0 * i / k, y = -1 + 2.0 * j / k;
      m.vertices.emplace_back(x, y, base + tilt * x);
    }
  for (int j = 0; j < k; ++j)
    for (int i = 0; i < k; ++i) {
      const int a = first + j * (k + 1) + i, b = a + 1, c = a + k + 1, d = c + 1;
      m.faces.push_back({a, b, d});
      m.faces.push_back({a, d, c});
    }
}

}  // namespace

// Two open sheets stacked closer than the ±1 % band of the contact test (geological horizons, as
// horizons.off of libcgal-demo): a point between them is inside exactly when it is behind the
// sheet nearest to it (the reference: ExactMeshQuery::inside on the input, and here also the
// analytic heights). hdm must agree there too, also where the point lies in no slab.
TEST(FidelityTest, ContactAgreesBetweenTwoStackedOpenSheets) {
  TriangleMesh input;
  add_sheet(input, 0.0, 0.0);
  add_sheet(input, 0.03, 0.015);  // 0.015 to 0.045 above the first
  const ExactMeshQuery exact(input);
  ASSERT_FALSE(exact.closed());
  // The reference itself against the analytic sheets, between them.
  for (double x = -0.9; x < 0.9; x += 0.1)
    for (const double f : {0.2, 0.4, 0.6, 0.8}) {
      const double top = 0.03 + 0.015 * x;
      EXPECT_EQ(exact.inside(Vec3(x, 0.1, f * top)), f > 0.5) << x << " " << f;
    }
  BakeOptions o;
  o.slabs = 128;
  o.grid_n = 6;
  const SlabModel m = bake_slabs(input, "two sheets", o);
  const ContactAccuracy c = measure_contact(m, exact, 20000, 7);
  EXPECT_GE(c.agreement, 0.995) << "false inside " << c.false_inside << ", missed below the shell "
                                << c.missed_below_shell << ", missed in the shell " << c.missed_in_shell;
}
