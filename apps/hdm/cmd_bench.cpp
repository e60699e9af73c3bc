// SPDX-License-Identifier: MIT
// hdm bench: bakes a model, then times the haptic query against the exact alternative (Embree
// closest point + inside test) on the same points in the same run (docs/performance.md), and
// against CGAL's AABB-tree closest point as a second baseline. This file holds the command line and
// the report; the workloads, timers and statistics are bench/workloads.h (shared with the
// micro-benchmarks), which also describes the timing method.
#include "commands.h"
#include "workloads.h"

#include <hdm/analysis/cgal_closest_point.h>
#include <hdm/core/error.h>
#include <hdm/io/read_mesh.h>
#include <hdm/mesh/split_faces.h>
#include <hdm/slab/bake.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace hdm::app {
namespace {

using namespace hdm::bench;

struct BenchArgs {
  std::string model;
  int slabs = 0, grid = 16, texels = 2, repeat = 5, ticks = 20000, points = 20000, subdivide = 0;
  bool json = false, no_separate = false, no_cgal = false;
  uint64_t seed = 1;
};

// Default model: the repository's data/meshes/bunny00.off. HDM_DEFAULT_SCRIPT (set by
// apps/hdm/CMakeLists.txt) is <repo>/data/scripts/..., so the repository's data directory is known at
// compile time; if it has moved, fall back to <executable>/../../data/meshes (build-*/bin/hdm).
std::string default_model() {
  namespace fs = std::filesystem;
  const fs::path compiled = fs::path(HDM_DEFAULT_SCRIPT).parent_path().parent_path() / "meshes/bunny00.off";
  if (fs::exists(compiled)) return compiled.string();
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return (exe.parent_path() / "../../data/meshes/bunny00.off").lexically_normal().string();
}

nlohmann::json to_json(const Summary& s) {
  return {{"median", s.s.median},
          {"p99", s.s.p99},
          {"max", s.s.max},
          {"mean", s.s.mean},
          {"spread", {s.spread_lo, s.spread_hi}}};
}

// The input as benchmarked: the file, subdivided --subdivide times and until it has more
// triangles than --slabs.
struct BenchInput {
  std::string path;
  TriangleMesh mesh;
  int64_t file_triangles = 0;
  int subdivisions = 0;
};

BenchInput read_bench_input(const BenchArgs& a) {
  BenchInput in;
  in.path = a.model.empty() ? default_model() : a.model;
  in.mesh = read_mesh(in.path);
  in.file_triangles = static_cast<int64_t>(in.mesh.faces.size());
  for (; in.subdivisions < a.subdivide; ++in.subdivisions)
    in.mesh = split_faces(in.mesh);  // a larger baseline input
  while (a.slabs > 0 && static_cast<int64_t>(in.mesh.faces.size()) <= a.slabs)
    in.mesh = split_faces(in.mesh), ++in.subdivisions;
  return in;
}

// ns per visited (or changed) sample of the rows whose tool passes @p take.
template <class Take>
double ns_per(const std::vector<EditRow>& rows, Take take, bool changed = false) {
  double ns = 0, n = 0;
  for (const EditRow& e : rows)
    if (take(e)) ns += e.ns, n += changed ? e.changed : e.visited;
  return n > 0 ? ns / n : 0.0;
}

// The edit figures of the report: warm strokes at 1 kHz and cold single stamps.
nlohmann::json edit_figures(const std::vector<EditRow>& warm, const std::vector<EditRow>& edits) {
  auto warm_tool = [&](const char* tool) {
    return ns_per(warm, [&](const EditRow& e) { return std::string(e.tool) == tool; });
  };
  auto cold = [&](char tool, bool changed) {
    return ns_per(
        edits, [&](const EditRow& e) { return e.tool[0] == tool; }, changed);
  };
  nlohmann::json edit_rows = nlohmann::json::array(), warm_rows = nlohmann::json::array();
  for (const EditRow& e : warm)
    warm_rows.push_back({{"tool", e.tool},
                         {"radius_pct_diagonal", e.radius_pct},
                         {"ticks", e.ops},
                         {"visited", e.visited},
                         {"changed", e.changed},
                         {"ns_per_tick", e.ops ? e.ns / e.ops : 0.0},
                         {"ns_per_visited", e.visited ? e.ns / e.visited : 0.0},
                         {"ns_per_changed", e.changed ? e.ns / e.changed : 0.0}});
  for (const EditRow& e : edits)
    edit_rows.push_back({{"tool", e.tool},
                         {"radius_pct_diagonal", e.radius_pct},
                         {"ops", e.ops},
                         {"visited", e.visited},
                         {"changed", e.changed},
                         {"ns_per_op", e.ops ? e.ns / e.ops : 0.0},
                         {"ns_per_visited", e.visited ? e.ns / e.visited : 0.0}});
  return {{"edit_ns_per_sample", ns_per(edits, [](const EditRow& e) { return e.tool[0] != 'p'; })},  // carve + add
          {"edit_ns_per_visited",
           {{"carve", cold('c', false)}, {"add", cold('a', false)}, {"paint_per_texel", cold('p', false)}}},
          {"edit_ns_per_changed",
           {{"carve", cold('c', true)}, {"add", cold('a', true)}, {"paint_per_texel", cold('p', true)}}},
          {"edits", edit_rows},
          {"edit_warm_ns_per_visited",
           {{"carve", warm_tool("carve")},
            {"add", warm_tool("add")},
            {"smooth", warm_tool("smooth")},
            {"flatten", warm_tool("flatten")},
            {"paint_per_texel", warm_tool("paint")}}},
          {"edits_warm", warm_rows}};
}

// The latency figures of the report: hdm's query, tick and proxy tick against Embree and CGAL.
nlohmann::json latency_figures(const LatencyRuns& lat, bool with_cgal, double cgal_build_s) {
  const Summary s_coh = summarise(lat.coherent), s_glo = summarise(lat.global), s_tick = summarise(lat.tick),
                s_ecoh = summarise(lat.embree_coherent), s_eglo = summarise(lat.embree_global);
  const bool have_proxy = !lat.proxy_tick.empty();
  const Summary s_ccoh = with_cgal ? summarise(lat.cgal_coherent) : Summary{},
                s_cglo = with_cgal ? summarise(lat.cgal_global) : Summary{};
  const nlohmann::json none;
  return {{"hdm",
           {{"coherent_ns", to_json(s_coh)},
            {"global_ns", to_json(s_glo)},
            {"tick_ns", to_json(s_tick)},
            {"proxy_tick_ns", have_proxy ? to_json(summarise(lat.proxy_tick)) : none},
            {"sphere_tick_ns", lat.sphere_tick.empty() ? none : to_json(summarise(lat.sphere_tick))},
            {"rigid_tick_ns", lat.rigid_tick.empty() ? none : to_json(summarise(lat.rigid_tick))}}},
          {"baseline",
           {{"embree_ns", to_json(s_ecoh)},
            {"embree_global_ns", to_json(s_eglo)},
            {"cgal_closest_ns", with_cgal ? to_json(s_ccoh) : none},
            {"cgal_closest_global_ns", with_cgal ? to_json(s_cglo) : none},
            {"cgal_build_s", with_cgal ? nlohmann::json(cgal_build_s) : none}}},
          {"ratio_coherent", s_ecoh.s.median / s_coh.s.median},
          {"ratio_global", s_eglo.s.median / s_glo.s.median},
          {"ratio_cgal_coherent", with_cgal ? nlohmann::json(s_ccoh.s.median / s_coh.s.median) : none},
          {"ratio_cgal_global", with_cgal ? nlohmann::json(s_cglo.s.median / s_glo.s.median) : none}};
}

// The report as text, from its JSON form.
void print_report(const nlohmann::json& j) {
  const auto d = [](const nlohmann::json& v) { return v.get<double>(); };
  std::printf("hdm bench: %s, %lld input triangles (%d subdivisions), %d slabs, n = %d, %d samples\n",
              j["model"].get<std::string>().c_str(), (long long)j["input_triangles"].get<int64_t>(),
              j["subdivisions"].get<int>(), j["slabs"].get<int>(), j["grid"].get<int>(), j["samples"].get<int>());
  std::printf("  %d repeats; latency per query from batches of %d, median over repeats [spread of medians]\n",
              j["repeat"].get<int>(), j["batch"].get<int>());
  std::printf("  %-34s %9s %9s %9s %9s  %s\n", "latency [ns]", "median", "p99", "max", "mean", "spread");
  auto row = [&](const char* name, const nlohmann::json& s) {
    if (s.is_null()) return;
    std::printf("  %-34s %9.0f %9.0f %9.0f %9.0f  [%.0f..%.0f]\n", name, d(s["median"]), d(s["p99"]), d(s["max"]),
                d(s["mean"]), d(s["spread"][0]), d(s["spread"][1]));
  };
  const nlohmann::json &h = j["hdm"], &b = j["baseline"];
  row("hdm coherent (1 kHz path)", h["coherent_ns"]);
  row("hdm global (random near-surface)", h["global_ns"]);
  row("hdm servo tick (query + force)", h["tick_ns"]);
  row("hdm servo tick (proxy_step)", h["proxy_tick_ns"]);
  row("hdm sphere proxy tick, r = 1 %", h["sphere_tick_ns"]);
  row("hdm rigid tool tick, 1,000 points", h["rigid_tick_ns"]);
  row("Embree closest+inside, path pts", b["embree_ns"]);
  row("Embree closest+inside, global pts", b["embree_global_ns"]);
  row("CGAL AABB closest, path pts", b["cgal_closest_ns"]);
  row("CGAL AABB closest, global pts", b["cgal_closest_global_ns"]);
  std::printf("  speed-up vs Embree (median)       coherent %.1fx, global %.1fx\n", d(j["ratio_coherent"]),
              d(j["ratio_global"]));
  if (!b["cgal_build_s"].is_null())
    std::printf("  speed-up vs CGAL closest (median) coherent %.1fx, global %.1fx (tree built in %.2f s)\n",
                d(j["ratio_cgal_coherent"]), d(j["ratio_cgal_global"]), d(b["cgal_build_s"]));
  std::printf("  points in shell                   coherent %.1f%%, global %.1f%%; max path step %.3f mm\n",
              100 * d(j["in_shell_fraction"]["coherent"]), 100 * d(j["in_shell_fraction"]["global"]),
              d(j["trajectory_max_step_mm"]));
  std::printf("  ticks in contact                  penalty %.1f%%, rigid tool %.1f%%\n", 100 * d(j["contact_fraction"]),
              100 * d(j["rigid_contact_fraction"]));
  const nlohmann::json &w = j["edit_warm_ns_per_visited"], &v = j["edit_ns_per_visited"], &c = j["edit_ns_per_changed"];
  std::printf(
      "  edits, warm strokes at 1 kHz      carve %.1f, add %.1f, smooth %.1f, flatten %.1f ns per visited sample, "
      "paint %.1f per texel\n",
      d(w["carve"]), d(w["add"]), d(w["smooth"]), d(w["flatten"]), d(w["paint_per_texel"]));
  std::printf("  edits, cold stamps [ns per visited] carve %.1f, add %.1f, paint %.1f per texel\n", d(v["carve"]),
              d(v["add"]), d(v["paint_per_texel"]));
  std::printf("  edits, cold stamps [ns per changed] carve %.1f, add %.1f, paint %.1f per texel\n", d(c["carve"]),
              d(c["add"]), d(c["paint_per_texel"]));
  std::printf("  bake                              %.2f s (locator %.3f s)\n", d(j["bake_s"]), d(j["locator_build_s"]));
  std::printf("  memory                            %.1f B/sample, %.0f B/slab, %.1f B/texel, peak RSS %.0f MB\n",
              d(j["bytes_per_sample"]), d(j["bytes_per_slab"]), d(j["bytes_per_texel"]), d(j["peak_rss_mb"]));
}

void run_bench(const BenchArgs& a) {
  const BenchInput in = read_bench_input(a);
  const TriangleMesh& mesh = in.mesh;
  const std::string& path = in.path;
  const double diag = bounds(mesh).diagonal();

  // ---- (e) bake ----
  BakeOptions bo;
  bo.slabs = a.slabs;
  bo.grid_n = a.grid;
  bo.texel_density = a.texels;
  bo.separate_slabs = !a.no_separate;
  BakeReport br;
  const auto b0 = Clock::now();
  SlabModel model = bake_slabs(mesh, path, bo, &br);
  const double bake_s = seconds_since(b0);
  const auto l0 = Clock::now();
  const SlabLocator locator(model);
  const double locator_s = seconds_since(l0);
  const ExactMeshQuery exact(mesh);
  // The second baseline, CGAL's AABB tree (closest point only), unless --no-cgal.
  const std::unique_ptr<CgalClosestPoint> cgal = a.no_cgal ? nullptr : std::make_unique<CgalClosestPoint>(mesh);

  // ---- points: device scale maps the diagonal onto a 16 cm workspace ----
  std::mt19937_64 rng(a.seed);
  const Aabb box = surface_box(model);
  const Workspace ws = fit_workspace(box, 0.16);
  const double step = 1e-4 * ws.scale;  // <= 0.1 mm of device motion per 1 ms tick (0.1 m/s)
  const std::vector<Vec3> path_pts = coherent_path(model, a.ticks, step, 0.005 * diag, rng);
  const std::vector<Vec3> global_pts = global_points(model, a.points, 0.01 * diag, rng);
  double max_step = 0;
  for (size_t k = 1; k < path_pts.size(); ++k) max_step = std::max(max_step, (path_pts[k] - path_pts[k - 1]).norm());
  const std::vector<Vec3> velocity = path_velocity(path_pts, ws);

  // ---- (a)-(c) latency, hdm and the baselines interleaved in each repeat ----
  const LatencyRuns lat = time_queries(model, locator, exact, cgal.get(), ws, path_pts, velocity, global_pts, a.repeat);
  nlohmann::json j = latency_figures(lat, cgal != nullptr, cgal ? cgal->build_seconds() : 0.0);

  // ---- (d) edits vs touched samples: last, on the model itself (a copy would double peak memory) ----
  const std::vector<EditRow> warm = warm_strokes(model, locator, ws, path_pts, diag, 2000);
  const std::vector<EditRow> edits = cold_stamps(model, locator, diag, rng);
  j.update(edit_figures(warm, edits));

  // ---- (f) memory ----
  const ModelBytes mb = model_bytes(model, locator);
  const int S = model.slab_count();
  j.update({{"model", path},
            {"subdivisions", in.subdivisions},
            {"file_triangles", in.file_triangles},
            {"input_triangles", static_cast<int64_t>(mesh.faces.size())},
            {"slabs", S},
            {"grid", model.grid_n},
            {"samples", model.samples.count},
            {"repeat", a.repeat},
            {"batch", kBatch},
            {"ticks", path_pts.size()},
            {"global_points", global_pts.size()},
            {"trajectory_max_step_mm", max_step / ws.scale * 1000},
            {"in_shell_fraction",
             {{"coherent", double(lat.in_shell_coherent) / path_pts.size()},
              {"global", double(lat.in_shell_global) / global_pts.size()}}},
            {"contact_fraction", double(lat.contacts) / path_pts.size()},
            {"rigid_contact_fraction", double(lat.rigid_contacts) / path_pts.size()},
            {"bake_s", bake_s},
            {"bake_separate_slabs", !a.no_separate},
            {"bake_report_s", br.seconds},
            {"locator_build_s", locator_s},
            {"bytes_per_sample", double(mb.samples) / model.samples.count},
            {"bytes_per_slab", double(mb.slabs) / S},
            {"bytes_per_texel", double(mb.texels) / model.texels.count},
            {"model_bytes", mb.samples + mb.texels + mb.slabs},
            {"peak_rss_mb", peak_rss_mb()}});
  if (a.json)
    std::printf("%s\n", j.dump(2).c_str());
  else
    print_report(j);
}

}  // namespace

