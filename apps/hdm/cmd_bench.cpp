// SPDX-License-Identifier: MIT
// hdm bench: bakes a model, then times the haptic query against the exact alternative (Embree
// closest point + inside test) on the same points in the same run (design README, "How we
// measure"; docs/performance.md), and against CGAL's AABB-tree closest point as a second baseline.
//
// Timing method: every latency figure is a distribution over batches of kBatch consecutive
// queries, each batch timed with two steady_clock reads and divided by kBatch, so the timer's own
// cost (~20-40 ns) is spread over the batch. Median and p99 are over batches; max is the slowest
// batch mean (a single slow query shows up diluted by kBatch). Each measurement is repeated
// --repeat times, interleaving hdm and Embree so machine noise hits both; the figures reported are
// the median over repeats, with the spread (min..max of the repeat medians).
#include "commands.h"

#include <hdm/analysis/cgal_closest_point.h>
#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/core/error.h>
#include <hdm/edit/edit_tools.h>
#include <hdm/edit/stroke_editor.h>
#include <hdm/haptics/force.h>
#if __has_include(<hdm/haptics/proxy.h>)
#include <hdm/haptics/proxy.h>
#define HDM_BENCH_PROXY 1
#endif
#include <hdm/io/read_mesh.h>
#include <hdm/slab/bake.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <random>
#include <unistd.h>

