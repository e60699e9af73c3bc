// SPDX-License-Identifier: MIT
// The exact alternative hdm is measured against: Embree closest point plus ray-parity inside test
// on the input mesh, on the same points as bench_query.
#include "bench_common.h"

#include <benchmark/benchmark.h>

namespace hdm::bench {
namespace {

const ExactMeshQuery& exact() {
  static const ExactMeshQuery q(fixture().mesh);
  return q;
}

void embree(benchmark::State& state, bool closest, bool inside, bool coherent) {
  const Fixture& f = fixture();
  const std::vector<Vec3>& pts = coherent ? f.path_points : f.global_points;
  const ExactMeshQuery& q = exact();
  size_t k = 0;
  for (auto _ : state) {
    if (closest) benchmark::DoNotOptimize(q.closest_point(pts[k]));
    if (inside) benchmark::DoNotOptimize(q.inside(pts[k]));
    if (++k == pts.size()) k = 0;
  }
  state.SetItemsProcessed(state.iterations());
}

BENCHMARK_CAPTURE(embree, closest_inside_path, true, true, true);
BENCHMARK_CAPTURE(embree, closest_inside_global, true, true, false);
BENCHMARK_CAPTURE(embree, closest_only_global, true, false, false);
BENCHMARK_CAPTURE(embree, inside_only_global, false, true, false);

}  // namespace
}  // namespace hdm::bench

BENCHMARK_MAIN();
