// SPDX-License-Identifier: MIT
// The single-stamp edit tools (from commit 73d4ce2, src/edit/edit_tools.cpp: carve,
// add_material, paint, single stamps, flood fill, normals of the changed ring), kept verbatim in
// the benchmark so that bench_edit compares the current kernels with them in the same run on the
// same machine (a shared, noisy one). Not part of the library.
#include "legacy_edit_tools.h"

#include <hdm/slab/triangle_grid.h>

#include <hdm/query/detail/surface_eval.h>

#include <algorithm>
#include <cmath>

namespace hdm::bench::legacy {

namespace {

uint32_t next_stamp(EditScratch& s, std::vector<uint32_t>& marks) noexcept {
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
  Vec3 i0, i1, i2, o0, o1, o2;
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

// Marks the slabs of the grid triangles incident to a sample (or texel). Consecutive incident
// triangles mostly share a slab, so the slab range is remembered instead of dividing each time.
struct DirtyMarker {
  std::vector<uint8_t>& dirty;
  int32_t per_slab;
  int32_t lo = 0, hi = 0;  // triangle range [lo, hi) of the last slab marked
  void mark(const SampleLayout& L, int32_t s) noexcept {
    if (s >= L.first_interior) {  // interior: held by its home slab only
      dirty[L.home_slab[s]] = 1;
      return;
    }
    for (int32_t e = L.triangle_offsets[s]; e < L.triangle_offsets[s + 1]; ++e) {
      const int32_t tri = L.incident_triangles[e];
      if (tri >= lo && tri < hi) continue;
      const int32_t slab = tri / per_slab;
      dirty[slab] = 1;
      lo = slab * per_slab, hi = lo + per_slab;
    }
  }
};

// Shared flood fill over the sample graph: `visit(s)` returns true to continue into s's neighbours
// and records changes itself.
template <class Visit>
int32_t flood(const SampleLayout& L, std::vector<uint32_t>& marks, uint32_t stamp, std::vector<int32_t>& queue,
              const int32_t seeds[3], Visit visit) noexcept {
  size_t head = 0, tail = 0;
  for (int k = 0; k < 3; ++k)
    if (marks[seeds[k]] != stamp) marks[seeds[k]] = stamp, queue[tail++] = seeds[k];
  while (head < tail) {
    const int32_t s = queue[head++];
    if (!visit(s)) continue;
    // Branch-free push: whether a neighbour was already queued is a coin flip inside a patch, and
    // a mispredicted branch per neighbour cost more than the unconditional stores.
    for (int32_t e = L.neighbour_offsets[s]; e < L.neighbour_offsets[s + 1]; ++e) {
      const int32_t t = L.neighbours[e];
      const bool fresh = marks[t] != stamp;
      marks[t] = stamp;
      queue[tail] = t;
      tail += fresh;
    }
  }
  return static_cast<int32_t>(tail);
}

// Appends sample c and its grid neighbours not yet stamped with @p stamp to out[count...], stamping
// them; returns the new count. Branch-free, as in flood() (out has room for one more).
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

// After displacements changed (positions already refreshed by the visit): normals of the changed
// samples and their one-ring (docs/design.md#normals), dirty flags of every slab that holds a changed
// sample.
void finish_geometry_edit(SlabModel& m, EditScratch& s, int32_t changed) noexcept {
  if (changed == 0) return;
  const uint32_t stamp = next_stamp(s, s.sample_stamp);
  int32_t ring = 0;
  const SampleLayout& L = m.samples;
  DirtyMarker dirty{s.dirty_slabs, L.n * L.n};
  for (int32_t k = 0; k < changed; ++k) {
    ring = add_with_neighbours(L, s.changed[k], s.sample_stamp, stamp, s.ring.data(), ring);
    dirty.mark(L, s.changed[k]);
  }
  update_normals(m, s.ring.data(), ring, s.faces, false);  // also refreshes the slab-major copy
  // The force-shading normals read the one-ring of normals: the ring and its neighbours change,
  // each listed once (the flood fill is done, so its queue is free to hold them).
  const uint32_t again = next_stamp(s, s.sample_stamp);
  int32_t wide = 0;
  for (int32_t k = 0; k < ring; ++k)
    wide = add_with_neighbours(L, s.ring[k], s.sample_stamp, again, s.queue.data(), wide);
  update_haptic_normals(m, s.queue.data(), static_cast<size_t>(wide), false);
}

// Flood fill over the displacement samples, seeded with the grid cell under the contact.
template <class Visit>
int32_t flood_samples(SlabModel& m, EditScratch& s, const Contact& contact, Visit visit) noexcept {
  int32_t seeds[3];
  cell_points(m.samples, contact.slab, contact.coords.bary, seeds);
  const uint32_t stamp = next_stamp(s, s.sample_stamp);
  return flood(m.samples, s.sample_stamp, stamp, s.queue, seeds, visit);
}

}  // namespace

EditResult carve(SlabModel& m, EditScratch& s, const Contact& contact, const Vec3& hip, double radius,
                 double resilience) noexcept {
  EditResult r;
  if (!contact.in_shell() || !(radius > 0) || !hip.allFinite()) return r;
  const Vec3 centre = hip + contact.normal * (radius + std::max(resilience, 0.0));
  const double r2 = radius * radius;
  LineEvaluator line_of{m, s.grid_weights.data()};
  r.visited = flood_samples(m, s, contact, [&](int32_t id) {
    Vec3 p0, p1;
    line_of(id, p0, p1);
    // Line P(t) = p0 + t·L against the sphere: a t² + b t + c = 0 (docs/design.md#carving).
    const Vec3 L = p1 - p0, w = p0 - centre;
    const double a = L.squaredNorm(), b = 2 * L.dot(w), c = w.squaredNorm() - r2;
    const double disc = b * b - 4 * a * c;
    if (disc < 0 || a <= 0) return false;
    const double sq = std::sqrt(disc), t_in = (-b - sq) / (2 * a), t_out = (-b + sq) / (2 * a);
    if (t_out < 0 || t_in > 1) return false;  // the line meets the sphere outside the slab
    const double delta = m.displacement[id];
    if (t_in < delta && delta <= t_out) {
      const float lowered = static_cast<float>(std::max(t_in, 0.0));
      if (lowered < m.displacement[id]) {
        m.displacement[id] = lowered;
        m.positions[id] = (p0 + static_cast<double>(lowered) * L).cast<float>();  // = sample_position()
        s.changed[r.changed++] = id;
      }
    }
    return true;
  });
  finish_geometry_edit(m, s, r.changed);
  return r;
}

EditResult add_material(SlabModel& m, EditScratch& s, const Contact& contact, double radius, double height) noexcept {
  EditResult r;
  if (!contact.in_shell() || !(radius > 0) || !(height > 0)) return r;
  const Vec3 centre = contact.surface_point;
  LineEvaluator line_of{m, s.grid_weights.data()};
  r.visited = flood_samples(m, s, contact, [&](int32_t id) {
    Vec3 p0, p1;
    line_of(id, p0, p1);
    const double len = (p1 - p0).norm();
    const double d = (p0 + double(m.displacement[id]) * (p1 - p0) - centre).norm();
    if (d >= radius || len <= 0) return false;
    const float raised = static_cast<float>(std::min(1.0, m.displacement[id] + height * (1 - d / radius) / len));
    if (raised > m.displacement[id]) {
      m.displacement[id] = raised;
      m.positions[id] = (p0 + static_cast<double>(raised) * (p1 - p0)).cast<float>();  // = sample_position()
      s.changed[r.changed++] = id;
    }
    return true;
  });
  finish_geometry_edit(m, s, r.changed);
  return r;
}

EditResult paint(SlabModel& m, EditScratch& s, const Contact& contact, double radius, const Vec3f& colour,
                 double pressure) noexcept {
  EditResult r;
  pressure = std::clamp(pressure, 0.0, 1.0);
  if (!contact.in_shell() || !(radius > 0) || !(pressure > 0)) return r;
  const Vec3 centre = contact.surface_point;
  const SampleLayout& T = m.texels;
  int32_t seeds[3];
  cell_points(T, contact.slab, contact.coords.bary, seeds);
  const uint32_t stamp = next_stamp(s, s.texel_stamp);
  DirtyMarker dirty{s.dirty_slabs, T.n * T.n};
  const double N = T.n;
  r.visited = flood(T, s.texel_stamp, stamp, s.queue, seeds, [&](int32_t id) {
    const int local = T.home_index[id], slab = T.home_slab[id];
    // The texel on the displaced surface: evaluate_surface()'s point, without its normal.
    const Vec3 bary(1 - (T.point_i[local] + T.point_j[local]) / N, T.point_j[local] / N, T.point_i[local] / N);
    const detail::LocalCell cell = detail::local_cell(m.grid_n, bary[1], bary[2]);
    double delta;
    Vec3 ray;
    const double d = (detail::surface_point(m, slab, bary[1], bary[2], cell, delta, ray) - centre).norm();
    if (d >= radius) return false;
    const float k = static_cast<float>(pressure * (1 - d / radius));
    m.colour[id] = k * colour + (1 - k) * m.colour[id];
    ++r.changed;
    dirty.mark(T, id);
    return true;
  });
  return r;
}

}  // namespace hdm::bench::legacy
