// SPDX-License-Identifier: MIT
#include <hdm/analysis/fidelity.h>
#include <hdm/mesh/winding_number.h>
#include <hdm/query/slab_query.h>
#include "../core/morton.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <utility>

namespace hdm {
namespace {

struct Sum {
  double sq = 0, max = 0;
  double sq_within = 0;  // squares of the distances up to `far` alone
  Sum operator+(const Sum& o) const { return {sq + o.sq, std::max(max, o.max), sq_within + o.sq_within}; }
};

// @p s with one more distance @p d; flags it beyond @p far.
Sum add(Sum s, double d, double far, uint8_t* far_flag) {
  if (far_flag && d > far) *far_flag = 1;
  if (d <= far) s.sq_within += d * d;
  s.sq += d * d;
  s.max = std::max(s.max, d);
  return s;
}

// Exact distances from `count` points to `target`. Most points lie within `near` of it, so the
// query starts with that radius; the others are queried again without a bound (same result).
// Points farther than `far` are flagged in `far_flags` (#count, or empty: not flagged).
template <class PointAt>
Sum distances(int64_t count, const ExactMeshQuery& target, double near, PointAt point_at, double far = INFINITY,
              std::vector<uint8_t>* far_flags = nullptr) {
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<int64_t>(0, count, 1024), Sum{},
      [&](const tbb::blocked_range<int64_t>& r, Sum s) {
        for (int64_t k = r.begin(); k < r.end(); ++k) {
          const Vec3 p = point_at(k);
          ClosestPoint c = target.closest_point(p, near);
          if (c.face < 0) c = target.closest_point(p);
          s = add(s, c.distance, far, far_flags ? &(*far_flags)[k] : nullptr);
        }
        return s;
      },
      [](const Sum& a, const Sum& b) { return a + b; });
}

// The Sum of distances() over distances already measured, with the same blocks and order.
Sum distances(int64_t count, const std::vector<double>& measured, double far, std::vector<uint8_t>* far_flags) {
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<int64_t>(0, count, 1024), Sum{},
      [&](const tbb::blocked_range<int64_t>& r, Sum s) {
        for (int64_t k = r.begin(); k < r.end(); ++k) s = add(s, measured[k], far, far_flags ? &(*far_flags)[k] : nullptr);
        return s;
      },
      [](const Sum& a, const Sum& b) { return a + b; });
}

// The indices of @p points by the Morton code of each in their bounding box, in one 64-bit word a
// point: the index in the low bits, the code's leading bits above it (8 bytes a point, not 16).
struct MortonOrder {
  std::vector<uint64_t> keys;
  uint64_t mask = 0;
  int64_t operator[](size_t k) const { return int64_t(keys[k] & mask); }

  explicit MortonOrder(const std::vector<Vec3>& points) : keys(points.size()) {
    Aabb box;
    for (const Vec3& p : points) box.extend(p);
    int bits = 1;
    while ((uint64_t(1) << bits) < points.size()) ++bits;
    mask = (uint64_t(1) << bits) - 1;
    const int drop = std::max(0, bits - 1);  // the code has 63 bits; 64 - bits of them stay
    tbb::parallel_for(size_t(0), points.size(), [&](size_t k) {
      keys[k] = (core::detail::morton_code(points[k], box) >> drop) << bits | uint64_t(k);
    });
    tbb::parallel_sort(keys.begin(), keys.end());
  }
};