void add_bench_command(CLI::App& app) {
  auto a = std::make_shared<BenchArgs>();
  CLI::App* cmd =
      app.add_subcommand("bench", "Bake a model and time the haptic query, servo tick, edits and bake against Embree");
  cmd->add_option("--model", a->model, "input mesh (default: <repository>/data/meshes/bunny00.off)");
  cmd->add_option("--slabs", a->slabs,
                  "target slab count (default: input triangles * 4 / n^2); the input is "
                  "subdivided 1-to-4 until it has more triangles")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--grid", a->grid, "displacement intervals per slab edge n")->check(CLI::Range(1, 256));
  cmd->add_option("--subdivide", a->subdivide,
                  "subdivide the input 1-to-4 this many times first (same shape, 4^k triangles: the baselines' input "
                  "grows, the slab model does not)")
      ->check(CLI::Range(0, 4));
  cmd->add_option("--texels", a->texels, "colour texels per displacement interval (1 saves memory at 10^5 slabs)")
      ->check(CLI::Range(1, 16));
  cmd->add_option("--repeat", a->repeat, "repeats of every latency measurement")->check(CLI::Range(1, 1000));
  cmd->add_option("--ticks", a->ticks, "ticks of the coherent 1 kHz path")->check(CLI::Range(kBatch, 10000000));
  cmd->add_option("--points", a->points, "global query points")->check(CLI::Range(kBatch, 10000000));
  cmd->add_option("--seed", a->seed, "random seed of the points");
  cmd->add_flag("--no-separate-slabs", a->no_separate,
                "bake without thinning overlapping slabs apart (much faster at 10^4+ slabs)");
  cmd->add_flag("--no-cgal", a->no_cgal, "skip the second baseline (CGAL's AABB tree closest point)");
  cmd->add_flag("--json", a->json, "print one JSON object");
  cmd->callback([a] { run_bench(*a); });
}

}  // namespace hdm::app
