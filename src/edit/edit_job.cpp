// SPDX-License-Identifier: MIT
#include "edit_job.h"

#include <hdm/slab/triangle_grid.h>

#include <hdm/query/detail/surface_eval.h>

#include <algorithm>
#include <cmath>

namespace hdm::detail {

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
  const int32_t* ids = &L.ids[static_cast<size_t>(slab) * L.per_slab];
  out[0] = ids[grid::index(N, i, j)];
  out[1] = ids[grid::index(N, i + 1, j)];
  out[2] = ids[grid::index(N, i, j + 1)];
}

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
    const int32_t home = m.samples.home_slab[id];
    if (home != slab) {
      slab = home;
      const Tri& t = m.slabs[home];
      i0 = m.inner[t[0]], i1 = m.inner[t[1]], i2 = m.inner[t[2]];
      o0 = m.outer[t[0]], o1 = m.outer[t[1]], o2 = m.outer[t[2]];
    }
    const std::array<double, 3>& w = weights[m.samples.home_index[id]];
    p0 = w[0] * i0 + w[1] * i1 + w[2] * i2;
    p1 = w[0] * o0 + w[1] * o1 + w[2] * o2;
  }
};

// Flags (once, with the list) the slabs of the grid triangles incident to a sample or texel.
// Consecutive incident triangles mostly share a slab, so the slab range is remembered instead of
// dividing each time.
struct DirtyMarker {
  EditScratch& s;
  int32_t per_slab;
  int32_t lo = 0, hi = 0;  // triangle range [lo, hi) of the last slab flagged
  void flag(int32_t slab) noexcept {
    if (s.dirty_slabs[slab]) return;
    s.dirty_slabs[slab] = 1;
    s.dirty_list[s.dirty_count++] = slab;
  }
  void mark(const SampleLayout& L, int32_t id) noexcept {
    if (id >= L.first_interior) {  // interior: held by its home slab only
      flag(L.home_slab[id]);
      return;
    }
    for (int32_t e = L.triangle_offsets[id]; e < L.triangle_offsets[id + 1]; ++e) {
      const int32_t tri = L.incident_triangles[e];
      if (tri >= lo && tri < hi) continue;
      const int32_t slab = tri / per_slab;
      flag(slab);
      lo = slab * per_slab, hi = lo + per_slab;
    }
  }
};

// Appends sample c and its grid neighbours not yet stamped with @p stamp to out[count...], stamping
// them; returns the new count. Branch-free, as in the flood (out has room for one more).
int32_t add_with_neighbours(const SampleLayout& L, int32_t c, std::vector<uint32_t>& marks, uint32_t stamp,
                            int32_t* out, int32_t count) noexcept {
  for (int32_t e = L.neighbour_offsets[c] - 1; e < L.neighbour_offsets[c + 1]; ++e) {
    const int32_t t = e < L.neighbour_offsets[c] ? c : L.neighbours[e];
    const bool fresh = marks[t] != stamp;
    marks[t] = stamp;
    out[count] = t;
    count += fresh;
  }
  return count;
}

