// SPDX-License-Identifier: MIT
#include <hdm/edit/edit_tools.h>

#include <hdm/query/detail/surface_eval.h>
#include "edit_job.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hdm {

EditScratch::EditScratch(SlabModel& m)
    : sample_stamp(m.samples.count, 0),
      texel_stamp(m.texels.count, 0),
      queue(std::max(m.samples.count, m.texels.count) + 1),  // +1: branch-free pushes write one past
      changed(m.samples.count),
      changed_mark(m.samples.count, 0),
      ring(m.samples.count + 1),
      dirty_slabs(m.slab_count(), 0),
      dirty_list(m.slab_count(), 0),
      faces(),
      grid_weights(m.samples.per_slab),
      texel_weights(m.texels.per_slab),
      texel_points(m.texels.per_slab) {
  materialise_fields(m);
  const SampleLayout& L = m.samples;
  const double n = L.n;
  for (int k = 0; k < L.per_slab; ++k) {  // projection_line()'s arithmetic
    const double wT = L.point_i[k] / n, wS = L.point_j[k] / n, wR = 1.0 - wT - wS;
    grid_weights[k] = {wR, wS, wT};
  }
  const SampleLayout& T = m.texels;
  for (int k = 0; k < T.per_slab; ++k) {
    const double wS = T.point_j[k] / double(T.n), wT = T.point_i[k] / double(T.n);
    const slab_query::detail::LocalCell c = slab_query::detail::local_cell(m.grid_n, wS, wT);
    texel_weights[k] = {wS, wT, c.wa, c.wb, c.wd};
    texel_points[k] = {c.la, c.lb, c.ld};
  }
  double sum = 0;
  int64_t edges = 0;
  // Each grid edge once (from its smaller id: the neighbour relation is symmetric).
  for (int32_t a = 0; a < L.count && a < static_cast<int32_t>(m.displacement.size()); ++a) {
    const Vec3 pa = sample_position(m, a);
    L.for_each_neighbour(a, [&](int32_t t) {
      if (t < a) return;
      sum += (sample_position(m, t) - pa).norm();
      ++edges;
    });
  }
  sample_spacing = edges > 0 ? sum / double(edges) : 0.0;
}

void refresh_normals(SlabModel& m, EditScratch& s) noexcept {
  edit::detail::EditJob job;
  job.start_normals(s);
  edit::detail::Deadline never = edit::detail::Deadline::never();
  job.run(m, s, never);
}

void clear_dirty(EditScratch& s) noexcept {
  for (int32_t k = 0; k < s.dirty_count; ++k) s.dirty_slabs[s.dirty_list[k]] = 0;
  s.dirty_count = 0;
}

namespace {

EditResult run_to_end(SlabModel& m, EditScratch& s, edit::detail::EditJob& job) noexcept {
  edit::detail::Deadline never = edit::detail::Deadline::never();
  job.run(m, s, never);
  const EditResult r = job.result;
  refresh_normals(m, s);
  return r;
}

BrushSweep stamp_at(const Contact& c, const Vec3& centre, const Brush& b) noexcept {
  BrushSweep sw;
  sw.brush = b;
  sw.from = sw.to = centre;
  sw.seed_slab = c.in_shell() ? c.slab : -1;
  sw.seed_bary = c.coords.bary;
  return sw;
}

// Appends the interval of t where a·t² + 2·b·t + c <= 0 (a > 0) to [lo, hi].
inline void union_quadratic(double a, double b, double c, double& lo, double& hi) noexcept {
  const double disc = b * b - a * c;
  if (!(disc >= 0)) return;
  const double sq = std::sqrt(disc);
  lo = std::min(lo, (-b - sq) / a);
  hi = std::max(hi, (-b + sq) / a);
}

}  // namespace

