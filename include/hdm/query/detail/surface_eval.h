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
#include <cstddef>
#include <cstring>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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
  const SlabIds ids = model.samples.slab_ids(slab);
  c.a = ids[c.la], c.b = ids[c.lb], c.d = ids[c.ld];
  return c;
}

/// The three grid points of @p cell in @p slab's block of SlabModel::slab_samples.
inline const SlabSample* slab_block(const SlabModel& model, int slab) noexcept {
  return model.slab_samples.data() + static_cast<size_t>(slab) * model.samples.per_slab;
}

/// δ over @p cell of @p slab, from the slab-major copy (SlabModel::slab_samples): the one
/// interpolation of the displacement that the query, the proxy and the edits share.
inline double interpolated_delta(const SlabModel& model, int slab, const LocalCell& cell) noexcept {
  const SlabSample* v = slab_block(model, slab);
  return cell.wa * v[cell.la].delta + cell.wb * v[cell.lb].delta + cell.wd * v[cell.ld].delta;
}

/// The slab holding @p p and its coordinates @p c, searched from @p cache's slab and α, which are
/// updated when a slab is found (-1: none).
inline int find_cached(const SlabLocator& locator, const Vec3& p, QueryCache& cache, AlphaSolver solver,
                       SlabCoordinates& c) noexcept {
  const int slab = locator.find(p, cache.last_slab, solver, cache.last_alpha, c);
  if (slab >= 0) cache.last_slab = slab, cache.last_alpha = c.alpha;
  return slab;
}

/// Projection-line direction D(w) = Σ wV dV at barycentrics (·, wS, wT) of a slab [model units]:
/// the one formula for every reader, so a direction recomputed later agrees bit for bit.
inline Vec3 ray_at(const SlabGeometry& g, double wS, double wT) noexcept { return g.dR + wS * g.d1 + wT * g.d2; }

/// Surface point P0(w) + δ(w)·D(w) at barycentrics (·, wS, wT) of @p slab [model units]; also
/// returns δ and D(w). Reads the slab-major copy (SlabModel::slab_samples), whose values equal
/// `displacement`, so the result is the same as interpolating `displacement`.
inline Vec3 surface_point(const SlabModel& model, int slab, double wS, double wT, const LocalCell& cell, double& delta,
                          Vec3& ray) noexcept {
  const SlabGeometry& g = model.geometry[slab];
  delta = interpolated_delta(model, slab, cell);
  ray = ray_at(g, wS, wT);
  const Vec3 p0 = g.R0 + wS * g.e1 + wT * g.e2;  // P0(w) = Σ wV V0
  return p0 + delta * ray;
}

/// The snorm16 codes of @p v's normal (@p byte_offset 0) or force-shading normal (6), weighted by
/// @p cell and summed: the interpolated vector in code units (32,767 per unit), not normalised.
/// Every reader normalises it, so the scale is never applied.
inline Vec3f interpolate_codes(const SlabSample* v, const LocalCell& cell, size_t byte_offset) noexcept {
  const auto* a = reinterpret_cast<const char*>(v + cell.la) + byte_offset;
  const auto* b = reinterpret_cast<const char*>(v + cell.lb) + byte_offset;
  const auto* d = reinterpret_cast<const char*>(v + cell.ld) + byte_offset;
#if defined(__SSE2__)
  // Four codes (the three wanted and the next field's first two bytes, unused) as four floats:
  // three conversions per corner instead of nine scalar ones.
  auto codes = [](const char* p) noexcept {
    const __m128i c = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(p));
    return _mm_cvtepi32_ps(_mm_srai_epi32(_mm_unpacklo_epi16(c, c), 16));
  };
  const __m128 sum = _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_set1_ps(float(cell.wa)), codes(a)),
                                           _mm_mul_ps(_mm_set1_ps(float(cell.wb)), codes(b))),
                                _mm_mul_ps(_mm_set1_ps(float(cell.wd)), codes(d)));
  alignas(16) float out[4];
  _mm_store_ps(out, sum);
  return {out[0], out[1], out[2]};
#else
  int16_t ca[3], cb[3], cd[3];
  std::memcpy(ca, a, 6), std::memcpy(cb, b, 6), std::memcpy(cd, d, 6);
  Vec3f sum;
  for (int k = 0; k < 3; ++k)
    sum[k] = float(cell.wa) * float(ca[k]) + float(cell.wb) * float(cb[k]) + float(cell.wd) * float(cd[k]);
  return sum;
#endif
}

/// Interpolated normal over @p cell of @p slab, from the stored snorm16 codes: in code units, not
/// normalised (interpolate_codes()).
inline Vec3f interpolated_normal(const SlabModel& model, int slab, const LocalCell& cell) noexcept {
  return interpolate_codes(slab_block(model, slab), cell, offsetof(SlabSample, n));
}

/// Interpolated force-shading normal over @p cell of @p slab (SlabSample::h): in code units, not
/// normalised (interpolate_codes()).
inline Vec3f interpolated_shading(const SlabModel& model, int slab, const LocalCell& cell) noexcept {
  return interpolate_codes(slab_block(model, slab), cell, offsetof(SlabSample, h));
}

}  // namespace hdm::slab_query::detail
