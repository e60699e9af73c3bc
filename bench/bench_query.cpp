// SPDX-License-Identifier: MIT
// The haptic query: coherent (1 kHz path, cache kept) and global (no hint), Newton and bisection.
#include "bench_common.h"

#include <benchmark/benchmark.h>

namespace hdm::bench {
namespace {

void coherent(benchmark::State& state, AlphaSolver solver) {
  const Fixture& f = fixture();
  QueryCache cache;
  size_t k = 0;
  int64_t hits = 0;
  for (auto _ : state) {
    const Contact c = query(f.model, *f.locator, f.path_points[k], cache, solver);
    hits += c.in_shell();
    benchmark::DoNotOptimize(c);
    if (++k == f.path_points.size()) k = 0;
  }
  state.SetItemsProcessed(state.iterations());
  // Points in no slab need the hint's neighbourhood and a grid cell to prove it: they set the cost at 10^5 slabs.
  state.counters["in_shell"] = double(hits) / double(state.iterations());
}

void global(benchmark::State& state, AlphaSolver solver) {
  const Fixture& f = fixture();
  QueryCache cache;
  size_t k = 0;
  int64_t hits = 0;
  for (auto _ : state) {
    cache = QueryCache{};
    const Contact c = query(f.model, *f.locator, f.global_points[k], cache, solver);
    hits += c.in_shell();
    benchmark::DoNotOptimize(c);
    if (++k == f.global_points.size()) k = 0;
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["in_shell"] = double(hits) / double(state.iterations());
}

// The slab search alone (no surface evaluation), to split the global cost.
void global_find(benchmark::State& state) {
  const Fixture& f = fixture();
  size_t k = 0;
  SlabCoordinates c;
  for (auto _ : state) {
    benchmark::DoNotOptimize(f.locator->find(f.global_points[k], -1, AlphaSolver::Newton, c));
    if (++k == f.global_points.size()) k = 0;
  }
  state.SetItemsProcessed(state.iterations());
}

BENCHMARK(global_find);
BENCHMARK_CAPTURE(coherent, newton, AlphaSolver::Newton);
BENCHMARK_CAPTURE(coherent, bisection, AlphaSolver::Bisection);
BENCHMARK_CAPTURE(global, newton, AlphaSolver::Newton);
BENCHMARK_CAPTURE(global, bisection, AlphaSolver::Bisection);

}  // namespace
}  // namespace hdm::bench

BENCHMARK_MAIN();
