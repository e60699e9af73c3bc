// SPDX-License-Identifier: MIT
#include "workloads.h"

#include <hdm/analysis/cgal_closest_point.h>
#include <hdm/edit/brush_registry.h>
#include <hdm/haptics/rigid_tool.h>
#include <hdm/haptics/sphere_proxy.h>
#include <hdm/slab/model_memory.h>

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <numbers>
#include <string>
#include <string_view>

namespace hdm::bench {
namespace {

volatile double g_sink;  // keeps results alive so the compiler cannot drop the timed work

}  // namespace

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

std::vector<Vec3> coherent_path(const SlabModel& m, int ticks, double step, double depth, std::mt19937_64& rng) {
  const SampleLayout& L = m.samples;
  std::uniform_int_distribution<int32_t> pick(0, L.count - 1);
  std::vector<Vec3> path;
  path.reserve(ticks);
  int32_t at = pick(rng), target = pick(rng);
  const double fine = step / 8;
  double carry = 0;  // arc length already walked into the current segment
  Vec3 prev = Vec3::Constant(NAN);
  auto point = [&](int32_t s) -> Vec3f { return float_point(m, s).cast<float>(); };
  while (static_cast<int>(path.size()) < ticks) {
    // Next sample: the neighbour closest to the target, if it gets closer.
    const Vec3f goal = point(target);
    int32_t next = -1;
    float best = (point(at) - goal).squaredNorm();
    L.for_each_neighbour(at, [&](int32_t t) {
      const float d = (point(t) - goal).squaredNorm();
      if (d < best) best = d, next = t;
    });
    if (next < 0) {  // reached the target or a local minimum: pick another target
      target = pick(rng);
      continue;
    }
    const Vec3 a = point(at).cast<double>(), b = point(next).cast<double>();
    const Vec3 na = sample_normal(m, at).cast<double>(), nb = sample_normal(m, next).cast<double>();
    const double len = (b - a).norm();
    for (; carry < len && static_cast<int>(path.size()) < ticks; carry += fine) {
      const double u = carry / len;
      const Vec3 nrm = ((1 - u) * na + u * nb).normalized();
      const double phase = 2 * std::numbers::pi * static_cast<double>(path.size()) / 1000.0;
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

std::vector<Vec3> global_points(const SlabModel& m, int count, double dist, std::mt19937_64& rng) {
  const SampleLayout& L = m.samples;
  std::uniform_int_distribution<int32_t> tri(0, L.triangle_count() - 1);
  std::uniform_real_distribution<double> u01(0, 1), off(-dist, dist);
  std::vector<Vec3> pts;
  pts.reserve(count);
  for (int k = 0; k < count; ++k) {
    const Tri t = L.grid_triangle(tri(rng));
    double a = u01(rng), b = u01(rng);
    if (a + b > 1) a = 1 - a, b = 1 - b;
    const Vec3 p0 = float_point(m, t[0]), p1 = float_point(m, t[1]), p2 = float_point(m, t[2]);
    const Vec3 n = (p1 - p0).cross(p2 - p0).normalized();
    pts.push_back(p0 + a * (p1 - p0) + b * (p2 - p0) + off(rng) * n);
  }
  return pts;
}

std::vector<Vec3> path_velocity(const std::vector<Vec3>& path, const Workspace& ws) {
  std::vector<Vec3> velocity(path.size(), Vec3::Zero());
  for (size_t k = 1; k < path.size(); ++k) velocity[k] = (path[k] - path[k - 1]) / ws.scale * 1000.0;
  return velocity;
}

std::vector<Eigen::Quaterniond> tool_orientations(const SlabModel& model, const SlabLocator& locator,
                                                  const std::vector<Vec3>& path) {
  std::vector<Eigen::Quaterniond> out;
  out.reserve(path.size());
  QueryCache cache;
  Vec3 axis = Vec3::Zero();
  for (const Vec3& p : path) {
    const Contact c = query(model, locator, p, cache);
    const Vec3 n = c.in_shell() ? c.normal : Vec3(axis.norm() > 0 ? axis : Vec3::UnitZ());
    axis = axis.norm() > 0 ? Vec3((axis + 0.02 * (n - axis)).normalized()) : n;  // a hand's lag: ~50 ticks
    out.push_back(Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), axis));
  }
  return out;
}

LatencyRuns time_queries(const SlabModel& model, const SlabLocator& locator, const ExactMeshQuery& exact,
                         const CgalClosestPoint* cgal, const Workspace& ws, const std::vector<Vec3>& path,
                         const std::vector<Vec3>& velocity, const std::vector<Vec3>& points, int repeat) {
  LatencyRuns out;
  const ForceParams fp;
  const std::vector<Eigen::Quaterniond> orientation = tool_orientations(model, locator, path);
  for (int r = 0; r < repeat; ++r) {
    QueryCache cache;
    double sink = 0;
    int64_t hits = 0;
    out.coherent.push_back(time_batches(path.size(), [&](size_t k) {
      const Contact c = query(model, locator, path[k], cache);
      sink += c.depth;
      hits += c.in_shell();
    }));
    out.in_shell_coherent = hits;
    out.embree_coherent.push_back(time_batches(
        path.size(), [&](size_t k) { sink += exact.closest_point(path[k]).distance + exact.inside(path[k]); }));
    QueryCache gcache;  // global: a fresh search each time (no coherence to exploit)
    hits = 0;
    out.global.push_back(time_batches(points.size(), [&](size_t k) {
      gcache = QueryCache{};
      const Contact c = query(model, locator, points[k], gcache);
      sink += c.depth;
      hits += c.in_shell();
    }));
    out.in_shell_global = hits;
    out.embree_global.push_back(time_batches(
        points.size(), [&](size_t k) { sink += exact.closest_point(points[k]).distance + exact.inside(points[k]); }));
    if (cgal) {
      out.cgal_coherent.push_back(
          time_batches(path.size(), [&](size_t k) { sink += cgal->closest_point(path[k]).x(); }));
      out.cgal_global.push_back(
          time_batches(points.size(), [&](size_t k) { sink += cgal->closest_point(points[k]).x(); }));
    }
    QueryCache tcache;
    int64_t in_contact = 0;
    out.tick.push_back(time_batches(path.size(), [&](size_t k) {
      const Contact c = query(model, locator, path[k], tcache);
      const ForceSample f = penalty_force(c, velocity[k], fp, ws);
      sink += f.force.x();
      in_contact += f.status != ForceStatus::Free;
    }));
    out.contacts = in_contact;
    // The full servo tick with the god-object proxy (friction, re-projection) on the same path.
    ProxyState ps;
    const ProxyParams pp;
    out.proxy_tick.push_back(time_batches(path.size(), [&](size_t k) {
      const ProxyOutput o = proxy_step(model, locator, ws, ws.to_device(path[k]), velocity[k], pp, ps);
      sink += o.force.x();
    }));
    // The sphere proxy: the path is the ball's centre, so the ball touches wherever the path comes
    // within r of the surface.
    auto ss = std::make_unique<SphereProxyState>();  // ~3 KB of per-sample caches: off the stack
    SphereProxyParams sp;
    out.sphere_tick.push_back(time_batches(path.size(), [&](size_t k) {
      const ProxyOutput o = sphere_proxy_step(model, locator, ws, ws.to_device(path[k]), velocity[k], sp, *ss);
      sink += o.force.x();
    }));
    // The rigid tool: a 1,000-point burr, its tip (the head's centre) on the path, its shaft along
    // the path's orientations (tool_orientations()).
    const ToolShell burr = burr_shell(0.01 * model.source_diagonal);
    auto rs = std::make_unique<RigidToolState>();  // ~200 KB of per-point state: off the stack
    const RigidToolParams rp;
    int64_t pushed = 0;
    out.rigid_tick.push_back(time_batches(
        path.size(),
        [&](size_t k) {
          const ToolPose pose{ws.to_device(path[k]), orientation[k]};
          const ToolWrench w =
              rigid_tool_step(model, locator, ws, burr, pose, ToolTwist{velocity[k], Vec3::Zero()}, rp, *rs);
          sink += w.force.x() + w.torque.y();
          pushed += w.status != ForceStatus::Free;
        },
        1));
    out.rigid_contacts = pushed;
    g_sink = sink;
  }
  return out;
}

Brush workload_brush(BrushTool tool, double radius) {
  const BrushInfo* info = find_brush(tool);
  Brush b;
  b.tool = tool;
  b.radius = radius;
  b.height = 0.2 * radius;
  if (info) b.falloff = info->falloff;
  // The relaxing brushes at half their rate; a brush not named here strokes at full strength.
  const std::string_view name = info ? info->name : "";
  if (name == "smooth" || name == "flatten") b.strength = 0.5;
  return b;
}

std::vector<EditRow> warm_strokes(SlabModel& model, const SlabLocator& locator, const Workspace& ws,
                                  const std::vector<Vec3>& path, double diag, int ticks) {
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
        t.units_per_metre = ws.scale;
        t.time_s = 1e-3 * double(samples.size());
        if (t.contact.in_shell()) samples.push_back(t);
      }
    }
    for (const BrushInfo& info : brush_registry()) {
      const Brush b = workload_brush(info.tool, radius);
      EditRow row{info.name, pct};
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

std::vector<EditRow> cold_stamps(SlabModel& model, const SlabLocator& locator, double diag, std::mt19937_64& rng,
                                 int ops) {
  std::vector<EditRow> rows;
  EditScratch scratch(model);
  std::uniform_int_distribution<int32_t> pick(0, model.samples.count - 1);
  for (double pct : {0.25, 0.5, 1.0, 2.0}) {
    const double radius = pct / 100 * diag;
    for (const char* tool : {"carve", "add", "paint"}) {
      EditRow row{tool, pct};
      for (int k = 0; k < ops; ++k) {
        const int32_t s = pick(rng);
        // A hip 0.2·radius below the surface at sample s: the carve sphere then cuts into it.
        const Vec3 hip = float_point(model, s) - 0.2 * radius * sample_normal(model, s).cast<double>();
        QueryCache qc;
        const Contact c = query(model, locator, hip, qc);
        if (!c.in_shell()) continue;
        const auto t0 = Clock::now();
        EditResult er;
        if (tool[0] == 'c')
          er = carve(model, scratch, c, hip, radius, 0.0);
        else if (tool[0] == 'a')
          er = add_material(model, scratch, c, radius, 0.1 * radius);
        else
          er = paint(model, scratch, c, radius, Vec3f(0.8f, 0.1f, 0.1f), 0.5);
        row.ns += std::chrono::duration<double, std::nano>(Clock::now() - t0).count();
        ++row.ops, row.visited += er.visited, row.changed += er.changed;
      }
      rows.push_back(row);
    }
  }
  return rows;
}

ModelBytes model_bytes(const SlabModel& model, const SlabLocator& locator) {
  const ModelMemory m = model_memory(model);
  ModelBytes b;
  b.samples = static_cast<size_t>(m.sample_fields + m.sample_layout + m.caches);
  b.texels = static_cast<size_t>(m.texel_fields + m.texel_layout);
  b.slabs = static_cast<size_t>(m.coarse + m.slab_constants) + locator.memory_bytes();
  return b;
}

double peak_rss_mb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;  // ru_maxrss is in KiB on Linux
}

}  // namespace hdm::bench
