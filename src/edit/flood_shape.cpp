// SPDX-License-Identifier: MIT
// The shape brushes' kernels: carve and add (the swept sphere's boolean), and the paper's cone deposit.
#include "edit_kernels.h"

namespace hdm::edit::detail {

namespace {

// Carve / Add: the swept sphere's boolean with the surface, sample by sample.
template <bool add>
bool flood_boolean(EditJob& job, SlabModel& m, EditScratch& s, Deadline& d) noexcept {
  const Brush& b = job.sweep.brush;
  const Vec3 A = job.sweep.from, u = job.u;
  const double uu = u.squaredNorm(), r = b.radius, strength = std::clamp(b.strength, 0.0, 1.0);
  const double r2 = job.r2;
  const bool soft = job.soft;
  StrokeMemory* st = job.stroke;
  const PointEvaluator point_of{m, s.grid_weights.data()};
  DirtyMarker dirty{s};
  // Boolean with the swept sphere. A surface point inside the tool moves to the tool's entry
  // (carve) or exit (add) on its projection line; one outside stays (a tool buried under a
  // column leaves it: no cavities; a tool floating over it adds nothing: no overhangs). The
  // cheap point test decides; the line (evaluated with the point) is intersected only for the
  // samples inside.
  // The fill continues through the surface within `reach` of the tool, which includes the
  // surface the previous sweep left on the tool's boundary.
  const double reach = r + std::max(0.25 * r, 1.5 * s.sample_spacing), reach2 = reach * reach;
  const Vec3 B = job.sweep.to;
  const double inv_uu = uu > 0 ? 1 / uu : 0.0;
  return job.flood(m.samples, s.sample_stamp, s, d, [&](int32_t id) noexcept {
    Vec3 p0, L;  // the projection line, from the slab constants with the point
    const Vec3 w = point_of.point(id, p0, L) - A;
    const double t = std::clamp(w.dot(u) * inv_uu, 0.0, 1.0);
    const double dist2 = (w - t * u).squaredNorm();
    if (dist2 > reach2) return false;
    // On the tool's boundary (within 1e-5 of the radius: where the previous sweep left the
    // surface) nothing is cut: the new capsule would only move it by rounding.
    if (dist2 >= r2 * (1 - 2e-5)) return true;
    double t0, t1;
    if (!line_capsule(p0, L, A, B, r, t0, t1)) return true;
    const float cur = m.displacement[id];
    const double delta = cur;
    if (add ? !(t0 <= delta && delta < t1) : !(t0 < delta && delta <= t1)) return true;  // point test vs exact line
    double target = add ? std::min(t1, 1.0) : std::max(t0, 0.0);
    if (soft) {
      const double base = base_delta(m, st, id);
      const double x = line_segment_distance(p0, L, A, u, uu) / r;
      target = base + strength * falloff_weight(b.falloff, x) * (target - base);
    }
    const float v = static_cast<float>(target);
    if (add ? v > cur : v < cur) job.set_delta(m, s, dirty, id, v, L.squaredNorm());
    return true;
  });
}

// Carve never raises a sample; add never lowers one, and adds nothing without a height.
FloodOn carve_start(const BrushSweep&, double) noexcept { return FloodOn::Samples; }
FloodOn add_start(const BrushSweep& sw, double) noexcept {
  return sw.brush.height > 0 ? FloodOn::Samples : FloodOn::Nothing;
}

}  // namespace

// The registry's entries (brush_registry.cpp) point at these.
extern const BrushHooks carve_brush, add_brush;
const BrushHooks carve_brush{&carve_start, &flood_boolean<false>};
const BrushHooks add_brush{&add_start, &flood_boolean<true>};

// The paper's cone deposit (add_material): raises samples under a cone around the contact.
bool paper_cone_flood(EditJob& job, SlabModel& m, EditScratch& s, Deadline& d) noexcept {
  const Brush& b = job.sweep.brush;
  const Vec3 A = job.sweep.from;
  const double r = b.radius;
  LineEvaluator line_of{m, s.grid_weights.data()};
  DirtyMarker dirty{s};
  return job.flood(m.samples, s.sample_stamp, s, d, [&](int32_t id) noexcept {
    Vec3 p0, p1;
    line_of(id, p0, p1);
    const Vec3 L = p1 - p0;
    const double len = L.norm();
    const double dist = (p0 + double(m.displacement[id]) * L - A).norm();
    if (dist >= r || len <= 0) return false;
    const float raised = static_cast<float>(std::min(1.0, m.displacement[id] + b.height * (1 - dist / r) / len));
    if (raised > m.displacement[id]) job.set_delta(m, s, dirty, id, raised, L.squaredNorm());
    return true;
  });
}

}  // namespace hdm::edit::detail
