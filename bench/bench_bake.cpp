// SPDX-License-Identifier: MIT
// Bake time against the slab count (Arg; 0 = input triangles / n²) on the fixture's input mesh.
#include "bench_common.h"

#include <hdm/io/read_mesh.h>
#include <hdm/slab/bake.h>

#include <benchmark/benchmark.h>

namespace hdm::bench {
namespace {

void bake(benchmark::State& state) {
  const TriangleMesh mesh = read_mesh(model_path());
  BakeOptions o;
  o.slabs = static_cast<int>(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(bake_slabs(mesh, model_path(), o));
  state.counters["input_triangles"] = double(mesh.faces.size());
}

BENCHMARK(bake)->Arg(0)->Arg(150)->Arg(1000)->Arg(4000)->Unit(benchmark::kMillisecond)->Iterations(2);

}  // namespace
}  // namespace hdm::bench

BENCHMARK_MAIN();