// The slabs in Morton order of their boxes' centres, cut into runs of at most @p chunk_triangles
// grid triangles (one run when the whole surface fits). The back distances build one BVH per run,
// in turn, so the fidelity's memory stays bounded whatever the slab count (at 100,000 slabs and
// n = 16 the whole surface is 25.6 M triangles, 1.7 GB with its BVH).
std::vector<std::vector<int32_t>> surface_chunks(const SlabModel& model, int64_t chunk_triangles) {
  const int32_t S = model.slab_count();
  const int64_t per_chunk = std::max<int64_t>(1, chunk_triangles / (int64_t(model.samples.n) * model.samples.n));
  std::vector<int32_t> slabs(S);
  if (S <= per_chunk) {
    for (int32_t s = 0; s < S; ++s) slabs[s] = s;
    return {std::move(slabs)};
  }
  std::vector<Vec3> centres(S);
  for (int32_t s = 0; s < S; ++s) {
    const Aabb b = slab_bounds(model, s);
    centres[s] = 0.5 * (b.min + b.max);
  }
  const MortonOrder order(centres);
  std::vector<std::vector<int32_t>> chunks;
  for (int64_t b = 0; b < S; b += per_chunk) {
    std::vector<int32_t>& c = chunks.emplace_back();
    for (int64_t k = b; k < std::min<int64_t>(S, b + per_chunk); ++k) c.push_back(int32_t(order[size_t(k)]));
  }
  return chunks;
}

// The displaced surface of @p slabs: their grid triangles over the samples they use, numbered in
// order of first use, at sample_position() (as displaced_surface() gives them). @p local_of
// (#samples, all -1) is scratch, all -1 again on return.
TriangleMesh chunk_surface(const SlabModel& model, const std::vector<int32_t>& slabs, std::vector<int32_t>& local_of) {
  TriangleMesh m;
  std::vector<int32_t> global;
  m.faces.reserve(slabs.size() * size_t(model.samples.n) * model.samples.n);
  for (int32_t slab : slabs)
    model.samples.for_each_slab_triangle(slab, [&](const Tri& t) {
      Tri u;
      for (int k = 0; k < 3; ++k) {
        int32_t& l = local_of[t[k]];
        if (l < 0) l = int32_t(global.size()), global.push_back(t[k]);
        u[k] = l;
      }
      m.faces.push_back(u);
    });
  m.vertices.resize(global.size());
  tbb::parallel_for(size_t(0), global.size(), [&](size_t v) { m.vertices[v] = sample_position(model, global[v]); });
  for (int32_t g : global) local_of[g] = -1;
  return m;
}

// Distance from @p p to the box @p b (0 inside).
double box_distance(const Aabb& b, const Vec3& p) {
  return (p.cwiseMax(b.min).cwiseMin(b.max) - p).norm();
}

// Exact distance from each point (points[order[k]], k in Morton order) to the displaced surface,
// the least over its chunks: first within `near` of each point (where nearly every point's
// closest point lies), then, for the points with none that close, without a bound.
std::vector<double> back_distances(const SlabModel& model, const std::vector<Vec3>& points, const MortonOrder& order,
                                   double near, int64_t chunk_triangles) {
  const int64_t nb = static_cast<int64_t>(points.size());
  std::vector<double> best(nb, INFINITY);
  std::vector<uint8_t> unbounded(nb, 0);
  const std::vector<std::vector<int32_t>> chunks = surface_chunks(model, chunk_triangles);
  std::vector<int32_t> local_of(model.samples.count, -1);
  for (int pass = 0; pass < 2; ++pass) {
    if (pass == 1) {
      int64_t open = 0;
      for (int64_t k = 0; k < nb; ++k) open += unbounded[k] = best[k] == INFINITY;
      if (open == 0) break;
    }
    for (const std::vector<int32_t>& chunk : chunks) {
      const ExactMeshQuery q(chunk_surface(model, chunk, local_of), BvhQuality::compact);
      const Aabb box = bounds(q.mesh());
      tbb::parallel_for(tbb::blocked_range<int64_t>(0, nb, 1024), [&](const tbb::blocked_range<int64_t>& r) {
        for (int64_t k = r.begin(); k < r.end(); ++k) {
          if (pass == 1 && !unbounded[k]) continue;
          const Vec3 p = points[order[size_t(k)]];
          const double radius = pass == 0 ? std::min(best[k], near) : best[k];
          if (box_distance(box, p) > radius) continue;
          const ClosestPoint c = radius < INFINITY ? q.closest_point(p, radius) : q.closest_point(p);
          if (c.face >= 0 && c.distance < best[k]) best[k] = c.distance;
        }
      });
    }
  }
  return best;
}

}  // namespace