// Distance from point p to the segment a + s·u, s in [0,1].
double point_segment_distance(const Vec3& p, const Vec3& a, const Vec3& u, double uu) noexcept {
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
double line_segment_distance(const Vec3& p0, const Vec3& L, const Vec3& a, const Vec3& u, double uu) noexcept {
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
void list_changed(SlabModel& m, EditScratch& s, int32_t id) noexcept {
  const float v = m.displacement[id];
  if (m.slab_samples.size() == m.samples.ids.size())
    m.samples.for_each_slot(id, [&](int32_t slot) { m.slab_samples[slot].delta = v; });
  if (s.changed_mark[id] == s.changed_epoch) return;
  s.changed_mark[id] = s.changed_epoch;
  s.changed[s.changed_count++] = id;
}

}  // namespace

void EditJob::start_sweep(const SlabModel& m, EditScratch& s, const BrushSweep& sw, StrokeMemory* stroke) noexcept {
  result = {};
  motion2_ = 0;
  phase_ = Phase::Idle;
  const Brush& b = sw.brush;
  if (sw.seed_slab < 0 || sw.seed_slab >= m.slab_count() || !(b.radius > 0) || !sw.from.allFinite() ||
      !sw.to.allFinite() || !sw.seed_bary.allFinite())
    return;
  sweep_ = sw;
  stroke_ = stroke;
  u_ = sw.to - sw.from;
  r2_ = b.radius * b.radius;
  const double strength = std::clamp(b.strength, 0.0, 1.0), pressure = std::clamp(sw.pressure, 0.0, 1.0);
  soft_ = strength < 1 || b.falloff != Falloff::Constant;
  // Smooth and flatten relax at 20 s⁻¹ × strength × pressure (time constant 50 ms at full strength).
  coef_ = 20.0 * strength * pressure * std::max(sw.dt, 0.0);
  switch (b.tool) {
    case BrushTool::Carve:
      kernel_ = Kernel::Carve;
      break;
    case BrushTool::Add:
      kernel_ = Kernel::Add;
      break;
    case BrushTool::Smooth:
      kernel_ = Kernel::Smooth;
      break;
    case BrushTool::Flatten:
      kernel_ = Kernel::Flatten;
      break;
    case BrushTool::Paint:
      kernel_ =
          b.field == BrushField::Colour || b.field == BrushField::Roughness ? Kernel::PaintTexel : Kernel::PaintSample;
      break;
  }
  if ((kernel_ == Kernel::Smooth || kernel_ == Kernel::Flatten) && !(coef_ > 0)) return;
  if ((kernel_ == Kernel::PaintTexel || kernel_ == Kernel::PaintSample) && !(strength * pressure > 0)) return;
  if (kernel_ == Kernel::Flatten && !(sw.plane_normal.allFinite() && sw.plane_point.allFinite())) return;
  if (kernel_ == Kernel::Add && !(b.height > 0)) return;
  const SampleLayout& L = kernel_ == Kernel::PaintTexel ? m.texels : m.samples;
  int32_t seeds[3];
  cell_points(L, sw.seed_slab, sw.seed_bary, seeds);
  stamp_ = next_stamp(s);
  std::vector<uint32_t>& marks = kernel_ == Kernel::PaintTexel ? s.texel_stamp : s.sample_stamp;
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
  if (phase_ != Phase::Idle) kernel_ = Kernel::PaperCone;
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

template <class Visit>
bool EditJob::flood(const SampleLayout& L, std::vector<uint32_t>& marks, EditScratch& s, Deadline& d,
                    Visit visit) noexcept {
  int32_t* q = s.queue.data();
  size_t head = head_, tail = tail_;
  const uint32_t stamp = stamp_;
  const int32_t* offsets = L.neighbour_offsets.data();
  const int32_t* nb = L.neighbours.data();
  uint32_t* mk = marks.data();
  while (head < tail) {
    if (d.expired()) {
      head_ = head, tail_ = tail;
      return false;
    }
    const int32_t id = q[head++];
    if (!visit(id)) continue;
    // Branch-free push: whether a neighbour was already queued is a coin flip inside a patch, and
    // a mispredicted branch per neighbour costs more than the unconditional stores.
    for (int32_t e = offsets[id]; e < offsets[id + 1]; ++e) {
      const int32_t t = nb[e];
      const bool fresh = mk[t] != stamp;
      mk[t] = stamp;
      q[tail] = t;
      tail += fresh;
    }
  }
  head_ = head, tail_ = tail;
  result.visited = static_cast<int32_t>(tail);
  return true;
}

// First touch of a sample (texel) in this stroke: remember and record its values.
static inline void touch_sample(const SlabModel& m, StrokeMemory* st, int32_t id) noexcept {
  if (!st || st->sample_mark[id] == st->id) return;
  st->sample_mark[id] = st->id;
  const SampleValues v = sample_values(m, id);
  st->sample_base[id] = v;
  st->sample_k[id] = 0;
  if (st->history)
    st->history->record(
        {id, {v.delta, v.friction_static, v.friction_dynamic, v.stiffness_scale, v.layer_displacement}});
}
static inline void touch_texel(const SlabModel& m, StrokeMemory* st, int32_t id) noexcept {
  if (!st || st->texel_mark[id] == st->id) return;
  st->texel_mark[id] = st->id;
  const TexelValues v = texel_values(m, id);
  st->texel_base[id] = v;
  st->texel_k[id] = 0;
  if (st->history) st->history->record({-(id + 1), {v.r, v.g, v.b, v.roughness, 0.0f}});
}
// A sample's displacement at the start of the stroke (its current one when there is no stroke).
static inline double base_delta(const SlabModel& m, const StrokeMemory* st, int32_t id) noexcept {
  return st && st->sample_mark[id] == st->id ? double(st->sample_base[id].delta) : double(m.displacement[id]);
}

// Stores a new displacement and its position (= sample_position(), same arithmetic).
inline void EditJob::set_delta(SlabModel& m, EditScratch& s, int32_t id, float v, const Vec3& p0,
                               const Vec3& L) noexcept {
  touch_sample(m, stroke_, id);
  const double step = double(v) - double(m.displacement[id]);
  motion2_ = std::max(motion2_, step * step * L.squaredNorm());
  m.displacement[id] = v;
  m.positions[id] = (p0 + static_cast<double>(v) * L).cast<float>();
  list_changed(m, s, id);
  ++result.changed;
}

// Carve / Add: the swept sphere's boolean with the surface, sample by sample.
bool EditJob::flood_boolean(SlabModel& m, EditScratch& s, Deadline& d) noexcept {
  const Brush& b = sweep_.brush;
  const Vec3 A = sweep_.from, u = u_;
  const double uu = u.squaredNorm(), r = b.radius, strength = std::clamp(b.strength, 0.0, 1.0);
  StrokeMemory* st = stroke_;
  LineEvaluator line_of{m, s.grid_weights.data()};
  // Boolean with the swept sphere. A surface point inside the tool moves to the tool's entry
  // (carve) or exit (add) on its projection line; one outside stays (a tool buried under a
  // column leaves it: no cavities; a tool floating over it adds nothing: no overhangs). The
  // cheap point test decides; the line is intersected only for the samples that change.
  // The fill continues through the surface within `reach` of the tool, which includes the
  // surface the previous sweep left on the tool's boundary.
  const bool add = kernel_ == Kernel::Add;
  const double reach = r + std::max(0.25 * r, 1.5 * s.sample_spacing), reach2 = reach * reach;
  const Vec3 B = sweep_.to;
  const double inv_uu = uu > 0 ? 1 / uu : 0.0;
  return flood(m.samples, s.sample_stamp, s, d, [&](int32_t id) noexcept {
    const Vec3 w = m.positions[id].cast<double>() - A;
    const double t = std::clamp(w.dot(u) * inv_uu, 0.0, 1.0);
    const double dist2 = (w - t * u).squaredNorm();
    if (dist2 > reach2) return false;
    // On the tool's boundary (within 1e-5 of the radius: where the previous sweep left the
    // surface) nothing is cut: the new capsule would only move it by rounding.
    if (dist2 >= r2_ * (1 - 2e-5)) return true;
    Vec3 p0, p1;
    line_of(id, p0, p1);
    const Vec3 L = p1 - p0;
    double t0, t1;
    if (!line_capsule(p0, L, A, B, r, t0, t1)) return true;
    const float cur = m.displacement[id];
    const double delta = cur;
    if (add ? !(t0 <= delta && delta < t1) : !(t0 < delta && delta <= t1))
      return true;  // float position vs exact line
    double target = add ? std::min(t1, 1.0) : std::max(t0, 0.0);
    if (soft_) {
      const double base = base_delta(m, st, id);
      const double x = line_segment_distance(p0, L, A, u, uu) / r;
      target = base + strength * falloff_weight(b.falloff, x) * (target - base);
    }
    const float v = static_cast<float>(target);
    if (add ? v > cur : v < cur) set_delta(m, s, id, v, p0, L);
    return true;
  });
}

// The paper's cone deposit (add_material): raises samples under a cone around the contact.
bool EditJob::flood_paper_cone(SlabModel& m, EditScratch& s, Deadline& d) noexcept {
  const Brush& b = sweep_.brush;
  const Vec3 A = sweep_.from;
  const double r = b.radius;
  LineEvaluator line_of{m, s.grid_weights.data()};
  return flood(m.samples, s.sample_stamp, s, d, [&](int32_t id) noexcept {
    Vec3 p0, p1;
    line_of(id, p0, p1);
    const Vec3 L = p1 - p0;
    const double len = L.norm();
    const double dist = (p0 + double(m.displacement[id]) * L - A).norm();
    if (dist >= r || len <= 0) return false;
    const float raised = static_cast<float>(std::min(1.0, m.displacement[id] + b.height * (1 - dist / r) / len));
    if (raised > m.displacement[id]) set_delta(m, s, id, raised, p0, L);
    return true;
  });
}

// Smooth / Flatten: relaxes displacements towards the neighbours' mean or the tool's plane.
bool EditJob::flood_relax(SlabModel& m, EditScratch& s, Deadline& d) noexcept {
  const Brush& b = sweep_.brush;
  const Segment path(sweep_.from, u_);
  const double inv_r2 = 1 / r2_;
  LineEvaluator line_of{m, s.grid_weights.data()};
  const SampleLayout& S = m.samples;
  const bool smooth = kernel_ == Kernel::Smooth;
  const Vec3 q = sweep_.plane_point, n = sweep_.plane_normal;
  static constexpr double kInverse[] = {0,       1,       1 / 2.,  1 / 3.,  1 / 4.,  1 / 5.,
                                        1 / 6.,  1 / 7.,  1 / 8.,  1 / 9.,  1 / 10., 1 / 11.,
                                        1 / 12., 1 / 13., 1 / 14., 1 / 15., 1 / 16.};
  return flood(S, s.sample_stamp, s, d, [&](int32_t id) noexcept {
    const double w = falloff_at(b.falloff, path.distance2(m.positions[id].cast<double>()), inv_r2);
    if (!(w > 0)) return false;
    const double e = coef_ * w;
    // 1 - exp(-e): its series while e is small (per tick e ~ 0.01; error < e⁴/24), else exp.
    const double lambda = e < 0.02 ? e * (1 - e * (0.5 - e * (1.0 / 6))) : 1 - std::exp(-e);
    const float cur = m.displacement[id];
    Vec3 p0, p1;
    double target;
    if (smooth) {  // mean of the grid neighbours' displacements (across seams)
      double sum = 0;
      const int32_t first = S.neighbour_offsets[id], last = S.neighbour_offsets[id + 1];
      for (int32_t e = first; e < last; ++e) sum += m.displacement[S.neighbours[e]];
      const int32_t valence = last - first;
      if (valence == 0) return true;
      target = sum * (valence <= 16 ? kInverse[valence] : 1.0 / valence);
      if (static_cast<float>(cur + lambda * (target - cur)) == cur) return true;
      line_of(id, p0, p1);
    } else {  // where the projection line meets the tool's plane
      line_of(id, p0, p1);
      const Vec3 L = p1 - p0;
      const double ln = L.dot(n);
      if (!(std::abs(ln) > 1e-6 * L.norm())) return true;
      target = std::clamp((q - p0).dot(n) / ln, 0.0, 1.0);
    }
    const float v = static_cast<float>(cur + lambda * (target - cur));
    if (v != cur) set_delta(m, s, id, v, p0, p1 - p0);
    return true;
  });
}

// Paint of a per-sample field (friction, stiffness, layer thickness), once per stroke.
bool EditJob::flood_paint_samples(SlabModel& m, EditScratch& s, Deadline& d) noexcept {
  const Brush& b = sweep_.brush;
  const double strength = std::clamp(b.strength, 0.0, 1.0);
  const Segment path(sweep_.from, u_);
  const double inv_r2 = 1 / r2_;
  const double pressure = std::clamp(sweep_.pressure, 0.0, 1.0);
  StrokeMemory* st = stroke_;
  LineEvaluator line_of{m, s.grid_weights.data()};
  const SampleLayout& S = m.samples;
  DirtyMarker dirty{s, S.n * S.n};
  return flood(S, s.sample_stamp, s, d, [&](int32_t id) noexcept {
    const double w = falloff_at(b.falloff, path.distance2(m.positions[id].cast<double>()), inv_r2);
    if (!(w > 0)) return false;
    const float k = static_cast<float>(pressure * strength * w);
    if (!(k > (st && st->sample_mark[id] == st->id ? st->sample_k[id] : 0.0f))) return true;
    touch_sample(m, st, id);
    const SampleValues base = st ? st->sample_base[id] : sample_values(m, id);
    if (st) st->sample_k[id] = k;
    auto blend = [k](float from, float to) { return k * to + (1 - k) * from; };
    switch (b.field) {
      case BrushField::FrictionStatic:
        m.friction_static[id] = blend(base.friction_static, b.value);
        break;
      case BrushField::FrictionDynamic:
        m.friction_dynamic[id] = blend(base.friction_dynamic, b.value);
        break;
      case BrushField::Stiffness:
        m.stiffness_scale[id] = blend(base.stiffness_scale, b.value);
        break;
      default: {  // LayerThickness: the layer's top `value` below the stroke's starting surface
        Vec3 p0, p1;
        line_of(id, p0, p1);
        const double len = (p1 - p0).norm();
        if (!(len > 0)) return true;
        const float top = static_cast<float>(std::clamp(base.delta - b.value / len, 0.0, 1.0));
        m.layer_displacement[id] = std::clamp(blend(base.layer_displacement, top), 0.0f, 1.0f);
      }
    }
    ++result.changed;
    dirty.mark(S, id);
    return true;
  });
}

// Paint of a per-texel field (colour, roughness), once per stroke.
bool EditJob::flood_paint_texels(SlabModel& m, EditScratch& s, Deadline& d) noexcept {
  const Brush& b = sweep_.brush;
  const double strength = std::clamp(b.strength, 0.0, 1.0);
  const Segment path(sweep_.from, u_);
  const double inv_r2 = 1 / r2_;
  const double pressure = std::clamp(sweep_.pressure, 0.0, 1.0);
  StrokeMemory* st = stroke_;
  const SampleLayout& T = m.texels;
  DirtyMarker dirty{s, T.n * T.n};
  int32_t cached = -1;
  const SlabGeometry* g = nullptr;
  const SlabSample* v = nullptr;
  return flood(T, s.texel_stamp, s, d, [&](int32_t id) noexcept {
    const int32_t local = T.home_index[id], slab = T.home_slab[id];
    if (slab != cached) {  // consecutive texels mostly share their home slab
      cached = slab;
      g = &m.geometry[slab];
      v = m.slab_samples.data() + static_cast<size_t>(slab) * m.samples.per_slab;
    }
    // The texel on the displaced surface: surface_point() with the cell from the table.
    const std::array<double, 5>& w = s.texel_weights[local];
    const std::array<int32_t, 3>& c = s.texel_points[local];
    const double delta = w[2] * v[c[0]].delta + w[3] * v[c[1]].delta + w[4] * v[c[2]].delta;
    const Vec3 p = g->R0 + w[0] * g->e1 + w[1] * g->e2 + delta * (g->dR + w[0] * g->d1 + w[1] * g->d2);
    const double fw = falloff_at(b.falloff, path.distance2(p), inv_r2);
    if (!(fw > 0)) return false;
    const float k = static_cast<float>(pressure * strength * fw);
    if (!(k > (st && st->texel_mark[id] == st->id ? st->texel_k[id] : 0.0f))) return true;
    touch_texel(m, st, id);
    const TexelValues base = st ? st->texel_base[id] : texel_values(m, id);
    if (st) st->texel_k[id] = k;
    if (b.field == BrushField::Colour) {
      m.colour[id] = k * b.colour + (1 - k) * Vec3f(base.r, base.g, base.b);
    } else {
      m.roughness[id] = std::clamp(k * b.value + (1 - k) * base.roughness, 0.0f, 1.0f);
    }
    ++result.changed;
    dirty.mark(T, id);
    return true;
  });
}

bool EditJob::run_flood(SlabModel& m, EditScratch& s, Deadline& d) noexcept {
  bool done = false;
  switch (kernel_) {
    case Kernel::Carve:
    case Kernel::Add:
      done = flood_boolean(m, s, d);
      break;
    case Kernel::PaperCone:
      done = flood_paper_cone(m, s, d);
      break;
    case Kernel::Smooth:
    case Kernel::Flatten:
      done = flood_relax(m, s, d);
      break;
    case Kernel::PaintSample:
      done = flood_paint_samples(m, s, d);
      break;
    case Kernel::PaintTexel:
      done = flood_paint_texels(m, s, d);
      break;
    default:
      done = true;
  }
  if (!done) return false;
  phase_ = Phase::Idle;
  return true;
}

void EditJob::start_normals(EditScratch& s) noexcept {
  result = {};
  phase_ = s.changed_count > 0 ? Phase::Ring : Phase::Idle;
  cursor_ = ring_count_ = 0;
  if (phase_ == Phase::Ring) stamp_ = next_stamp(s);
}

bool EditJob::run_history(SlabModel& m, EditScratch& s, Deadline& d) noexcept {
  DirtyMarker dirty_t{s, m.texels.n * m.texels.n};
  DirtyMarker dirty_s{s, m.samples.n * m.samples.n};
  while (rec_pos_ < rec_end_) {
    if (d.expired(2)) return false;
    UndoRecord& r = history_->at(rec_pos_++);
    if (r.index >= 0) {
      const int32_t id = r.index;
      const SampleValues now = sample_values(m, id);
      m.displacement[id] = r.v[0];
      m.friction_static[id] = r.v[1];
      m.friction_dynamic[id] = r.v[2];
      m.stiffness_scale[id] = r.v[3];
      m.layer_displacement[id] = r.v[4];
      r.v[0] = now.delta, r.v[1] = now.friction_static, r.v[2] = now.friction_dynamic;
      r.v[3] = now.stiffness_scale, r.v[4] = now.layer_displacement;
      if (m.displacement[id] != now.delta) {
        update_positions(m, &id, 1);
        list_changed(m, s, id);
      }
      dirty_s.mark(m.samples, id);
      ++result.changed;
    } else {
      const int32_t id = -(r.index + 1);
      const TexelValues now = texel_values(m, id);
      m.colour[id] = Vec3f(r.v[0], r.v[1], r.v[2]);
      m.roughness[id] = r.v[3];
      r.v[0] = now.r, r.v[1] = now.g, r.v[2] = now.b, r.v[3] = now.roughness;
      dirty_t.mark(m.texels, id);
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

// After displacements changed (positions already refreshed): normals of the changed samples and
// their one-ring (docs/design.md#normals), the slab-major copy, then the force-shading normals of the
// ring and its neighbours; dirty flags of every slab holding a ring sample (its normal changed).
bool EditJob::run_normals(SlabModel& m, EditScratch& s, Deadline& d) noexcept {
  const SampleLayout& L = m.samples;
  constexpr int32_t kChunk = 16;
  if (phase_ == Phase::Ring) {
    DirtyMarker dirty{s, L.n * L.n};
    while (cursor_ < s.changed_count) {
      if (d.expired(kChunk)) return false;
      const int32_t end = std::min(s.changed_count, cursor_ + kChunk);
      for (; cursor_ < end; ++cursor_) {
        const int32_t before = ring_count_;
        ring_count_ = add_with_neighbours(L, s.changed[cursor_], s.sample_stamp, stamp_, s.ring.data(), ring_count_);
        for (int32_t k = before; k < ring_count_; ++k) dirty.mark(L, s.ring[k]);
      }
    }
    phase_ = Phase::Normals;
    cursor_ = 0;
  }
  if (phase_ == Phase::Normals) {
    while (cursor_ < ring_count_) {
      if (d.expired(8 * kChunk)) return false;  // a normal costs several flood visits
      const int32_t n = std::min(kChunk, ring_count_ - cursor_);
      update_normals(m, s.ring.data() + cursor_, static_cast<size_t>(n), s.faces, false);  // also the slab-major copy
      cursor_ += n;
    }
    phase_ = Phase::Wide;
    cursor_ = wide_count_ = 0;
    stamp_ = next_stamp(s);
  }
  if (phase_ == Phase::Wide) {
    // The force-shading normals read the one-ring of normals: the ring and its neighbours change,
    // each listed once (the flood is done, so its queue is free to hold them).
    while (cursor_ < ring_count_) {
      if (d.expired(kChunk)) return false;
      const int32_t end = std::min(ring_count_, cursor_ + kChunk);
      for (; cursor_ < end; ++cursor_)
        wide_count_ = add_with_neighbours(L, s.ring[cursor_], s.sample_stamp, stamp_, s.queue.data(), wide_count_);
    }
    phase_ = Phase::Haptic;
    cursor_ = 0;
  }
  while (cursor_ < wide_count_) {
    if (d.expired(4 * kChunk)) return false;
    const int32_t n = std::min(kChunk * 2, wide_count_ - cursor_);
    update_haptic_normals(m, s.queue.data() + cursor_, static_cast<size_t>(n), false);
    cursor_ += n;
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

}  // namespace hdm::detail
