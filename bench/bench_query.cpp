// SPDX-License-Identifier: MIT
// The haptic query: coherent (1 kHz path, cache kept) and global (no hint), Newton and bisection.
#include "bench_common.h"

#include "workloads.h"

#include <hdm/haptics/proxy.h>

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

// The slab search alone (no surface evaluation) over @p points; with @p coherent, the previous
// point's slab and α are the hint and the solver's start, as the query's cache keeps them.
void find_only(benchmark::State& state, const std::vector<Vec3>& points, bool coherent) {
  const Fixture& f = fixture();
  size_t k = 0;
  SlabCoordinates c;
  int hint = -1;
  double alpha = -1;
  for (auto _ : state) {
    const int s = f.locator->find(points[k], hint, AlphaSolver::Newton, alpha, c);
    if (coherent && s >= 0) hint = s, alpha = c.alpha;
    benchmark::DoNotOptimize(s);
    if (++k == points.size()) k = 0;
  }
  state.SetItemsProcessed(state.iterations());
}

// The slab search alone, to split the global and the coherent cost.
void global_find(benchmark::State& state) { find_only(state, fixture().global_points, false); }
void coherent_find(benchmark::State& state) { find_only(state, fixture().path_points, true); }

// The proxy tick with friction (default ProxyParams) on the coherent path, as `hdm bench`'s
// proxy_tick_ns: the HIP's query while free, then the surface under the proxy, its material and up
// to three re-projections per tick in contact.
void proxy_tick(benchmark::State& state) {
  const Fixture& f = fixture();
  const Aabb box = surface_box(f.model);
  const Workspace ws = fit_workspace(box, 0.16);
  const std::vector<Vec3> velocity = path_velocity(f.path_points, ws);
  std::vector<Vec3> device(f.path_points.size());
  for (size_t k = 0; k < device.size(); ++k) device[k] = ws.to_device(f.path_points[k]);
  ProxyState ps;
  const ProxyParams pp;
  size_t k = 0;
  int64_t contacts = 0;
  for (auto _ : state) {
    const ProxyOutput o = proxy_step(f.model, *f.locator, ws, device[k], velocity[k], pp, ps);
    contacts += o.status != ProxyStatus::Free;
    benchmark::DoNotOptimize(o);
    if (++k == device.size()) k = 0;
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["contact"] = double(contacts) / double(state.iterations());
}

BENCHMARK(global_find);
BENCHMARK(coherent_find);
BENCHMARK(proxy_tick);
BENCHMARK_CAPTURE(coherent, newton, AlphaSolver::Newton);
BENCHMARK_CAPTURE(coherent, bisection, AlphaSolver::Bisection);
BENCHMARK_CAPTURE(global, newton, AlphaSolver::Newton);
BENCHMARK_CAPTURE(global, bisection, AlphaSolver::Bisection);

}  // namespace
}  // namespace hdm::bench

BENCHMARK_MAIN();
