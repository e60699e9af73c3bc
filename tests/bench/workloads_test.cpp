// SPDX-License-Identifier: MIT
// The workloads and statistics of `hdm bench` and the micro-benchmarks (bench/workloads.h), checked
// against what they promise: statistics against a brute-force count, the paths' step bound and
// distance to the surface against Embree on the displaced surface, subdivision against the input's
// area and topology, warm strokes against the model before them.
#include "support/test_models.h"
#include "workloads.h"

#include <hdm/edit/brush_registry.h>
#include <hdm/slab/bake.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

namespace hdm::bench {
namespace {

// Number of elements of v strictly below x.
size_t below(const std::vector<double>& v, double x) {
  return static_cast<size_t>(std::count_if(v.begin(), v.end(), [&](double y) { return y < x; }));
}

TEST(Workloads, StatsOfMatchesOrderStatistics) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0, 1000);
  for (size_t n : {1, 2, 7, 100, 1001}) {
    std::vector<double> v(n);
    for (double& x : v) x = u(rng);
    const Stats s = stats_of(v);
    EXPECT_EQ(below(v, s.median), n / 2) << n;                                        // distinct values
    EXPECT_EQ(below(v, s.p99), std::min(n - 1, static_cast<size_t>(0.99 * n))) << n;  // the p99 rank
    EXPECT_EQ(s.max, *std::max_element(v.begin(), v.end()));
    EXPECT_NEAR(s.mean, std::accumulate(v.begin(), v.end(), 0.0L) / n, 1e-9);
  }
  const Stats empty = stats_of({});
  EXPECT_EQ(empty.median + empty.p99 + empty.max + empty.mean, 0.0);
}

TEST(Workloads, SummariseTakesTheMedianOfEachStatisticAndTheSpreadOfMedians) {
  const std::vector<Stats> runs = {{5, 9, 12, 6}, {3, 8, 20, 4}, {4, 7, 10, 5}};
  const Summary r = summarise(runs);
  EXPECT_EQ(r.s.median, 4);
  EXPECT_EQ(r.s.p99, 8);
  EXPECT_EQ(r.s.max, 12);
  EXPECT_EQ(r.s.mean, 5);
  EXPECT_EQ(r.spread_lo, 3);
  EXPECT_EQ(r.spread_hi, 5);
}

TEST(Workloads, TimeBatchesRunsEveryWholeBatchOnceInOrder) {
  std::vector<size_t> calls;
  const size_t n = 5 * kBatch + 3;
  const Stats s = time_batches(n, [&](size_t k) { calls.push_back(k); });
  ASSERT_EQ(calls.size(), 5u * kBatch);  // the tail shorter than a batch is not run
  for (size_t k = 0; k < calls.size(); ++k) EXPECT_EQ(calls[k], k);
  EXPECT_GE(s.median, 0.0);
  EXPECT_LE(s.median, s.max);
}

// The default bunny bake's displaced surface, as Embree sees it (independent of the slab code).
struct Surface {
  const SlabModel& model = test::baked_bunny(150, 16);
  TriangleMesh mesh;
  std::unique_ptr<ExactMeshQuery> exact;
  double diag = 0;
  Surface() {
    displaced_surface(model, mesh.vertices, mesh.faces);
    exact = std::make_unique<ExactMeshQuery>(mesh);
    diag = bounds(mesh).diagonal();
  }
};

TEST(Workloads, CoherentPathMovesAtMostAStepPerTickAndStaysNearTheSurface) {
  const Surface s;
  std::mt19937_64 rng(1);
  const double step = s.diag / 1600, depth = 0.005 * s.diag;
  const std::vector<Vec3> path = coherent_path(s.model, 5000, step, depth, rng);
  ASSERT_EQ(path.size(), 5000u);
  double max_step = 0, max_dist = 0;
  for (size_t k = 1; k < path.size(); ++k) max_step = std::max(max_step, (path[k] - path[k - 1]).norm());
  for (const Vec3& p : path) max_dist = std::max(max_dist, s.exact->closest_point(p).distance);
  EXPECT_LE(max_step, step * (1 + 1e-9));
  EXPECT_GT(max_step, 0.5 * step);  // it does move
  // Offsets along the normal are at most `depth`; chords between samples add a little.
  EXPECT_LE(max_dist, depth + 0.002 * s.diag);
}

TEST(Workloads, GlobalPointsLieWithinTheirDistanceOfTheSurface) {
  const Surface s;
  std::mt19937_64 rng(2);
  const double dist = 0.01 * s.diag;
  const std::vector<Vec3> pts = global_points(s.model, 2000, dist, rng);
  ASSERT_EQ(pts.size(), 2000u);
  int far_half = 0;
  for (const Vec3& p : pts) {
    const double d = s.exact->closest_point(p).distance;
    EXPECT_LE(d, dist * (1 + 1e-6) + 1e-6 * s.diag);
    far_half += d > 0.5 * dist;
  }
  EXPECT_GT(far_half, 100);  // spread over [-dist, dist], not all on the surface
}

TEST(Workloads, WarmStrokesEditAndLeaveTheModelAsItWas) {
  SlabModel model = test::baked_bunny(150, 16);
  const SlabLocator locator(model);
  const std::vector<float> before = test::values(model.displacement);
  const std::vector<Srgb8> colour = model.colour.codes();
  const Aabb box = surface_box(model);
  const Workspace ws = fit_workspace(box, 0.16);
  std::mt19937_64 rng(1);
  const double diag = box.diagonal();
  const std::vector<Vec3> path = coherent_path(model, 400, 1e-4 * ws.scale, 0.005 * diag, rng);
  const std::vector<EditRow> rows = warm_strokes(model, locator, ws, path, diag, 200);
  ASSERT_EQ(rows.size(), 2 * brush_registry().size());  // every registered brush at two radii
  for (const EditRow& r : rows) {
    EXPECT_GT(r.ops, 0) << r.tool;
    EXPECT_GT(r.visited, 0) << r.tool;
  }
  EXPECT_EQ(test::values(model.displacement), before);
  EXPECT_EQ(model.colour.codes(), colour);
}

}  // namespace
}  // namespace hdm::bench
