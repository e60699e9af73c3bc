// SPDX-License-Identifier: MIT
#pragma once
// Internal: what the brushes' flood kernels share (edit_job.cpp runs them through the brush
// registry; flood_shape.cpp, flood_relax.cpp and flood_paint.cpp hold one brush family each): the projection lines from
// tables, the dirty-slab marks, the brush path's distances, the stroke's first-touch records, and
// the flood fill itself. Inline, since every one runs per visited sample.

#include "edit_job.h"

#include <hdm/query/detail/surface_eval.h>
#include <hdm/slab/triangle_grid.h>

#include <algorithm>
#include <cmath>

namespace hdm::edit::detail {

// projection_line() with the same arithmetic (so the same bits), fed from tables: the grid
// weights come from EditScratch::grid_weights and the six coarse corners of the last home slab are
// kept, since consecutive samples of a flood fill mostly share their home slab.
struct LineEvaluator {
  LineEvaluator(const SlabModel& model, const std::array<double, 3>* w) noexcept : m(model), weights(w) {}
  const SlabModel& m;
  const std::array<double, 3>* weights;
  int32_t slab = -1;
  Vec3 i0 = Vec3::Zero(), i1 = Vec3::Zero(), i2 = Vec3::Zero(), o0 = Vec3::Zero(), o1 = Vec3::Zero(), o2 = Vec3::Zero();
  void operator()(int32_t id, Vec3& p0, Vec3& p1) noexcept {
    const int32_t home = m.samples.home(id).slab;
    if (home != slab) {
      slab = home;
      const Tri& t = m.slabs[home];
      i0 = m.inner[t[0]], i1 = m.inner[t[1]], i2 = m.inner[t[2]];
      o0 = m.outer[t[0]], o1 = m.outer[t[1]], o2 = m.outer[t[2]];
    }
    const std::array<double, 3>& w = weights[m.samples.home(id).index];
    p0 = w[0] * i0 + w[1] * i1 + w[2] * i2;
    p1 = w[0] * o0 + w[1] * o1 + w[2] * o2;
  }
};

// A sample's surface point at its current displacement, from its home slab's constants:
// R0 + wS·e1 + wT·e2 + δ·(dR + wS·d1 + wT·d2), sample_position() to rounding with half its
// arithmetic. The floods' point test (brush distance and falloff) runs it on every visited sample;
// the model keeps no cache of surface points (12 B per sample).
struct PointEvaluator {
  const SlabModel& m;
  const std::array<double, 3>* weights;  // EditScratch::grid_weights: (wR, wS, wT) per grid index
  Vec3 operator()(int32_t id) const noexcept {
    Vec3 p0, L;
    return point(id, p0, L);
  }
  // The same point, with its line's inner end p0 and direction L (p1 - p0, to rounding): what the
  // relaxing brushes need besides it, without evaluating the line again (LineEvaluator).
  Vec3 point(int32_t id, Vec3& p0, Vec3& L) const noexcept {
    const GridSlot h = m.samples.home(id);
    const SlabGeometry& g = m.geometry[h.slab];
    const double wS = weights[h.index][1], wT = weights[h.index][2], d = m.displacement[id].value();
    p0 = g.R0 + wS * g.e1 + wT * g.e2, L = g.dR + wS * g.d1 + wT * g.d2;
    return p0 + d * L;
  }
};

// Flags (once, with the list) the slabs that hold a sample or texel, before it is written: the
// slab of each of its slots (SampleLayout::for_each_slot), each asked of the write gate when first
// flagged. Consecutive slots mostly share a slab, so the slab's slot range is remembered instead of
// dividing each time. A refusal sets EditScratch::write_refused: the caller stops before the write
// and comes back to it on the editor's next call.
struct DirtyMarker {
  EditScratch& s;
  int32_t lo = 0, hi = 0;  // slot range [lo, hi) of the last slab flagged
  bool flag(int32_t slab) noexcept {
    if (s.dirty_slabs[slab]) return true;
    if (s.gate.allow && !s.gate.allow(s.gate.user, slab)) {
      s.write_refused = true;
      return false;
    }
    s.dirty_slabs[slab] = 1;
    s.dirty_list[s.dirty_count++] = slab;
    return true;
  }
  bool mark(const SampleLayout& L, int32_t id) noexcept {
    bool ok = true;
    L.for_each_slot(id, [&](int32_t slot) noexcept {
      if (!ok || (slot >= lo && slot < hi)) return;
      const int32_t slab = slot / L.per_slab;
      ok = flag(slab);
      if (ok) lo = slab * L.per_slab, hi = lo + L.per_slab;
    });
    return ok;
  }
};

// Appends sample c and its grid neighbours not yet stamped with @p stamp to out[count...], stamping
// them; returns the new count. Branch-free, as in the flood (out has room for one more).
inline int32_t add_with_neighbours(const SampleLayout& L, int32_t c, std::vector<uint32_t>& marks, uint32_t stamp,
                                   int32_t* out, int32_t count) noexcept {
  const auto add = [&](int32_t t) noexcept {
    const bool fresh = marks[t] != stamp;
    marks[t] = stamp;
    out[count] = t;
    count += fresh;
  };
  add(c);
  L.for_each_neighbour<false>(c, add);
  return count;
}

// Distance from point p to the segment a + s·u, s in [0,1].
inline double point_segment_distance(const Vec3& p, const Vec3& a, const Vec3& u, double uu) noexcept {
  const Vec3 w = p - a;
  const double s = uu > 0 ? std::clamp(w.dot(u) / uu, 0.0, 1.0) : 0.0;
  return (w - s * u).norm();
}

// The brush path as the soft brushes test it: squared distance to the segment, with the divisions
// done once per sweep.
struct Segment {
  Vec3 a, u;
  double inv_uu;
  Segment(const Vec3& from, const Vec3& dir) noexcept : a(from), u(dir) {
    const double uu = dir.squaredNorm();
    inv_uu = uu > 0 ? 1 / uu : 0.0;
  }
  double distance2(const Vec3& p) const noexcept {
    const Vec3 w = p - a;
    const double t = std::clamp(w.dot(u) * inv_uu, 0.0, 1.0);
    return (w - t * u).squaredNorm();
  }
};

// Falloff at squared distance d2 from the path, for a radius with 1/r² = inv_r2 (no square root
// for the constant falloff); 0 outside.
inline double falloff_at(Falloff f, double d2, double inv_r2) noexcept {
  const double x2 = d2 * inv_r2;
  if (!(x2 < 1)) return 0.0;
  return f == Falloff::Constant ? 1.0 : falloff_weight(f, std::sqrt(x2));
}

// Distance between the line p0 + t·L (all t) and the segment a + s·u, s in [0,1].
inline double line_segment_distance(const Vec3& p0, const Vec3& L, const Vec3& a, const Vec3& u, double uu) noexcept {
  const Vec3 w = p0 - a;
  const double aa = L.squaredNorm();
  if (!(aa > 0)) return point_segment_distance(p0, a, u, uu);
  const double b = L.dot(u), d = L.dot(w), e = u.dot(w);
  const double denom = aa * uu - b * b;
  double s = denom > 1e-12 * aa * uu ? std::clamp((aa * e - b * d) / denom, 0.0, 1.0) : 0.0;
  const double t = (b * s - d) / aa;
  return (w + t * L - s * u).norm();
}

// A sample's displacement changed: the query reads the slab-major copy at once (the normals follow
// in the next refresh), and the sample is listed once for that refresh.
inline void list_changed(SlabModel& m, EditScratch& s, int32_t id) noexcept {
  const Unorm16 v = m.displacement[id];
  if (m.slab_samples.size() == m.samples.slot_count())
    m.samples.for_each_slot(id, [&](int32_t slot) { m.slab_samples[slot].delta = v; });
  if (s.changed_mark[id] == s.changed_epoch) return;
  s.changed_mark[id] = s.changed_epoch;
  s.changed[s.changed_count++] = id;
}

// First touch of a sample (texel) in this stroke: remember and record its values.
inline void touch_sample(const SlabModel& m, StrokeMemory* st, int32_t id) noexcept {
  if (!st || st->sample_mark[id] == st->id) return;
  st->sample_mark[id] = st->id;
  const SampleValues v = sample_values(m, id);
  st->sample_base[id] = v;
  st->sample_k[id] = 0;
  if (st->history) st->history->record(UndoRecord(id, v));
}
// A texel is recorded for undo only when its 8-bit codes first change (record_texel), so a touch
// that rounds to the same codes leaves no record and flags no slab.
inline void touch_texel(const SlabModel& m, StrokeMemory* st, int32_t id) noexcept {
  if (!st || st->texel_mark[id] == st->id) return;
  st->texel_mark[id] = st->id;
  st->texel_base[id] = texel_codes(m, id);
  st->texel_k[id] = 0;
}
// Before a touched texel's codes change from @p stored: records its values at the stroke's start,
// the first time (while its stored codes are still the stroke's base codes).
inline void record_texel(StrokeMemory* st, int32_t id, TexelCodes stored) noexcept {
  if (!st || !st->history) return;
  const TexelCodes base = st->texel_base[id];
  if (!(stored == base)) return;
  const TexelValues v = decode_texel(base);
  st->history->record(UndoRecord(id, v));
}
// A sample's displacement at the start of the stroke (its current one when there is no stroke).
inline double base_delta(const SlabModel& m, const StrokeMemory* st, int32_t id) noexcept {
  return st && st->sample_mark[id] == st->id ? double(st->sample_base[id].delta) : double(m.displacement[id]);
}

// Stores a new displacement on a projection line of squared length line2. With a write gate its
// slabs are flagged first; false (nothing written) when the gate refused one.
inline bool EditJob::set_delta(SlabModel& m, EditScratch& s, DirtyMarker& dirty, int32_t id, float v,
                               double line2) noexcept {
  const Unorm16 q = v;
  if (q.code == m.displacement[id].code) return true;  // rounds to the code it has: nothing to store
  if (s.gate.allow && !dirty.mark(m.samples, id)) return false;
  touch_sample(m, stroke, id);
  const double step = double(float(q)) - double(m.displacement[id]);
  motion2_ = std::max(motion2_, step * step * line2);
  m.displacement[id] = q;
  list_changed(m, s, id);
  ++result.changed;
  return true;
}

template <class Visit>
bool EditJob::flood(const SampleLayout& L, std::vector<uint32_t>& marks, EditScratch& s, Deadline& d,
                    Visit visit) noexcept {
  int32_t* q = s.queue.data();
  size_t head = head_, tail = tail_;
  const uint32_t stamp = stamp_;
  uint32_t* mk = marks.data();
  const bool gated = s.gate.allow != nullptr;  // only a gate refuses: no load per element without one
  while (head < tail) {
    if (d.expired()) {
      head_ = head, tail_ = tail;
      return false;
    }
    const int32_t id = q[head++];
    const bool through = visit(id);
    if (gated && s.write_refused) {  // stopped before a write: visit this element again next time
      head_ = head - 1, tail_ = tail;
      return false;
    }
    if (!through) continue;
    // Branch-free push: whether a neighbour was already queued is a coin flip inside a patch, and
    // a mispredicted branch per neighbour costs more than the unconditional stores.
    L.for_each_neighbour<false>(id, [&](int32_t t) {
      const bool fresh = mk[t] != stamp;
      mk[t] = stamp;
      q[tail] = t;
      tail += fresh;
    });
  }
  head_ = head, tail_ = tail;
  result.visited = static_cast<int32_t>(tail);
  return true;
}

}  // namespace hdm::edit::detail