std::vector<uint8_t> interior_faces(const ExactMeshQuery& input) {
  const TriangleMesh& m = input.mesh();
  std::vector<uint8_t> interior(m.faces.size(), 0);
  // The generalized winding number counts the parts that cover a point: a face inside two
  // overlapping parts is interior too, where ray parity calls it outside; and rays of an open input
  // leave through its openings. Inside is a winding of at least 1/2, the rule
  // resolve_self_intersections() and resolve_open_self_intersections() drop faces by. A closed input is
  // probed 10⁻⁹ of the diagonal off the face, as resolve_self_intersections() does: its layers
  // may run closer than 10⁻⁵ of the diagonal (mannequin-devil.off), and a point farther out would
  // pass the layer above.
  const bool open = !input.closed();
  const double eps = (open ? 1e-5 : 1e-9) * bounds(m).diagonal();
  const WindingNumber winding(m);
  tbb::parallel_for(size_t(0), m.faces.size(), [&](size_t f) {
    const Tri& t = m.faces[f];
    const Vec3 c = (m.vertices[t[0]] + m.vertices[t[1]] + m.vertices[t[2]]) / 3.0;
    const Vec3 n = input.face_normal(static_cast<int32_t>(f));
    // Closed: a face with no material behind it either (a fin, a part turned inside out where it
    // crosses) is not on the material's boundary; resolve_self_intersections() drops it too.
    interior[f] = winding.inside(c + eps * n) || (!open && !winding.inside(c - eps * n));
  });
  return interior;
}

std::vector<Vec3> surface_points(const ExactMeshQuery& input, const std::vector<uint8_t>* interior) {
  const TriangleMesh& in = input.mesh();
  auto centroid = [&](size_t t) {
    const Tri& f = in.faces[t];
    return Vec3((in.vertices[f[0]] + in.vertices[f[1]] + in.vertices[f[2]]) / 3.0);
  };
  std::vector<Vec3> points;
  if (!interior) {
    points.reserve(in.vertices.size() + in.faces.size());
    points.insert(points.end(), in.vertices.begin(), in.vertices.end());
    for (size_t t = 0; t < in.faces.size(); ++t) points.push_back(centroid(t));
    return points;
  }
  std::vector<uint8_t> exposed(in.vertices.size(), 0);
  std::vector<Vec3> normal(in.vertices.size(), Vec3::Zero());
  for (size_t t = 0; t < in.faces.size(); ++t)
    if (!(*interior)[t]) {
      const Tri& f = in.faces[t];
      const Vec3 n = (in.vertices[f[1]] - in.vertices[f[0]]).cross(in.vertices[f[2]] - in.vertices[f[0]]);
      for (int32_t v : f) exposed[v] = 1, normal[v] += n;
      points.push_back(centroid(t));
    }
  // A vertex of an exposed face may itself lie inside another part (the face crosses it): it is
  // on the material's surface only if the point just in front of it is outside, as for faces.
  const double eps = (input.closed() ? 1e-9 : 1e-5) * bounds(in).diagonal();  // as interior_faces()
  const WindingNumber winding(in);
  tbb::parallel_for(size_t(0), in.vertices.size(), [&](size_t v) {
    if (!exposed[v] || !(normal[v].norm() > 0)) return;
    if (winding.inside(in.vertices[v] + eps * normal[v].normalized())) exposed[v] = 0;
  });
  for (size_t v = 0; v < in.vertices.size(); ++v)
    if (exposed[v]) points.push_back(in.vertices[v]);
  return points;
}