namespace hdm::app {
namespace {

constexpr int kBatch = 16;  // queries per timed batch
using Clock = std::chrono::steady_clock;

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

// 1-to-4 midpoint subdivision (geometry unchanged, 4x triangles): gives the bake enough input
// triangles for large slab counts.
TriangleMesh subdivide(const TriangleMesh& in) {
  TriangleMesh out;
  out.vertices = in.vertices;
  std::map<std::pair<int32_t, int32_t>, int32_t> mid;
  auto midpoint = [&](int32_t a, int32_t b) {
    const auto key = std::minmax(a, b);
    auto [it, fresh] = mid.try_emplace({key.first, key.second}, static_cast<int32_t>(out.vertices.size()));
    if (fresh) out.vertices.push_back(0.5 * (in.vertices[a] + in.vertices[b]));
    return it->second;
  };
  out.faces.reserve(4 * in.faces.size());
  for (const Tri& f : in.faces) {
    const int32_t ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
    out.faces.push_back({f[0], ab, ca});
    out.faces.push_back({ab, f[1], bc});
    out.faces.push_back({ca, bc, f[2]});
    out.faces.push_back({ab, bc, ca});
  }
  return out;
}

struct Stats {
  double median = 0, p99 = 0, max = 0, mean = 0;
};

Stats stats_of(std::vector<double> v) {
  Stats s;
  if (v.empty()) return s;
  double sum = 0;
  for (double x : v) sum += x;
  s.mean = sum / v.size();
  std::sort(v.begin(), v.end());
  s.median = v[v.size() / 2];
  s.p99 = v[std::min(v.size() - 1, static_cast<size_t>(0.99 * v.size()))];
  s.max = v.back();
  return s;
}

// Median over repeats of each statistic, plus the spread of the medians.
struct Summary {
  Stats s;
  double spread_lo = 0, spread_hi = 0;
};

Summary summarise(const std::vector<Stats>& runs) {
  Summary r;
  auto med = [&](double Stats::*f) {
    std::vector<double> v;
    for (const Stats& s : runs) v.push_back(s.*f);
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  r.s = {med(&Stats::median), med(&Stats::p99), med(&Stats::max), med(&Stats::mean)};
  r.spread_lo = r.spread_hi = runs[0].median;
  for (const Stats& s : runs)
    r.spread_lo = std::min(r.spread_lo, s.median), r.spread_hi = std::max(r.spread_hi, s.median);
  return r;
}

// Times `body(k)` for k in [0, n) in batches of kBatch; returns per-query ns of each batch.
template <class Body>
Stats time_batches(size_t n, Body&& body) {
  std::vector<double> per_query;
  per_query.reserve(n / kBatch + 1);
  for (size_t k0 = 0; k0 + kBatch <= n; k0 += kBatch) {
    const auto t0 = Clock::now();
    for (size_t k = k0; k < k0 + kBatch; ++k) body(k);
    const auto t1 = Clock::now();
    per_query.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / kBatch);
  }
  return stats_of(std::move(per_query));
}

// A 1 kHz device path over the surface: a greedy walk over the sample graph towards random target
// samples, offset along the interpolated normal by up to `depth` (a sine of period one second), so
// the point slides along and into the surface. The curve is traced finely and a point is kept
// whenever the next would be more than `step` from the last one kept, so no tick moves further.
std::vector<Vec3> coherent_path(const SlabModel& m, int ticks, double step, double depth, std::mt19937_64& rng) {
  const SampleLayout& L = m.samples;
  std::uniform_int_distribution<int32_t> pick(0, L.count - 1);
  std::vector<Vec3> path;
  path.reserve(ticks);
  int32_t at = pick(rng), target = pick(rng);
  const double fine = step / 8;
  double carry = 0;  // arc length already walked into the current segment
  Vec3 prev = Vec3::Constant(NAN);
  while (static_cast<int>(path.size()) < ticks) {
    // Next sample: the neighbour closest to the target, if it gets closer.
    const Vec3f goal = m.positions[target];
    int32_t next = -1;
    float best = (m.positions[at] - goal).squaredNorm();
    for (int32_t e = L.neighbour_offsets[at]; e < L.neighbour_offsets[at + 1]; ++e) {
      const int32_t t = L.neighbours[e];
      const float d = (m.positions[t] - goal).squaredNorm();
      if (d < best) best = d, next = t;
    }
    if (next < 0) {  // reached the target or a local minimum: pick another target
      target = pick(rng);
      continue;
    }
    const Vec3 a = m.positions[at].cast<double>(), b = m.positions[next].cast<double>();
    const Vec3 na = m.normals[at].cast<double>(), nb = m.normals[next].cast<double>();
    const double len = (b - a).norm();
    for (; carry < len && static_cast<int>(path.size()) < ticks; carry += fine) {
      const double u = carry / len;
      const Vec3 nrm = ((1 - u) * na + u * nb).normalized();
      const double phase = 2 * M_PI * static_cast<double>(path.size()) / 1000.0;
      const Vec3 q = (1 - u) * a + u * b + depth * std::sin(phase) * nrm;
      if (path.empty()) path.push_back(q);
      if ((q - path.back()).norm() > step && prev.allFinite() && (prev - path.back()).norm() > 0) path.push_back(prev);
      while ((q - path.back()).norm() > step && static_cast<int>(path.size()) < ticks)  // sharp turn of the normal
        path.push_back(path.back() + (q - path.back()).normalized() * step);
      prev = q;
    }
    carry -= len;
    at = next;
  }
  return path;
}

// Uniformly random near-surface points: a random sample, a random point of one of its grid
// triangles, offset along the normal by a uniform amount in [-dist, dist].
std::vector<Vec3> global_points(const SlabModel& m, int count, double dist, std::mt19937_64& rng) {
  const SampleLayout& L = m.samples;
  std::uniform_int_distribution<size_t> tri(0, L.triangles.size() - 1);
  std::uniform_real_distribution<double> u01(0, 1), off(-dist, dist);
  std::vector<Vec3> pts;
  pts.reserve(count);
  for (int k = 0; k < count; ++k) {
    const Tri& t = L.triangles[tri(rng)];
    double a = u01(rng), b = u01(rng);
    if (a + b > 1) a = 1 - a, b = 1 - b;
    const Vec3 p0 = m.positions[t[0]].cast<double>(), p1 = m.positions[t[1]].cast<double>(),
               p2 = m.positions[t[2]].cast<double>();
    const Vec3 n = (p1 - p0).cross(p2 - p0).normalized();
    pts.push_back(p0 + a * (p1 - p0) + b * (p2 - p0) + off(rng) * n);
  }
  return pts;
}

template <class T>
size_t bytes(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}

double peak_rss_mb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;  // ru_maxrss is in KiB on Linux
}

nlohmann::json to_json(const Summary& s) {
  return {{"median", s.s.median},
          {"p99", s.s.p99},
          {"max", s.s.max},
          {"mean", s.s.mean},
          {"spread", {s.spread_lo, s.spread_hi}}};
}

volatile double g_sink;  // keeps results alive so the compiler cannot drop the timed work

struct EditRow {
  const char* tool;
  double radius_pct;
  int64_t ops = 0, visited = 0, changed = 0;
  double ns = 0;
};

// Warm strokes: one tool sample per 1 kHz tick, the tool sliding at 20 mm/s of device motion over
// the surface under `path` (StrokeEditor::add_sample + work, timed together per tick), the HIP 0.2
// radius under the surface. Each stroke is undone afterwards, which restores the model bit for bit.
std::vector<EditRow> warm_strokes(SlabModel& model, const SlabLocator& locator, const Workspace& ws,
                                  const std::vector<Vec3>& path, double diag, int ticks) {
  using Clock = std::chrono::steady_clock;
  std::vector<EditRow> rows;
  StrokeEditor editor(model);
  const double step = 0.02e-3 * ws.scale;  // 20 mm/s at 1 kHz
  for (double pct : {1.0, 2.0}) {
    const double radius = pct / 100 * diag;
    std::vector<ToolSample> samples;
    QueryCache qc;
    for (size_t k = 0; k + 1 < path.size() && static_cast<int>(samples.size()) < ticks; ++k) {
      const Contact a = query(model, locator, path[k], qc), b = query(model, locator, path[k + 1], qc);
      if (!a.in_shell() || !b.in_shell()) continue;
      const int n = std::max(1, static_cast<int>((b.surface_point - a.surface_point).norm() / step));
      for (int i = 0; i < n; ++i) {
        ToolSample t;
        const Vec3 on = a.surface_point + (b.surface_point - a.surface_point) * (double(i) / n);
        t.hip = on - 0.2 * radius * a.normal;
        t.contact = query(model, locator, t.hip, qc);
        t.normal_force_n = 0.55;  // half pressure
        t.time_s = 1e-3 * double(samples.size());
        if (t.contact.in_shell()) samples.push_back(t);
      }
    }
    for (const char* tool : {"carve", "add", "smooth", "flatten", "paint"}) {
      Brush b;
      b.tool = parse_brush_tool(tool);
      b.radius = radius;
      b.height = 0.2 * radius;
      if (b.tool == BrushTool::Smooth || b.tool == BrushTool::Flatten) b.strength = 0.5, b.falloff = Falloff::Smooth;
      if (b.tool == BrushTool::Paint) b.falloff = Falloff::Linear;
      EditRow row{tool, pct};
      editor.begin_stroke(b);
      for (const ToolSample& t : samples) {
        const auto t0 = Clock::now();
        editor.add_sample(model, t);
        const EditWork w = editor.work(model, INT64_MAX);
        row.ns += std::chrono::duration<double, std::nano>(Clock::now() - t0).count();
        ++row.ops, row.visited += w.visited, row.changed += w.changed;
      }
      editor.end_stroke();
      editor.work(model, INT64_MAX);
      editor.undo();  // restores every changed value bit for bit
      editor.work(model, INT64_MAX);
      rows.push_back(row);
    }
  }
  return rows;
}

void run_bench(const BenchArgs& a) {
  const std::string path = a.model.empty() ? default_model() : a.model;
  TriangleMesh mesh = read_mesh(path);
  const int64_t file_triangles = static_cast<int64_t>(mesh.faces.size());
  int subdivisions = 0;
  for (; subdivisions < a.subdivide; ++subdivisions) mesh = subdivide(mesh);  // a larger baseline input
  while (a.slabs > 0 && static_cast<int64_t>(mesh.faces.size()) <= a.slabs) mesh = subdivide(mesh), ++subdivisions;
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
  const double bake_s = std::chrono::duration<double>(Clock::now() - b0).count();
  const auto l0 = Clock::now();
  const SlabLocator locator(model);
  const double locator_s = std::chrono::duration<double>(Clock::now() - l0).count();
  const ExactMeshQuery exact(mesh);
  // The second baseline, CGAL's AABB tree (closest point only), unless --no-cgal.
  const std::unique_ptr<CgalClosestPoint> cgal = a.no_cgal ? nullptr : std::make_unique<CgalClosestPoint>(mesh);

  // ---- points: device scale maps the diagonal onto a 16 cm workspace ----
  std::mt19937_64 rng(a.seed);
  Aabb box;
  for (const Vec3f& p : model.positions) box.extend(p.cast<double>());
  const Workspace ws = fit_workspace(box, 0.16);
  const double step = 1e-4 * ws.scale;  // <= 0.1 mm of device motion per 1 ms tick (0.1 m/s)
  const std::vector<Vec3> path_pts = coherent_path(model, a.ticks, step, 0.005 * diag, rng);
  const std::vector<Vec3> global_pts = global_points(model, a.points, 0.01 * diag, rng);
  double max_step = 0;
  for (size_t k = 1; k < path_pts.size(); ++k) max_step = std::max(max_step, (path_pts[k] - path_pts[k - 1]).norm());
  std::vector<Vec3> velocity(path_pts.size(), Vec3::Zero());
  for (size_t k = 1; k < path_pts.size(); ++k) velocity[k] = (path_pts[k] - path_pts[k - 1]) / ws.scale * 1000.0;

  // ---- (a)-(c) latency, hdm and Embree interleaved in each repeat ----
  std::vector<Stats> coh, glo, tick, proxy_tick, emb_coh, emb_glo, cgal_coh, cgal_glo;
  int64_t in_shell_coh = 0, in_shell_glo = 0, contacts = 0;
  const ForceParams fp;
  for (int r = 0; r < a.repeat; ++r) {
    QueryCache cache;
    double sink = 0;
    int64_t hits = 0;
    coh.push_back(time_batches(path_pts.size(), [&](size_t k) {
      const Contact c = query(model, locator, path_pts[k], cache);
      sink += c.depth;
      hits += c.in_shell();
    }));
    in_shell_coh = hits;
    emb_coh.push_back(time_batches(path_pts.size(), [&](size_t k) {
      sink += exact.closest_point(path_pts[k]).distance + exact.inside(path_pts[k]);
    }));
    QueryCache gcache;  // global: a fresh search each time (no coherence to exploit)
    hits = 0;
    glo.push_back(time_batches(global_pts.size(), [&](size_t k) {
      gcache = QueryCache{};
      const Contact c = query(model, locator, global_pts[k], gcache);
      sink += c.depth;
      hits += c.in_shell();
    }));
    in_shell_glo = hits;
    emb_glo.push_back(time_batches(global_pts.size(), [&](size_t k) {
      sink += exact.closest_point(global_pts[k]).distance + exact.inside(global_pts[k]);
    }));
    if (cgal) {
      cgal_coh.push_back(
          time_batches(path_pts.size(), [&](size_t k) { sink += cgal->closest_point(path_pts[k]).x(); }));
      cgal_glo.push_back(
          time_batches(global_pts.size(), [&](size_t k) { sink += cgal->closest_point(global_pts[k]).x(); }));
    }
    QueryCache tcache;
    int64_t in_contact = 0;
    tick.push_back(time_batches(path_pts.size(), [&](size_t k) {
      const Contact c = query(model, locator, path_pts[k], tcache);
      const ForceSample f = penalty_force(c, velocity[k], fp, ws);
      sink += f.force.x();
      in_contact += f.status != ForceStatus::Free;
    }));
    contacts = in_contact;
#ifdef HDM_BENCH_PROXY
    // The full servo tick with the god-object proxy (friction, re-projection) on the same path.
    ProxyState ps;
    const ProxyParams pp;
    proxy_tick.push_back(time_batches(path_pts.size(), [&](size_t k) {
      const ProxyOutput o = proxy_step(model, locator, ws, ws.to_device(path_pts[k]), velocity[k], pp, ps);
      sink += o.force.x();
    }));
#endif
    g_sink = sink;
  }
  const Summary s_coh = summarise(coh), s_glo = summarise(glo), s_tick = summarise(tick), s_ecoh = summarise(emb_coh),
                s_eglo = summarise(emb_glo);
  const bool have_proxy = !proxy_tick.empty();
  const Summary s_ccoh = cgal ? summarise(cgal_coh) : Summary{}, s_cglo = cgal ? summarise(cgal_glo) : Summary{};
  const Summary s_proxy = have_proxy ? summarise(proxy_tick) : Summary{};

  // ---- (d) edits vs touched samples: last, on the model itself (a copy would double peak memory) ----
  const std::vector<EditRow> warm = warm_strokes(model, locator, ws, path_pts, diag, 2000);
  auto warm_per_visited = [&](const char* tool) {
    double ns = 0, n = 0;
    for (const EditRow& e : warm)
      if (std::string(e.tool) == tool) ns += e.ns, n += e.visited;
    return n > 0 ? ns / n : 0.0;
  };
  std::vector<EditRow> edits;
  {
    SlabModel& work = model;
    EditScratch scratch(work);
    std::uniform_int_distribution<int32_t> pick(0, work.samples.count - 1);
    const int ops = 40;
    for (double pct : {0.25, 0.5, 1.0, 2.0}) {
      const double radius = pct / 100 * diag;
      for (const char* tool : {"carve", "add", "paint"}) {
        EditRow row{tool, pct};
        for (int k = 0; k < ops; ++k) {
          const int32_t s = pick(rng);
          // A hip 0.2·radius below the surface at sample s: the carve sphere then cuts into it.
          const Vec3 hip = work.positions[s].cast<double>() - 0.2 * radius * work.normals[s].cast<double>();
          QueryCache qc;
          const Contact c = query(work, locator, hip, qc);
          if (!c.in_shell()) continue;
          const auto t0 = Clock::now();
          EditResult er;
          if (tool[0] == 'c')
            er = carve(work, scratch, c, hip, radius, 0.0);
          else if (tool[0] == 'a')
            er = add_material(work, scratch, c, radius, 0.1 * radius);
          else
            er = paint(work, scratch, c, radius, Vec3f(0.8f, 0.1f, 0.1f), 0.5);
          row.ns += std::chrono::duration<double, std::nano>(Clock::now() - t0).count();
          ++row.ops, row.visited += er.visited, row.changed += er.changed;
        }
        edits.push_back(row);
      }
    }
  }
  auto per_visited = [&](char tool) {
    double ns = 0, n = 0;
    for (const EditRow& e : edits)
      if (e.tool[0] == tool) ns += e.ns, n += e.visited;
    return n > 0 ? ns / n : 0.0;
  };
  auto per_changed = [&](char tool) {
    double ns = 0, n = 0;
    for (const EditRow& e : edits)
      if (e.tool[0] == tool) ns += e.ns, n += e.changed;
    return n > 0 ? ns / n : 0.0;
  };
  const double geom_edit_ns = [&] {  // carve + add, the geometry edits, per visited sample
    double ns = 0, n = 0;
    for (const EditRow& e : edits)
      if (e.tool[0] != 'p') ns += e.ns, n += e.visited;
    return n > 0 ? ns / n : 0.0;
  }();

  // ---- (f) memory ----
  const SampleLayout& L = model.samples;
  const size_t sample_bytes =
      bytes(model.displacement) + bytes(model.layer_displacement) + bytes(model.friction_static) +
      bytes(model.friction_dynamic) + bytes(model.stiffness_scale) + bytes(model.positions) + bytes(model.normals) +
      bytes(model.haptic_normals) + bytes(L.ids) + bytes(L.triangles) + bytes(L.home_slab) + bytes(L.home_index) +
      bytes(L.neighbour_offsets) + bytes(L.neighbours) + bytes(L.triangle_offsets) + bytes(L.incident_triangles) +
      bytes(L.shared_slot_offsets) + bytes(L.slot_of_shared) + bytes(model.slab_samples);
  const SampleLayout& T = model.texels;
  const size_t texel_bytes = bytes(model.colour) + bytes(model.roughness) + bytes(T.ids) + bytes(T.triangles) +
                             bytes(T.home_slab) + bytes(T.home_index) + bytes(T.neighbour_offsets) +
                             bytes(T.neighbours) + bytes(T.triangle_offsets) + bytes(T.incident_triangles) +
                             bytes(T.shared_slot_offsets) + bytes(T.slot_of_shared);
  const size_t slab_bytes = bytes(model.slabs) + bytes(model.geometry) + bytes(model.edge_neighbour) +
                            bytes(model.inner) + bytes(model.outer) + bytes(model.vertex_slab_offsets) +
                            bytes(model.vertex_slabs) + locator.memory_bytes();
  const int S = model.slab_count();
  const double bytes_per_sample = double(sample_bytes) / L.count, bytes_per_slab = double(slab_bytes) / S;

  const double ratio_coh = s_ecoh.s.median / s_coh.s.median, ratio_glo = s_eglo.s.median / s_glo.s.median;
  nlohmann::json edit_rows = nlohmann::json::array();
  nlohmann::json warm_rows = nlohmann::json::array();
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
  const nlohmann::json j = {
      {"model", path},
      {"subdivisions", subdivisions},
      {"file_triangles", file_triangles},
      {"input_triangles", static_cast<int64_t>(mesh.faces.size())},
      {"slabs", S},
      {"grid", model.grid_n},
      {"samples", L.count},
      {"repeat", a.repeat},
      {"batch", kBatch},
      {"ticks", path_pts.size()},
      {"global_points", global_pts.size()},
      {"trajectory_max_step_mm", max_step / ws.scale * 1000},
      {"in_shell_fraction",
       {{"coherent", double(in_shell_coh) / path_pts.size()}, {"global", double(in_shell_glo) / global_pts.size()}}},
      {"contact_fraction", double(contacts) / path_pts.size()},
      {"hdm",
       {{"coherent_ns", to_json(s_coh)},
        {"global_ns", to_json(s_glo)},
        {"tick_ns", to_json(s_tick)},
        {"proxy_tick_ns", have_proxy ? to_json(s_proxy) : nlohmann::json()}}},
      {"baseline",
       {{"embree_ns", to_json(s_ecoh)},
        {"embree_global_ns", to_json(s_eglo)},
        {"cgal_closest_ns", cgal ? to_json(s_ccoh) : nlohmann::json()},
        {"cgal_closest_global_ns", cgal ? to_json(s_cglo) : nlohmann::json()},
        {"cgal_build_s", cgal ? nlohmann::json(cgal->build_seconds()) : nlohmann::json()}}},
      {"ratio_coherent", ratio_coh},
      {"ratio_global", ratio_glo},
      {"ratio_cgal_coherent", cgal ? nlohmann::json(s_ccoh.s.median / s_coh.s.median) : nlohmann::json()},
      {"ratio_cgal_global", cgal ? nlohmann::json(s_cglo.s.median / s_glo.s.median) : nlohmann::json()},
      {"edit_ns_per_sample", geom_edit_ns},
      {"edit_ns_per_visited",
       {{"carve", per_visited('c')}, {"add", per_visited('a')}, {"paint_per_texel", per_visited('p')}}},
      {"edit_ns_per_changed",
       {{"carve", per_changed('c')}, {"add", per_changed('a')}, {"paint_per_texel", per_changed('p')}}},
      {"edits", edit_rows},
      {"edit_warm_ns_per_visited",
       {{"carve", warm_per_visited("carve")},
        {"add", warm_per_visited("add")},
        {"smooth", warm_per_visited("smooth")},
        {"flatten", warm_per_visited("flatten")},
        {"paint_per_texel", warm_per_visited("paint")}}},
      {"edits_warm", warm_rows},
      {"bake_s", bake_s},
      {"bake_separate_slabs", !a.no_separate},
      {"bake_report_s", br.seconds},
      {"locator_build_s", locator_s},
      {"bytes_per_sample", bytes_per_sample},
      {"bytes_per_slab", bytes_per_slab},
      {"bytes_per_texel", double(texel_bytes) / T.count},
      {"model_bytes", sample_bytes + texel_bytes + slab_bytes},
      {"peak_rss_mb", peak_rss_mb()}};
  if (a.json) {
    std::printf("%s\n", j.dump(2).c_str());
    return;
  }
  std::printf("hdm bench: %s, %lld input triangles (%d subdivisions), %d slabs, n = %d, %d samples\n", path.c_str(),
              (long long)mesh.faces.size(), subdivisions, S, model.grid_n, L.count);
  std::printf("  %d repeats; latency per query from batches of %d, median over repeats [spread of medians]\n", a.repeat,
              kBatch);
  std::printf("  %-34s %9s %9s %9s %9s  %s\n", "latency [ns]", "median", "p99", "max", "mean", "spread");
  auto row = [](const char* name, const Summary& s) {
    std::printf("  %-34s %9.0f %9.0f %9.0f %9.0f  [%.0f..%.0f]\n", name, s.s.median, s.s.p99, s.s.max, s.s.mean,
                s.spread_lo, s.spread_hi);
  };
  row("hdm coherent (1 kHz path)", s_coh);
  row("hdm global (random near-surface)", s_glo);
  row("hdm servo tick (query + force)", s_tick);
  if (have_proxy) row("hdm servo tick (proxy_step)", s_proxy);
  row("Embree closest+inside, path pts", s_ecoh);
  row("Embree closest+inside, global pts", s_eglo);
  if (cgal) {
    row("CGAL AABB closest, path pts", s_ccoh);
    row("CGAL AABB closest, global pts", s_cglo);
  }
  std::printf("  speed-up vs Embree (median)       coherent %.1fx, global %.1fx\n", ratio_coh, ratio_glo);
  if (cgal)
    std::printf("  speed-up vs CGAL closest (median) coherent %.1fx, global %.1fx (tree built in %.2f s)\n",
                s_ccoh.s.median / s_coh.s.median, s_cglo.s.median / s_glo.s.median, cgal->build_seconds());
  std::printf("  points in shell                   coherent %.1f%%, global %.1f%%; max path step %.3f mm\n",
              100.0 * in_shell_coh / path_pts.size(), 100.0 * in_shell_glo / global_pts.size(),
              max_step / ws.scale * 1000);
  std::printf(
      "  edits, warm strokes at 1 kHz      carve %.1f, add %.1f, smooth %.1f, flatten %.1f ns per visited sample, "
      "paint %.1f per texel\n",
      warm_per_visited("carve"), warm_per_visited("add"), warm_per_visited("smooth"), warm_per_visited("flatten"),
      warm_per_visited("paint"));
  std::printf("  edits, cold stamps [ns per visited] carve %.1f, add %.1f, paint %.1f per texel\n", per_visited('c'),
              per_visited('a'), per_visited('p'));
  std::printf("  edits, cold stamps [ns per changed] carve %.1f, add %.1f, paint %.1f per texel\n", per_changed('c'),
              per_changed('a'), per_changed('p'));
  std::printf("  bake                              %.2f s (locator %.3f s)\n", bake_s, locator_s);
  std::printf("  memory                            %.1f B/sample, %.0f B/slab, %.1f B/texel, peak RSS %.0f MB\n",
              bytes_per_sample, bytes_per_slab, double(texel_bytes) / T.count, peak_rss_mb());
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
