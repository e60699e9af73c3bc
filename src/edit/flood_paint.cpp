// SPDX-License-Identifier: MIT
// The paint brush's kernel: per-sample fields, and per-texel colour and roughness.
#include "edit_kernels.h"

namespace hdm::edit::detail {

namespace {

// Paint of a per-sample field (friction, stiffness, layer thickness), once per stroke.
bool flood_paint_samples(EditJob& job, SlabModel& m, EditScratch& s, Deadline& d) noexcept {
  const Brush& b = job.sweep.brush;
  const double strength = std::clamp(b.strength, 0.0, 1.0);
  const Segment path(job.sweep.from, job.u);
  const double inv_r2 = 1 / job.r2;
  const double pressure = std::clamp(job.sweep.pressure, 0.0, 1.0);
  StrokeMemory* st = job.stroke;
  LineEvaluator line_of{m, s.grid_weights.data()};
  const PointEvaluator point_of{m, s.grid_weights.data()};
  const SampleLayout& S = m.samples;
  DirtyMarker dirty{s};
  return job.flood(S, s.sample_stamp, s, d, [&](int32_t id) noexcept {
    const double w = falloff_at(b.falloff, path.distance2(point_of(id)), inv_r2);
    if (!(w > 0)) return false;
    const float k = static_cast<float>(pressure * strength * w);
    if (!(k > (st && st->sample_mark[id] == st->id ? st->sample_k[id] : 0.0f))) return true;
    if (!dirty.mark(S, id)) return true;  // refused: the flood stops before this sample
    touch_sample(m, st, id);
    const SampleValues base = st ? st->sample_base[id] : sample_values(m, id);
    if (st) st->sample_k[id] = k;
    auto blend = [k](float from, float to) { return k * to + (1 - k) * from; };
    switch (b.field) {
      case BrushField::FrictionStatic:
        m.friction_static.set(id, blend(base.friction_static, b.value));
        break;
      case BrushField::FrictionDynamic:
        m.friction_dynamic.set(id, blend(base.friction_dynamic, b.value));
        break;
      case BrushField::Stiffness:
        m.stiffness_scale.set(id, blend(base.stiffness_scale, b.value));
        break;
      case BrushField::Hardness:
        m.hardness.set(id, std::max(blend(base.hardness, b.value), 1.0f));
        break;
      default: {  // LayerThickness: the layer's top `value` below the stroke's starting surface
        Vec3 p0, p1;
        line_of(id, p0, p1);
        const double len = (p1 - p0).norm();
        if (!(len > 0)) return true;
        const float top = static_cast<float>(std::clamp(base.delta - b.value / len, 0.0, 1.0));
        m.layer_displacement.set(id, std::clamp(blend(base.layer_displacement, top), 0.0f, 1.0f));
      }
    }
    ++job.result.changed;
    return true;
  });
}

// Paint of a per-texel field (colour, roughness), once per stroke.
bool flood_paint_texels(EditJob& job, SlabModel& m, EditScratch& s, Deadline& d) noexcept {
  const Brush& b = job.sweep.brush;
  const double strength = std::clamp(b.strength, 0.0, 1.0);
  const Segment path(job.sweep.from, job.u);
  const double inv_r2 = 1 / job.r2;
  const double pressure = std::clamp(job.sweep.pressure, 0.0, 1.0);
  StrokeMemory* st = job.stroke;
  const SampleLayout& T = m.texels;
  DirtyMarker dirty{s};
  int32_t cached = -1;
  const SlabGeometry* g = nullptr;
  const SlabSample* v = nullptr;
  return job.flood(T, s.texel_stamp, s, d, [&](int32_t id) noexcept {
    const int32_t local = T.home(id).index, slab = T.home(id).slab;
    if (slab != cached) {  // consecutive texels mostly share their home slab
      cached = slab;
      g = &m.geometry[slab];
      v = m.slab_samples.data() + static_cast<size_t>(slab) * m.samples.per_slab;
    }
    // The texel on the displaced surface: surface_point() with the cell from the table.
    const std::array<double, 5>& w = s.texel_weights[local];
    const std::array<int32_t, 3>& c = s.texel_points[local];
    const double delta = w[2] * v[c[0]].delta.value() + w[3] * v[c[1]].delta.value() + w[4] * v[c[2]].delta.value();
    const Vec3 p = g->R0 + w[0] * g->e1 + w[1] * g->e2 + delta * (g->dR + w[0] * g->d1 + w[1] * g->d2);
    const double fw = falloff_at(b.falloff, path.distance2(p), inv_r2);
    if (!(fw > 0)) return false;
    const float k = static_cast<float>(pressure * strength * fw);
    if (!(k > (st && st->texel_mark[id] == st->id ? st->texel_k[id] : 0.0f))) return true;
    touch_texel(m, st, id);
    // Blended from the stroke's base, never from the stored (quantised) value, and rounded once
    // to 8 bits: later ticks of the stroke rewrite the texel, they do not drift it.
    const TexelCodes stored = texel_codes(m, id), base = st ? st->texel_base[id] : stored;
    TexelCodes now = stored;
    if (b.field == BrushField::Colour)
      now.colour = encode_srgb8(k * b.colour + (1 - k) * decode_srgb8(base.colour));
    else
      now.roughness = unit_to_unorm8(k * b.value + (1 - k) * unorm8_to_unit(base.roughness));
    // A rise of k too small to move a code changes nothing: no undo record, no dirty slab. A store
    // needs the texel's slabs flagged (granted by the write gate), asked only when the codes move;
    // into a flagged interior texel's slab the same codes are stored without a branch on whether
    // they moved (a coin flip at the brush's rim).
    const bool moved = !(now == stored);
    if (id < T.first_interior || !s.dirty_slabs[slab]) {
      if (!moved) {
        if (st) st->texel_k[id] = k;
        return true;
      }
      if (!(id < T.first_interior ? dirty.mark(T, id) : dirty.flag(slab))) return true;  // refused: stop before it
    }
    if (st) st->texel_k[id] = k;
    m.colour.set(id, now.colour);
    m.roughness.set(id, now.roughness);
    job.result.changed += moved;
    if (moved & (stored == base)) record_texel(st, id, stored);  // its first change this stroke
    return true;
  });
}

bool texel_field(BrushField f) noexcept { return f == BrushField::Colour || f == BrushField::Roughness; }

// Paint blends once per stroke: nothing at zero strength or pressure.
FloodOn paint_start(const BrushSweep& sw, double) noexcept {
  if (!(std::clamp(sw.brush.strength, 0.0, 1.0) * std::clamp(sw.pressure, 0.0, 1.0) > 0)) return FloodOn::Nothing;
  return texel_field(sw.brush.field) ? FloodOn::Texels : FloodOn::Samples;
}
bool paint_flood(EditJob& job, SlabModel& m, EditScratch& s, Deadline& d) noexcept {
  return texel_field(job.sweep.brush.field) ? flood_paint_texels(job, m, s, d) : flood_paint_samples(job, m, s, d);
}

}  // namespace

// The registry's entry (brush_registry.cpp) points at this.
extern const BrushHooks paint_brush;
const BrushHooks paint_brush{&paint_start, &paint_flood};

}  // namespace hdm::edit::detail