Fidelity measure_fidelity(const SlabModel& model, const ExactMeshQuery& input, const std::vector<Vec3>* input_points,
                          double far_pct, std::vector<Vec3>* far_points, int64_t chunk_triangles) {
  const SampleLayout& L = model.samples;
  const double diag = bounds(input.mesh()).diagonal();
  Fidelity f;
  const int64_t ns = L.count, nt = L.triangle_count();
  // The model's points, as displaced_surface() would give them, without building it.
  const auto model_point = [&](int64_t k) {
    if (k < ns) return sample_position(model, int(k));
    const Tri t = L.grid_triangle(int32_t(k - ns));
    return Vec3((sample_position(model, t[0]) + sample_position(model, t[1]) + sample_position(model, t[2])) / 3.0);
  };
  const double near = 1e-2 * diag, far = far_pct / 100 * diag;
  std::vector<uint8_t> far_flags;
  if (far_points) far_points->clear(), far_flags.assign(ns + nt, 0);
  const Sum fwd = distances(ns + nt, input, near, model_point, far, far_points ? &far_flags : nullptr);
  for (int64_t k = 0; k < static_cast<int64_t>(far_flags.size()); ++k)
    if (far_flags[k]) far_points->push_back(model_point(k));
  std::vector<Vec3> all_points;  // every vertex and centroid, unless the caller chose the points
  if (!input_points) all_points = surface_points(input, nullptr);
  const std::vector<Vec3>& back_points = input_points ? *input_points : all_points;
  const auto nb = static_cast<int64_t>(back_points.size());
  // The input's points in Morton order (the model's come slab by slab, near each other already):
  // queries that follow each other then read the same BVH nodes and triangles; in an input's own
  // vertex order they cost 2.6 times as much (armadillo subdivided to 12.6 M triangles).
  const MortonOrder order(back_points);
  const std::vector<double> back_distance = back_distances(model, back_points, order, near, chunk_triangles);
  if (far_points) far_flags.assign(nb, 0);
  const Sum back = distances(nb, back_distance, far, far_points ? &far_flags : nullptr);
  for (int64_t k = 0; far_points && k < nb; ++k)
    if (far_flags[k]) far_points->push_back(back_points[order[k]]);
  f.points = ns + nt;
  f.back_points = nb;
  f.rms_pct = 100 * std::sqrt(fwd.sq / f.points) / diag;
  f.max_pct = 100 * fwd.max / diag;
  f.rms_back_pct = 100 * std::sqrt(back.sq / f.back_points) / diag;
  f.max_back_pct = 100 * back.max / diag;
  f.rms_within_pct = 100 * std::sqrt(fwd.sq_within / f.points) / diag;
  f.rms_back_within_pct = 100 * std::sqrt(back.sq_within / f.back_points) / diag;
  return f;
}

