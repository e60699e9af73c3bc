// SPDX-License-Identifier: MIT
// The alpha-plane solve alone (locate_in_slab on a point known to be in the slab): bisection (the
// paper's 15 steps) against Newton.
#include "bench_common.h"

#include <benchmark/benchmark.h>

namespace hdm::bench {
namespace {

struct Case {
  int slab;
  Vec3 p;
};

const std::vector<Case>& cases() {
  static const std::vector<Case> c = [] {
    const Fixture& f = fixture();
    std::vector<Case> out;
    QueryCache cache;
    for (const Vec3& p : f.global_points) {
      cache.last_slab = -1;
      const Contact q = query(f.model, *f.locator, p, cache);
      if (q.in_shell()) out.push_back({q.slab, p});
    }
    return out;
  }();
  return c;
}

void solve(benchmark::State& state, AlphaSolver solver) {
  const Fixture& f = fixture();
  const std::vector<Case>& c = cases();
  size_t k = 0;
  SlabCoordinates sc;
  for (auto _ : state) {
    benchmark::DoNotOptimize(locate_in_slab(f.model.geometry[c[k].slab], c[k].p, solver, sc));
    benchmark::DoNotOptimize(sc);
    if (++k == c.size()) k = 0;
  }
  state.SetItemsProcessed(state.iterations());
}

BENCHMARK_CAPTURE(solve, bisection, AlphaSolver::Bisection);
BENCHMARK_CAPTURE(solve, newton, AlphaSolver::Newton);

}  // namespace
}  // namespace hdm::bench

BENCHMARK_MAIN();
