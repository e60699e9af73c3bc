// SPDX-License-Identifier: MIT
#pragma once
// Internal: the displaced-surface interpolation shared by the query (slab_query.cpp) and the
// paint tool (edit_tools.cpp), inline so paint can skip the normal. One formula for both, so a
// texel's position agrees bit for bit with what evaluate_surface() reports.

#include <hdm/query/slab_query.h>
#include <hdm/slab/triangle_grid.h>

#include <algorithm>

namespace hdm::detail {

/// Grid triangle under (wS, wT) of @p slab: its three global sample ids and their weights
/// (design notes §4.1: the renderer's up/down split).
struct GridCell {
  int32_t a, b, d;
  double wa, wb, wd;
};

inline GridCell grid_cell(const SlabModel& model, int slab, double wS, double wT) noexcept {
  const int n = model.grid_n;
  double hx = std::max(0.0, n * wT), hy = std::max(0.0, n * wS);
  if (hx + hy > n) {  // rounding beyond the hypotenuse
    const double s = n / (hx + hy);
    hx *= s, hy *= s;
  }
  const int i = std::min(static_cast<int>(hx), n - 1);
  const int j = std::min(static_cast<int>(hy), n - 1 - i);
  double fx = hx - i, fy = hy - j;
  const int32_t* ids = &model.samples.ids[static_cast<size_t>(slab) * model.samples.per_slab];
  GridCell c;
  if (fx + fy > 1 && i + j <= n - 2) {  // "down" triangle (i+1,j+1), (i+1,j), (i,j+1)
    c.a = ids[grid::index(n, i + 1, j + 1)], c.b = ids[grid::index(n, i + 1, j)], c.d = ids[grid::index(n, i, j + 1)];
    c.wa = fx + fy - 1, c.wb = 1 - fy, c.wd = 1 - fx;
  } else {  // "up" triangle (i,j), (i+1,j), (i,j+1)
    if (fx + fy > 1) {
      const double s = 1 / (fx + fy);
      fx *= s, fy *= s;
    }
    c.a = ids[grid::index(n, i, j)], c.b = ids[grid::index(n, i + 1, j)], c.d = ids[grid::index(n, i, j + 1)];
    c.wa = 1 - fx - fy, c.wb = fx, c.wd = fy;
  }
  return c;
}

/// Surface point P0(w) + δ(w)·D(w) at barycentrics (·, wS, wT) of @p slab [model units]; also
/// returns δ and D(w) when asked.
inline Vec3 surface_point(const SlabModel& model, int slab, double wS, double wT, const GridCell& cell,
                          double& delta, Vec3& ray) noexcept {
  const SlabGeometry& g = model.geometry[slab];
  const float* disp = model.displacement.data();
  delta = cell.wa * disp[cell.a] + cell.wb * disp[cell.b] + cell.wd * disp[cell.d];
  ray = g.dR + wS * g.d1 + wT * g.d2;         // D(w) = Σ wV dV
  const Vec3 p0 = g.R0 + wS * g.e1 + wT * g.e2;  // P0(w) = Σ wV V0
  return p0 + delta * ray;
}

}  // namespace hdm::detail