ContactAccuracy measure_contact(const SlabModel& model, const ExactMeshQuery& input, int64_t count, uint64_t seed,
                                double offset_pct, const std::vector<uint8_t>* interior) {
  const TriangleMesh& m = input.mesh();
  const double diag = bounds(m).diagonal();
  // An open input that crosses itself: the interior faces are not on the surface a user touches,
  // and an open surface's inside is the back of its nearest face, so the reference is the
  // exposed faces alone (a closed input's inside, the union's winding, needs no such care).
  const bool exposed_only = interior && interior->size() == m.faces.size() && !input.closed();
  std::unique_ptr<ExactMeshQuery> exposed;
  if (exposed_only) {
    TriangleMesh e;
    std::vector<int32_t> id(m.vertices.size(), -1);
    for (size_t f = 0; f < m.faces.size(); ++f) {
      if ((*interior)[f]) continue;
      Tri t = m.faces[f];
      for (int32_t& v : t) {
        if (id[v] < 0) id[v] = static_cast<int32_t>(e.vertices.size()), e.vertices.push_back(m.vertices[v]);
        v = id[v];
      }
      e.faces.push_back(t);
    }
    if (!e.faces.empty()) exposed = std::make_unique<ExactMeshQuery>(e);
  }
  const ExactMeshQuery& reference = exposed ? *exposed : input;
  // Area-weighted face sampling.
  std::vector<double> cdf(m.faces.size());
  double total = 0;
  for (size_t f = 0; f < m.faces.size(); ++f) {
    const Tri& t = m.faces[f];
    if (!exposed || !(*interior)[f])
      total += (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).norm();
    cdf[f] = total;
  }
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3> points(count);
  for (auto& p : points) {
    const size_t f =
        std::min(cdf.size() - 1, size_t(std::lower_bound(cdf.begin(), cdf.end(), u(rng) * total) - cdf.begin()));
    double a = u(rng), b = u(rng);
    if (a + b > 1) a = 1 - a, b = 1 - b;
    const Tri& t = m.faces[f];
    p = m.vertices[t[0]] + a * (m.vertices[t[1]] - m.vertices[t[0]]) + b * (m.vertices[t[2]] - m.vertices[t[0]]) +
        (u(rng) * 2 - 1) * offset_pct / 100 * diag * input.face_normal(static_cast<int32_t>(f));
  }
  const SlabLocator locator(model);
  // A point in no slab is inside when the inner shell encloses it (winding number), for a closed
  // model. An open model encloses nothing: there the point is judged by the reference's own rule
  // for an open input, the side of the nearest face, applied to the model's displaced surface. The
  // inner shell would not do: it lies a shell thickness behind the surface, so between two sheets
  // stacked close together (horizons.off) it is nearer than the sheet the point lies on, and puts
  // the point behind the other sheet.
  TriangleMesh core_mesh{model.inner, model.slabs};
  if (analyze_topology(core_mesh).boundary_edges > 0) displaced_surface(model, core_mesh.vertices, core_mesh.faces);
  const ExactMeshQuery core_test(core_mesh);
  struct Acc {
    int64_t agree = 0, depth_n = 0, below = 0, above = 0, false_in = 0;
    double sq = 0, max = 0;
  };
  const Acc acc = tbb::parallel_deterministic_reduce(
      tbb::blocked_range<int64_t>(0, count, 256), Acc{},
      [&](const tbb::blocked_range<int64_t>& r, Acc a) {
        QueryCache cache;
        for (int64_t k = r.begin(); k < r.end(); ++k) {
          const Contact c = query(model, locator, points[k], cache);
          const bool exact_in = reference.inside(points[k]);
          const bool core = !c.in_shell() && core_test.inside(points[k]);
          a.agree += (c.penetrating() || core) == exact_in;
          a.below += exact_in && !c.in_shell() && !core;
          a.above += exact_in && c.in_shell() && !c.penetrating();
          a.false_in += !exact_in && (c.penetrating() || core);
          if (c.penetrating() && exact_in) {
            const double e = std::abs(c.depth - reference.closest_point(points[k]).distance);
            a.sq += e * e;
            a.max = std::max(a.max, e);
            ++a.depth_n;
          }
        }
        return a;
      },
      [](const Acc& a, const Acc& b) {
        return Acc{a.agree + b.agree,       a.depth_n + b.depth_n, a.below + b.below,     a.above + b.above,
                   a.false_in + b.false_in, a.sq + b.sq,           std::max(a.max, b.max)};
      });
  ContactAccuracy c;
  c.points = count;
  c.agreement = count ? double(acc.agree) / count : 1.0;
  c.depth_rms_pct = acc.depth_n ? 100 * std::sqrt(acc.sq / acc.depth_n) / diag : 0;
  c.depth_max_pct = 100 * acc.max / diag;
  c.missed_below_shell = acc.below;
  c.missed_in_shell = acc.above;
  c.false_inside = acc.false_in;
  return c;
}

}  // namespace hdm
