// SPDX-License-Identifier: MIT
#pragma once
// Internal (namespace hdm::slab_query::detail, not part of the API): the displaced-surface interpolation shared
// by the query (slab_query.cpp), the proxy, the edit kernels and the texture atlas, inline so paint
// can skip the normal. One formula for all, so a texel's position agrees bit for bit with what
// evaluate_surface() reports. All read the slab-major SlabModel::slab_samples (one slab's block
// per query) rather than the sample-indexed `displacement`, which is scattered over
// memory at 10^4+ slabs. Published under detail/ so that no source reaches it by a ../ path.

#include <hdm/query/slab_query.h>
#include <hdm/slab/triangle_grid.h>

#include <algorithm>

namespace hdm::slab_query::detail {

/// Grid triangle under (wS, wT) of a slab with n intervals per edge: its three grid indices
/// (grid::index order within the slab) and their weights (docs/design.md#query: the renderer's
/// up/down split). Depends on the slab's grid only, not on its data.
struct LocalCell {
  int32_t la, lb, ld;
  double wa, wb, wd;
};

/// LocalCell plus the three global sample ids (for sample-indexed fields such as friction).
struct GridCell : LocalCell {
  int32_t a, b, d;
};

inline LocalCell local_cell(int n, double wS, double wT) noexcept {
  double hx = std::max(0.0, n * wT), hy = std::max(0.0, n * wS);
  if (hx + hy > n) {  // rounding beyond the hypotenuse
    const double s = n / (hx + hy);
    hx *= s, hy *= s;
  }
  const int i = std::min(static_cast<int>(hx), n - 1);
  const int j = std::min(static_cast<int>(hy), n - 1 - i);
  double fx = hx - i, fy = hy - j;
  LocalCell c;
  if (fx + fy > 1 && i + j <= n - 2) {  // "down" triangle (i+1,j+1), (i+1,j), (i,j+1)
    c.la = grid::index(n, i + 1, j + 1), c.lb = grid::index(n, i + 1, j), c.ld = grid::index(n, i, j + 1);
    c.wa = fx + fy - 1, c.wb = 1 - fy, c.wd = 1 - fx;
  } else {  // "up" triangle (i,j), (i+1,j), (i,j+1)
    if (fx + fy > 1) {
      const double s = 1 / (fx + fy);
      fx *= s, fy *= s;
    }
    c.la = grid::index(n, i, j), c.lb = grid::index(n, i + 1, j), c.ld = grid::index(n, i, j + 1);
    c.wa = 1 - fx - fy, c.wb = fx, c.wd = fy;
  }
  return c;
}

inline GridCell grid_cell(const SlabModel& model, int slab, double wS, double wT) noexcept {
  GridCell c;
  static_cast<LocalCell&>(c) = local_cell(model.grid_n, wS, wT);
  const int32_t* ids = &model.samples.ids[static_cast<size_t>(slab) * model.samples.per_slab];
  c.a = ids[c.la], c.b = ids[c.lb], c.d = ids[c.ld];
  return c;
}

/// The three grid points of @p cell in @p slab's block of SlabModel::slab_samples.
inline const SlabSample* slab_block(const SlabModel& model, int slab) noexcept {
  return model.slab_samples.data() + static_cast<size_t>(slab) * model.samples.per_slab;
}

/// Surface point P0(w) + δ(w)·D(w) at barycentrics (·, wS, wT) of @p slab [model units]; also
/// returns δ and D(w). Reads the slab-major copy (SlabModel::slab_samples), whose values equal
/// `displacement`, so the result is the same as interpolating `displacement`.
inline Vec3 surface_point(const SlabModel& model, int slab, double wS, double wT, const LocalCell& cell, double& delta,
                          Vec3& ray) noexcept {
  const SlabGeometry& g = model.geometry[slab];
  const SlabSample* v = slab_block(model, slab);
  delta = cell.wa * v[cell.la].delta + cell.wb * v[cell.lb].delta + cell.wd * v[cell.ld].delta;
  ray = g.dR + wS * g.d1 + wT * g.d2;            // D(w) = Σ wV dV
  const Vec3 p0 = g.R0 + wS * g.e1 + wT * g.e2;  // P0(w) = Σ wV V0
  return p0 + delta * ray;
}

/// Interpolated (not normalised) normal over @p cell of @p slab, in float as the normals are stored.
inline Vec3f interpolated_normal(const SlabModel& model, int slab, const LocalCell& cell) noexcept {
  const SlabSample* v = slab_block(model, slab);
  using Map = Eigen::Map<const Vec3f>;
  return static_cast<float>(cell.wa) * Map(v[cell.la].n) + static_cast<float>(cell.wb) * Map(v[cell.lb].n) +
         static_cast<float>(cell.wd) * Map(v[cell.ld].n);
}

}  // namespace hdm::slab_query::detail
