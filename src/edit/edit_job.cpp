// SPDX-License-Identifier: MIT
#include "edit_kernels.h"

#include <hdm/edit/brush_registry.h>

#include <algorithm>
#include <cmath>

namespace hdm::edit::detail {

StrokeMemory::StrokeMemory(const SlabModel& m)
    : sample_mark(m.samples.count, 0),
      texel_mark(m.texels.count, 0),
      sample_base(m.samples.count),
      texel_base(m.texels.count),
      sample_k(m.samples.count, 0.0f),
      texel_k(m.texels.count, 0.0f) {}

void StrokeMemory::next_stroke() noexcept {
  if (++id == 0) {  // wrapped: forget every mark once every 2³² strokes
    std::fill(sample_mark.begin(), sample_mark.end(), 0u);
    std::fill(texel_mark.begin(), texel_mark.end(), 0u);
    id = 1;
  }
}

namespace {

uint32_t next_stamp(EditScratch& s) noexcept {
  if (++s.stamp == 0) {  // wrapped: clear every mark once every 2³² edits
    std::fill(s.sample_stamp.begin(), s.sample_stamp.end(), 0u);
    std::fill(s.texel_stamp.begin(), s.texel_stamp.end(), 0u);
    s.stamp = 1;
  }
  return s.stamp;
}

// The three grid points of the cell under barycentrics (wR, wS, wT) of a grid with N intervals.
void cell_points(const SampleLayout& L, int slab, const Vec3& bary, int32_t out[3]) noexcept {
  const int N = L.n;
  const double hx = std::clamp(N * bary[2], 0.0, double(N)), hy = std::clamp(N * bary[1], 0.0, double(N));
  const int i = std::min(static_cast<int>(hx), N - 1), j = std::min(static_cast<int>(hy), N - 1 - i);
  const SlabIds ids = L.slab_ids(slab);
  out[0] = ids[grid::index(N, i, j)];
  out[1] = ids[grid::index(N, i + 1, j)];
  out[2] = ids[grid::index(N, i, j + 1)];
}

}  // namespace

void EditJob::start_sweep(const SlabModel& m, EditScratch& s, const BrushSweep& sw, StrokeMemory* st) noexcept {
  result = {};
  motion2_ = 0;
  phase_ = Phase::Idle;
  const Brush& b = sw.brush;
  const BrushInfo* info = find_brush(b.tool);
  if (!info || sw.seed_slab < 0 || sw.seed_slab >= m.slab_count() || !(b.radius > 0) || !sw.from.allFinite() ||
      !sw.to.allFinite() || !sw.seed_bary.allFinite())
    return;
  sweep = sw;
  stroke = st;
  u = sw.to - sw.from;
  r2 = b.radius * b.radius;
  const double strength = std::clamp(b.strength, 0.0, 1.0), pressure = std::clamp(sw.pressure, 0.0, 1.0);
  soft = strength < 1 || b.falloff != Falloff::Constant;
  // Smooth and flatten relax at 20 s⁻¹ × strength × pressure (time constant 50 ms at full strength).
  coef = 20.0 * strength * pressure * std::max(sw.dt, 0.0);
  kernel_sum = 0;
  kernel_cursor = 0;
  kernel_second = false;
  const FloodOn on = info->hooks->start(sw, coef);
  if (on == FloodOn::Nothing) return;
  flood_ = info->hooks->flood;
  const bool texels = on == FloodOn::Texels;
  const SampleLayout& L = texels ? m.texels : m.samples;
  int32_t seeds[3];
  cell_points(L, sw.seed_slab, sw.seed_bary, seeds);
  stamp_ = next_stamp(s);
  std::vector<uint32_t>& marks = texels ? s.texel_stamp : s.sample_stamp;
  head_ = tail_ = 0;
  for (int k = 0; k < 3; ++k)
    if (marks[seeds[k]] != stamp_) marks[seeds[k]] = stamp_, s.queue[tail_++] = seeds[k];
  phase_ = Phase::Flood;
}

void EditJob::start_paper_cone(const SlabModel& m, EditScratch& s, const Contact& c, double radius,
                               double height) noexcept {
  BrushSweep sw;
  sw.brush.tool = BrushTool::Add;
  sw.brush.radius = radius;
  sw.brush.height = height;
  sw.from = sw.to = c.surface_point;
  sw.seed_slab = c.in_shell() ? c.slab : -1;
  sw.seed_bary = c.coords.bary;
  start_sweep(m, s, sw, nullptr);
  if (phase_ != Phase::Idle) flood_ = &paper_cone_flood;
}

void EditJob::start_history(EditScratch& s, UndoHistory& h, bool redo) noexcept {
  result = {};
  motion2_ = 1e300;  // an undo moves samples by any amount: refresh normals promptly
  phase_ = Phase::Idle;
  if (redo ? !h.can_redo() : !h.can_undo()) return;
  history_ = &h;
  redo_ = redo;
  if (redo)
    h.redo_range(rec_pos_, rec_end_);
  else
    h.undo_range(rec_pos_, rec_end_);
  phase_ = Phase::History;
}

bool EditJob::run_flood(SlabModel& m, EditScratch& s, Deadline& d) noexcept {
  if (!flood_(*this, m, s, d)) return false;
  phase_ = Phase::Idle;
  return true;
}

void EditJob::start_normals(EditScratch& s) noexcept {
  result = {};
  phase_ = s.changed_count > 0 ? Phase::Ring : Phase::Idle;
  cursor_ = ring_count_ = marked_ = 0;
  if (phase_ == Phase::Ring) stamp_ = next_stamp(s);
}

bool EditJob::run_history(SlabModel& m, EditScratch& s, Deadline& d) noexcept {
  DirtyMarker dirty_t{s};
  DirtyMarker dirty_s{s};
  while (rec_pos_ < rec_end_) {
    if (d.expired(2)) return false;
    UndoRecord& r = history_->at(rec_pos_);
    // The record's slabs flagged (and granted) first; a refusal stops before the record.
    if (r.index >= 0 ? !dirty_s.mark(m.samples, r.index) : !dirty_t.mark(m.texels, -(r.index + 1))) return false;
    ++rec_pos_;
    if (r.index >= 0) {
      const int32_t id = r.index;
      const SampleValues now = sample_values(m, id), was = r.sample();
      m.displacement[id] = was.delta;
      m.friction_static.set(id, was.friction_static);
      m.friction_dynamic.set(id, was.friction_dynamic);
      m.stiffness_scale.set(id, was.stiffness_scale);
      m.layer_displacement.set(id, was.layer_displacement);
      m.hardness.set(id, was.hardness);
      r.set(now);
      if (m.displacement[id] != now.delta) list_changed(m, s, id);  // also its slab-major copies
      ++result.changed;
    } else {
      const int32_t id = -(r.index + 1);
      const TexelValues now = texel_values(m, id);
      const TexelValues was = r.texel();
      set_texel_values(m, id, was.r, was.g, was.b, was.roughness);
      r.set(now);
      ++result.changed;
    }
  }
  if (redo_)
    history_->redone();
  else
    history_->undone();
  phase_ = Phase::Idle;
  return true;
}

// After displacements changed (their slab-major copies already refreshed): normals of the changed
// samples and their one-ring (docs/design.md#normals), the slab-major copy, then the force-shading
// normals of the ring and its neighbours; dirty flags of every slab holding a ring sample (its normal changed) or a
// sample whose force-shading code changed.
bool EditJob::run_normals(SlabModel& m, EditScratch& s, Deadline& d) noexcept {
  const SampleLayout& L = m.samples;
  constexpr int32_t kChunk = 16;
  if (phase_ == Phase::Ring) {
    DirtyMarker dirty{s};
    for (;;) {
      for (; marked_ < ring_count_; ++marked_)  // their normals change: flagged before written
        if (!dirty.mark(L, s.ring[marked_])) return false;
      if (cursor_ >= s.changed_count) break;
      if (d.expired(kChunk)) return false;
      const int32_t end = std::min(s.changed_count, cursor_ + kChunk);
      for (; cursor_ < end; ++cursor_)
        ring_count_ = add_with_neighbours(L, s.changed[cursor_], s.sample_stamp, stamp_, s.ring.data(), ring_count_);
    }
    phase_ = Phase::Normals;
    cursor_ = 0;
  }
  if (phase_ == Phase::Normals) {
    while (cursor_ < ring_count_) {
      if (d.expired(8 * kChunk)) return false;  // a normal costs several flood visits
      const int32_t n = std::min(kChunk, ring_count_ - cursor_);
      // Normals into the slab-major copy.
      update_normals(m, s.ring.data() + cursor_, static_cast<size_t>(n), s.faces, false);
      cursor_ += n;
    }
    phase_ = Phase::ShadingRing;
    cursor_ = shading_count_ = marked_ = 0;
    stamp_ = next_stamp(s);
  }
  if (phase_ == Phase::ShadingRing) {
    // The force-shading normals read the one-ring of normals: the ring and its neighbours may
    // change, each listed once (the flood is done, so its queue is free to hold them).
    while (cursor_ < ring_count_) {
      if (d.expired(kChunk)) return false;
      const int32_t end = std::min(ring_count_, cursor_ + kChunk);
      for (; cursor_ < end; ++cursor_)
        shading_count_ =
            add_with_neighbours(L, s.ring[cursor_], s.sample_stamp, stamp_, s.queue.data(), shading_count_);
    }
    phase_ = Phase::ForceShading;
    cursor_ = 0;
  }
  // A sample's slabs are flagged only when its stored code changes: a slab whose data are the same
  // keeps its epoch, so a renderer does not upload it again.
  DirtyMarker dirty{s};
  while (cursor_ < shading_count_) {
    if (d.expired(4 * kChunk)) return false;
    const int32_t end = std::min(shading_count_, cursor_ + 2 * kChunk);
    for (; cursor_ < end; ++cursor_) {
      const int32_t id = s.queue[cursor_];
      const ForceShadingCode c = force_shading_code(m, id);
      if (std::equal(c.begin(), c.end(), home_slab_sample(m, id).h)) continue;
      if (!dirty.mark(L, id)) return false;
      store_force_shading_code(m, id, c);
    }
  }
  // The listed samples are refreshed: start a new listing.
  s.changed_count = 0;
  if (++s.changed_epoch == 0) {
    std::fill(s.changed_mark.begin(), s.changed_mark.end(), 0u);
    s.changed_epoch = 1;
  }
  phase_ = Phase::Idle;
  return true;
}

bool EditJob::run(SlabModel& m, EditScratch& s, Deadline& d) noexcept {
  s.write_refused = false;
  switch (phase_) {
    case Phase::Idle:
      return true;
    case Phase::Flood:
      return run_flood(m, s, d);
    case Phase::History:
      return run_history(m, s, d);
    default:
      return run_normals(m, s, d);
  }
}

}  // namespace hdm::edit::detail
