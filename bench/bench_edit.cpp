// SPDX-License-Identifier: MIT
// Edits per visited sample (texel for paint), two workloads:
// - stroke (warm): the tool slides along the surface at 20 mm/s of device motion (the model's
//   diagonal on a 16 cm workspace), one tool position per 1 kHz tick. New: StrokeEditor sweeps
//   the brush from the last position to this one (a capsule). Against it in the same run, a stamp
//   at every tick (edit_tools.h's carve, add_material, paint: the paper's single stamps). Arg: tool
//   radius in thousandths of the diagonal.
// - stamp (cold): single edits at 1024 random places (what a 10 Hz edit meets), restored after.
// Counters: ns_per_visited (the benchmark's target: 30 ns), ns_per_changed, visited and changed
// per op. Edits include the slab-major copies, normals of the changed samples' rings, force-shading normals,
// dirty-slab marking and (strokes) undo recording.
#include "bench_common.h"
#include "workloads.h"
#include <hdm/edit/brush_registry.h>
#include <hdm/edit/edit_tools.h>
#include <hdm/edit/stroke_editor.h>
#include <hdm/slab/slab_snapshots.h>

#include <benchmark/benchmark.h>

#include <map>
#include <random>
#include <string>

namespace hdm::bench {
namespace {

// Restores the edited members from the fixture's model (paused: not timed).
void restore(SlabModel& m, const SlabModel& from) {
  m.displacement = from.displacement;
  m.slab_samples = from.slab_samples;
  m.colour = from.colour;
  m.roughness = from.roughness;
}

// A 1 kHz tool path at 20 mm/s (device scale) over the surface: surface points found by walking the
// sample graph (coherent_path, workloads.h), the HIP `depth` under each along the normal, and the
// contact of the HIP on the unedited model.
struct Path {
  std::vector<Vec3> hip;
  std::vector<Contact> contact;
};

const Path& stroke_path(double depth_frac) {
  static std::map<double, Path> cache;
  Path& p = cache[depth_frac];
  if (!p.hip.empty()) return p;
  const Fixture& f = fixture();
  const double step = 0.02e-3 * f.diagonal / 0.16;  // 20 mm/s at 1 kHz, 16 cm workspace
  const double depth = depth_frac * f.diagonal;
  QueryCache qc;
  for (size_t k = 0; k + 1 < f.path_points.size() && p.hip.size() < 4000; ++k) {
    // path_points are ≤ diagonal/1600 apart (~0.1 mm): subdivide to the tick step.
    const Vec3 a = f.path_points[k], b = f.path_points[k + 1];
    const int n = std::max(1, static_cast<int>((b - a).norm() / step));
    for (int i = 0; i < n; ++i) {
      const Vec3 x = a + (b - a) * (double(i) / n);
      Contact c = query(f.model, *f.locator, x, qc);
      if (!c.in_shell()) continue;
      // Put the HIP `depth` under the surface point of its projection line.
      const Vec3 hip = c.surface_point - depth * c.normal;
      c = query(f.model, *f.locator, hip, qc);
      if (!c.in_shell()) continue;
      p.hip.push_back(hip);
      p.contact.push_back(c);
    }
  }
  return p;
}

void report(benchmark::State& state, int64_t visited, int64_t changed) {
  state.counters["visited_per_op"] = benchmark::Counter(double(visited) / state.iterations());
  state.counters["changed_per_op"] = benchmark::Counter(double(changed) / state.iterations());
  state.counters["ns_per_visited"] =
      benchmark::Counter(double(visited), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["ns_per_changed"] =
      benchmark::Counter(double(changed), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// One iteration = one servo tick of a stroke: StrokeEditor::add_sample + work to the end.
void stroke(benchmark::State& state, BrushTool tool) {
  const Fixture& f = fixture();
  const double radius = state.range(0) / 1000.0 * f.diagonal;
  const Path& path = stroke_path(0.2 * state.range(0) / 1000.0);
  SlabModel m = f.model;
  StrokeEditor editor(m);
  const Brush brush = workload_brush(tool, radius);
  int64_t visited = 0, changed = 0;
  size_t k = 0;
  editor.begin_stroke(brush);
  for (auto _ : state) {
    if (k == path.hip.size()) {
      state.PauseTiming();
      editor.end_stroke();
      editor.work(m, INT64_MAX);
      restore(m, f.model);
      editor.begin_stroke(brush);
      k = 0;
      state.ResumeTiming();
    }
    ToolSample t;
    t.contact = path.contact[k];
    t.hip = path.hip[k];
    t.normal_force_n = 0.55;  // half pressure
    t.time_s = 1e-3 * double(k);
    editor.add_sample(m, t);
    const EditWork w = editor.work(m, INT64_MAX);
    visited += w.visited, changed += w.changed;
    ++k;
  }
  report(state, visited, changed);
}

// The same path with a stamp per tick (edit_tools.h's single stamps).
void stroke_stamps(benchmark::State& state, BrushTool tool) {
  const Fixture& f = fixture();
  const double radius = state.range(0) / 1000.0 * f.diagonal;
  const Path& path = stroke_path(0.2 * state.range(0) / 1000.0);
  SlabModel m = f.model;
  EditScratch scratch(m);
  int64_t visited = 0, changed = 0;
  size_t k = 0;
  for (auto _ : state) {
    if (k == path.hip.size()) {
      state.PauseTiming();
      restore(m, f.model);
      k = 0;
      state.ResumeTiming();
    }
    EditResult r;
    switch (tool) {
      case BrushTool::Carve:
        r = carve(m, scratch, path.contact[k], path.hip[k], radius, 0.0);
        break;
      case BrushTool::Add:
        r = add_material(m, scratch, path.contact[k], radius, 0.001 * radius);
        break;
      default:
        r = paint(m, scratch, path.contact[k], radius, Vec3f(0.8f, 0.1f, 0.1f), 0.5);
        break;
    }
    visited += r.visited, changed += r.changed;
    ++k;
  }
  report(state, visited, changed);
}

// Single edits at random places: the cold case (hip 0.2·radius below the surface).
void stamp(benchmark::State& state, BrushTool tool) {
  const Fixture& f = fixture();
  SlabModel m = f.model;
  EditScratch scratch(m);
  const double radius = state.range(0) / 1000.0 * f.diagonal;
  constexpr int kOps = 1024;
  std::mt19937_64 rng(3);
  std::uniform_int_distribution<int32_t> pick(0, m.samples.count - 1);
  std::vector<Vec3> hips;
  std::vector<Contact> contacts;
  while (contacts.size() < kOps) {
    const int32_t s = pick(rng);
    const Vec3 hip = float_point(m, s) - 0.2 * radius * sample_normal(m, s).cast<double>();
    QueryCache qc;
    const Contact c = query(m, *f.locator, hip, qc);
    if (c.in_shell()) hips.push_back(hip), contacts.push_back(c);
  }
  int64_t visited = 0, changed = 0, k = 0;
  for (auto _ : state) {
    if (k == kOps) {
      state.PauseTiming();
      restore(m, f.model);
      k = 0;
      state.ResumeTiming();
    }
    EditResult r;
    switch (tool) {
      case BrushTool::Carve:
        r = carve(m, scratch, contacts[k], hips[k], radius, 0.0);
        break;
      case BrushTool::Add:
        r = add_material(m, scratch, contacts[k], radius, 0.1 * radius);
        break;
      default:
        r = paint(m, scratch, contacts[k], radius, Vec3f(0.8f, 0.1f, 0.1f), 0.5);
        break;
    }
    visited += r.visited, changed += r.changed;
    ++k;
  }
  report(state, visited, changed);
}

// Copy on write for readers: the first write of Arg slabs after a publication copies each into a
// spare version (SlabSnapshots::before_write), then one commit publishes them (what SculptSession
// does between sweeps). Counter ns_per_slab. With an edit thread instead of edits in the servo
// tick, the proxy would need such a copy of every slab an edit touched before it could feel the edit.
void publish(benchmark::State& state) {
  const Fixture& f = fixture();
  SnapshotOptions o;
  o.spare_versions = 128;
  SlabSnapshots snaps(f.model, o);
  const int count = static_cast<int>(state.range(0));
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<int> pick(0, f.model.slab_count() - count);
  int64_t slabs = 0;
  for (auto _ : state) {
    const int first = pick(rng);
    for (int s = first; s < first + count; ++s) benchmark::DoNotOptimize(snaps.before_write(s));
    benchmark::DoNotOptimize(snaps.publish_commit());
    slabs += count;
  }
  state.counters["ns_per_slab"] =
      benchmark::Counter(double(slabs), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(publish)->Arg(1)->Arg(8)->Arg(64);

// The paper's single stamps (edit_tools.h): carve, add_material and paint.
BENCHMARK_CAPTURE(stroke_stamps, carve, BrushTool::Carve)->Arg(10)->Arg(20);
BENCHMARK_CAPTURE(stroke_stamps, add, BrushTool::Add)->Arg(10)->Arg(20);
BENCHMARK_CAPTURE(stroke_stamps, paint, BrushTool::Paint)->Arg(10)->Arg(20);
BENCHMARK_CAPTURE(stamp, carve, BrushTool::Carve)->Arg(10)->Arg(20);
BENCHMARK_CAPTURE(stamp, add, BrushTool::Add)->Arg(10)->Arg(20);
BENCHMARK_CAPTURE(stamp, paint, BrushTool::Paint)->Arg(10)->Arg(20);

}  // namespace
}  // namespace hdm::bench

// Strokes of every registered brush: stroke/<name>/<radius>.
int main(int argc, char** argv) {
  for (const hdm::BrushInfo& b : hdm::brush_registry())
    benchmark::RegisterBenchmark((std::string("stroke/") + b.name).c_str(), hdm::bench::stroke, b.tool)
        ->Arg(10)
        ->Arg(20);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
