// SPDX-License-Identifier: MIT
// The drill brush's kernel: material removed by Archard's wear law (Archard 1953, "Contact and
// rubbing of flat surfaces", J. Appl. Phys. 24(8), 981-988), V = K·F_n·v_s·Δt / H.
#include "edit_kernels.h"

#include <numbers>

namespace hdm::edit::detail {

namespace {

// A draw in [0, 1) for a sample and a sweep's stamp: a Weyl sequence in each (the fractional parts
// of id·φ and stamp·c, mod 2^32), evenly spread over the samples of a sweep and over the sweeps of
// a sample, and fixed, so a stroke replays to the same model.
float uniform_draw(uint32_t id, uint32_t stamp) noexcept {
  const uint32_t h = id * 0x9E3779B9u + stamp * 0x632BE5ABu;
  return float(h >> 8) * (1.0f / 16777216.0f);
}

// The surface element of a sample: the cross product of its home slab's alpha-triangle edges at
// the sample's displacement, over n² (so its norm is two grid triangles' area [model units²], the
// area a sample stands for on a regular grid, and its direction the alpha-plane's normal).
Vec3 sample_element(const SlabModel& m, int32_t id) noexcept {
  const SlabGeometry& g = m.geometry[m.samples.home(id).slab];
  const double a = m.displacement[id].value(), n = m.grid_n;
  return (g.e1 + a * g.d1).cross(g.e2 + a * g.d2) / (n * n);
}

// Two passes over the samples within the radius of the contact's path: the flood sums their
// falloff-weighted area (the contact area the force spreads over); then each visited sample takes
// its share of the force, F_i = F_n·w_i·A_i / Σ w·A, and is lowered by its own Archard depth
// K·F_i·v_s·Δt / (H_i·A_i) along the surface normal.
bool drill_flood(EditJob& job, SlabModel& m, EditScratch& s, Deadline& d) noexcept {
  const Brush& b = job.sweep.brush;
  const Segment path(job.sweep.from, job.u);
  const double inv_r2 = 1 / job.r2;
  const PointEvaluator point_of{m, s.grid_weights.data()};
  auto weight = [&](int32_t id) noexcept { return falloff_at(b.falloff, path.distance2(point_of(id)), inv_r2); };
  if (!job.kernel_second) {
    const bool done = job.flood(m.samples, s.sample_stamp, s, d, [&](int32_t id) noexcept {
      const double w = weight(id);
      if (!(w > 0)) return false;
      job.kernel_sum += w * sample_element(m, id).norm();
      return true;
    });
    if (!done) return false;
    job.kernel_second = true;
    job.kernel_cursor = 0;
  }
  const double upm = job.sweep.units_per_metre;
  const double area_m2 = job.kernel_sum / (upm * upm);
  if (!(area_m2 > 0)) return true;
  // v_s = ω·r [m/s], ω at the pedal's fraction `strength` of the burr's speed.
  const double speed = std::clamp(b.strength, 0.0, 1.0) * 2 * std::numbers::pi * b.rpm / 60 * (b.radius / upm);
  // Depth at weight 1 and hardness 1 Pa, in model units: K·F_n·v_s·Δt / area [m·Pa] × upm.
  const double depth_pa = b.wear_coefficient * job.sweep.normal_force_n * speed * job.sweep.dt / area_m2 * upm;
  DirtyMarker dirty{s};
  while (job.kernel_cursor < job.result.visited) {
    if (d.expired()) return false;
    const int32_t id = s.queue[job.kernel_cursor++];
    Vec3 p0, L;  // the projection line, from the slab constants with the point
    const double w = falloff_at(b.falloff, path.distance2(point_of.point(id, p0, L)), inv_r2);
    if (!(w > 0)) continue;
    const double depth = depth_pa * w / vickers_to_pa(sample_hardness_hv(m, id));  // along the normal
    const Vec3 e = sample_element(m, id);
    // Model units along the normal per unit of δ: L·n̂, at least 0.2·|L| (a line at a grazing angle).
    const double per_delta = std::max(L.dot(e) / e.norm(), 0.2 * L.norm());
    if (!(per_delta > 0)) continue;
    // A tick's removal is often far below a code step of δ (unorm16): rounded to nearest it would
    // vanish, so it is rounded up or down at random with the odds that keep its expected volume.
    const float v = Unorm16::dithered(float(std::max(0.0, m.displacement[id] - depth / per_delta)),
                                      uniform_draw(uint32_t(id), job.stamp()));
    if (v < m.displacement[id] && !job.set_delta(m, s, dirty, id, v, L.squaredNorm())) {
      --job.kernel_cursor;  // refused: this sample first, on the next call
      return false;
    }
  }
  return true;
}

// Nothing without force, contact time, a positive wear coefficient, speed (rpm and strength) or scale.
FloodOn drill_start(const BrushSweep& sw, double) noexcept {
  const Brush& b = sw.brush;
  const bool on = sw.normal_force_n > 0 && sw.dt > 0 && b.wear_coefficient > 0 && b.rpm > 0 && b.strength > 0 &&
                  sw.units_per_metre > 0 && std::isfinite(sw.normal_force_n * sw.dt * b.wear_coefficient * b.rpm) &&
                  std::isfinite(sw.units_per_metre);
  return on ? FloodOn::Samples : FloodOn::Nothing;
}

}  // namespace

// The registry's entry (brush_registry.cpp) points at this.
extern const BrushHooks drill_brush;
const BrushHooks drill_brush{&drill_start, &drill_flood};

}  // namespace hdm::edit::detail
