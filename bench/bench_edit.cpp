// SPDX-License-Identifier: MIT
// Edits per touched sample: carve, add and paint with a tool radius of Arg/10 % of the diagonal.
// Edits are timed one by one at 1024 random places, then the model is restored.
// Counter ns_per_sample: time per sample (texel for paint) visited by the flood fill, including
// position and normal updates and dirty-slab marking.
#include "bench_common.h"

#include <hdm/edit/edit_tools.h>

#include <benchmark/benchmark.h>

#include <random>

namespace hdm::bench {
namespace {

enum class Tool { Carve, Add, Paint };

void edit(benchmark::State& state, Tool tool) {
  const Fixture& f = fixture();
  SlabModel m = f.model;  // edited copy, restored every kOps edits so the surface stays comparable
  EditScratch scratch(m);
  const double radius = state.range(0) / 1000.0 * f.diagonal;
  // Contacts precomputed on the unedited model: a hip 0.2·radius below the surface at random samples.
  // 1024 places between restores: each edit lands where the previous ones did not warm the cache
  // (an edit at 10 Hz finds the model cold), and the restore's own cache traffic, paused but not
  // free, is spread over many edits.
  constexpr int kOps = 1024;
  std::mt19937_64 rng(3);
  std::uniform_int_distribution<int32_t> pick(0, m.samples.count - 1);
  std::vector<Vec3> hips;
  std::vector<Contact> contacts;
  while (contacts.size() < kOps) {
    const int32_t s = pick(rng);
    const Vec3 hip = m.positions[s].cast<double>() - 0.2 * radius * m.normals[s].cast<double>();
    QueryCache qc;
    const Contact c = query(m, *f.locator, hip, qc);
    if (c.in_shell()) hips.push_back(hip), contacts.push_back(c);
  }
  int64_t visited = 0, k = 0;
  for (auto _ : state) {
    if (k == kOps) {
      state.PauseTiming();
      m.displacement = f.model.displacement;
      m.positions = f.model.positions;
      m.normals = f.model.normals;
      m.slab_samples = f.model.slab_samples;
      m.colour = f.model.colour;
      k = 0;
      state.ResumeTiming();
    }
    EditResult r;
    switch (tool) {
      case Tool::Carve: r = carve(m, scratch, contacts[k], hips[k], radius, 0.0); break;
      case Tool::Add: r = add_material(m, scratch, contacts[k], radius, 0.1 * radius); break;
      case Tool::Paint: r = paint(m, scratch, contacts[k], radius, Vec3f(0.8f, 0.1f, 0.1f), 0.5); break;
    }
    visited += r.visited;
    ++k;
  }
  state.counters["visited_per_op"] = benchmark::Counter(double(visited) / state.iterations());
  state.counters["ns_per_sample"] = benchmark::Counter(
      double(visited), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

BENCHMARK_CAPTURE(edit, carve, Tool::Carve)->Arg(5)->Arg(10)->Arg(20);
BENCHMARK_CAPTURE(edit, add, Tool::Add)->Arg(5)->Arg(10)->Arg(20);
BENCHMARK_CAPTURE(edit, paint, Tool::Paint)->Arg(5)->Arg(10)->Arg(20);

}  // namespace
}  // namespace hdm::bench

BENCHMARK_MAIN();
