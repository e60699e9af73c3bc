// SPDX-License-Identifier: MIT
// The relaxing brushes' kernels: smooth and flatten.
#include "edit_kernels.h"

namespace hdm::edit::detail {

namespace {

// Smooth / Flatten: relaxes displacements towards the neighbours' mean or the tool's plane.
template <bool smooth>
bool flood_relax(EditJob& job, SlabModel& m, EditScratch& s, Deadline& d) noexcept {
  const Brush& b = job.sweep.brush;
  const Segment path(job.sweep.from, job.u);
  const double inv_r2 = 1 / job.r2, coef = job.coef;
  const PointEvaluator point_of{m, s.grid_weights.data()};
  const SampleLayout& S = m.samples;
  const Vec3 q = job.sweep.plane_point, n = job.sweep.plane_normal;
  DirtyMarker dirty{s};
  static constexpr double kInverse[] = {0,      1,       1 / 2.,  1 / 3.,  1 / 4.,  1 / 5.,  1 / 6.,  1 / 7., 1 / 8.,
                                        1 / 9., 1 / 10., 1 / 11., 1 / 12., 1 / 13., 1 / 14., 1 / 15., 1 / 16.};
  return job.flood(S, s.sample_stamp, s, d, [&](int32_t id) noexcept {
    Vec3 p0, L;  // the projection line, from the slab constants with the point (not bit for bit projection_line())
    const double w = falloff_at(b.falloff, path.distance2(point_of.point(id, p0, L)), inv_r2);
    if (!(w > 0)) return false;
    const double e = coef * w;
    // 1 - exp(-e): its series while e is small (per tick e ~ 0.01; error < e⁴/24), else exp.
    const double lambda = e < 0.02 ? e * (1 - e * (0.5 - e * (1.0 / 6))) : 1 - std::exp(-e);
    const float cur = m.displacement[id];
    double target;
    if (smooth) {  // mean of the grid neighbours' displacements (across seams)
      double sum = 0;
      int32_t valence = 0;
      S.for_each_neighbour(id, [&](int32_t t) noexcept { sum += m.displacement[t].value(), ++valence; });
      if (valence == 0) return true;
      target = sum * (valence <= 16 ? kInverse[valence] : 1.0 / valence);
    } else {  // where the projection line meets the tool's plane
      const double ln = L.dot(n);
      if (!(std::abs(ln) > 1e-6 * L.norm())) return true;
      target = std::clamp((q - p0).dot(n) / ln, 0.0, 1.0);
    }
    // A change below half a code step of δ (unorm16) stores nothing: no call.
    const float v = static_cast<float>(cur + lambda * (target - cur));
    if (Unorm16(v).code != m.displacement[id].code) job.set_delta(m, s, dirty, id, v, L.squaredNorm());
    return true;
  });
}

// Both relax at a rate: nothing without contact time, strength and pressure; flatten also needs
// its plane.
FloodOn smooth_start(const BrushSweep&, double coef) noexcept { return coef > 0 ? FloodOn::Samples : FloodOn::Nothing; }
FloodOn flatten_start(const BrushSweep& sw, double coef) noexcept {
  return coef > 0 && sw.plane_normal.allFinite() && sw.plane_point.allFinite() ? FloodOn::Samples : FloodOn::Nothing;
}

}  // namespace

// The registry's entries (brush_registry.cpp) point at these.
extern const BrushHooks smooth_brush, flatten_brush;
const BrushHooks smooth_brush{&smooth_start, &flood_relax<true>};
const BrushHooks flatten_brush{&flatten_start, &flood_relax<false>};

}  // namespace hdm::edit::detail