bool line_capsule(const Vec3& p0, const Vec3& L, const Vec3& a, const Vec3& b, double radius, double& t_in,
                  double& t_out) noexcept {
  // |w + t·L|² = r² with w = p0 - a, in the half-b form a t² + 2 b t + c = 0.
  const Vec3 w = p0 - a;
  const double aa = L.squaredNorm(), bw = L.dot(w), r2 = radius * radius, c = w.squaredNorm() - r2;
  if (!(aa > 0)) return false;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  union_quadratic(aa, bw, c, lo, hi);  // sphere at a
  const Vec3 u = b - a;
  const double uu = u.squaredNorm();
  if (uu > 0) {
    const double Lu = L.dot(u), wu = w.dot(u);
    union_quadratic(aa, bw - Lu, c - 2 * wu + uu, lo, hi);  // sphere at b: w - u
    // Cylinder between them: the part of the line whose projection on the axis falls in [0, |u|].
    const double ac = aa - Lu * Lu / uu, bc = bw - wu * Lu / uu, cc = c - wu * wu / uu;
    double s0 = -std::numeric_limits<double>::infinity(), s1 = -s0;  // t range with axial parameter in [0,1]
    if (Lu != 0) {
      s0 = -wu / Lu, s1 = (uu - wu) / Lu;
      if (s0 > s1) std::swap(s0, s1);
    } else if (wu < 0 || wu > uu) {
      s1 = s0;  // parallel to the end faces and outside them: empty
    }
    if (s0 < s1) {
      if (ac > 1e-12 * aa) {
        const double disc = bc * bc - ac * cc;
        if (disc >= 0) {
          const double sq = std::sqrt(disc);
          const double c0 = std::max(s0, (-bc - sq) / ac), c1 = std::min(s1, (-bc + sq) / ac);
          if (c0 <= c1) lo = std::min(lo, c0), hi = std::max(hi, c1);
        }
      } else if (cc <= 0) {  // the line runs along the axis, inside the cylinder
        lo = std::min(lo, s0), hi = std::max(hi, s1);
      }
    }
  }
  if (!(lo <= hi)) return false;
  t_in = lo, t_out = hi;
  return true;
}

EditResult apply_brush(SlabModel& m, EditScratch& s, const BrushSweep& sweep) noexcept {
  edit::detail::EditJob job;
  job.start_sweep(m, s, sweep, nullptr);
  return run_to_end(m, s, job);
}

EditResult carve(SlabModel& m, EditScratch& s, const Contact& contact, const Vec3& hip, double radius,
                 double resilience) noexcept {
  if (!contact.in_shell() || !(radius > 0) || !hip.allFinite()) return {};
  Brush b;
  b.tool = BrushTool::Carve;
  b.radius = radius;
  b.resilience = std::max(resilience, 0.0);
  return apply_brush(m, s, stamp_at(contact, hip + contact.normal * (radius + b.resilience), b));
}

EditResult add_material(SlabModel& m, EditScratch& s, const Contact& contact, double radius, double height) noexcept {
  if (!contact.in_shell() || !(radius > 0) || !(height > 0)) return {};
  edit::detail::EditJob job;
  job.start_paper_cone(m, s, contact, radius, height);
  return run_to_end(m, s, job);
}

EditResult paint(SlabModel& m, EditScratch& s, const Contact& contact, double radius, const Vec3f& colour,
                 double pressure) noexcept {
  Brush b;
  b.tool = BrushTool::Paint;
  b.field = BrushField::Colour;
  b.falloff = Falloff::Linear;
  b.radius = radius;
  b.colour = colour;
  BrushSweep sw = stamp_at(contact, contact.surface_point, b);
  sw.pressure = std::clamp(pressure, 0.0, 1.0);
  return apply_brush(m, s, sw);
}

void set_under_layer(SlabModel& m, double thickness, const UnderLayer& material) {
  m.under_layer = material;
  const SampleLayout& L = m.samples;
  std::vector<Unorm16> layer(size_t(L.count));
  for (int32_t id = 0; id < L.count; ++id) {
    Vec3 p0, p1;
    projection_line(m, L.home(id).slab, L.home(id).index, p0, p1);
    const double len = (p1 - p0).norm();
    // Thickness along the surface normal: the layer's top lies thickness / cos(ray, normal) down the ray.
    const double cosine = len > 0 && m.slab_samples.size() == L.slot_count()
                              ? std::max(0.2, std::abs((p1 - p0).dot(sample_normal(m, id).cast<double>())) / len)
                              : 1.0;
    const double top = len > 0 ? m.displacement[id] - std::max(thickness, 0.0) / (len * cosine) : 0.0;
    layer[id] = static_cast<float>(std::clamp(top, 0.0, 1.0));
  }
  m.layer_displacement.assign(std::move(layer));
}

double paint_pressure(double depth, double d0, double d1) noexcept {
  if (!(depth > d0) || !(d1 > d0)) return 0.0;
  return std::min(1.0, (depth - d0) / (d1 - d0));
}

}  // namespace hdm
