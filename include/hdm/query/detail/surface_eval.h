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

/// The snorm16 codes of the normals (SlabSample::n) of @p v's grid points under @p cell, weighted
/// by the cell and summed: the interpolated vector in code units (32,767 per unit), not normalised.
/// Every reader normalises it, so the scale is never applied.
inline Vec3f interpolate_codes(const SlabSample* v, const LocalCell& cell) noexcept {
  static_assert(offsetof(SlabSample, n) == 0 && offsetof(SlabSample, delta) == 6, "the normal, then δ: 8 bytes");
  const auto* a = reinterpret_cast<const char*>(v + cell.la);
  const auto* b = reinterpret_cast<const char*>(v + cell.lb);
  const auto* d = reinterpret_cast<const char*>(v + cell.ld);
#if defined(__SSE2__)
  // Four codes (the normal's three and δ's, unused) as four floats:
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
  return interpolate_codes(slab_block(model, slab), cell);
}

/// Interpolated force-shading normal over @p cell of @p slab (SlabSample::h): each corner's
/// octahedral code decoded and normalised (so the weights are the cell's, as for the normal), then
/// weighted and summed; not normalised. A corner without a normal (the code {-128, -128}) adds
/// nothing.
inline Vec3f interpolated_shading(const SlabModel& model, int slab, const LocalCell& cell) noexcept {
  const SlabSample* v = slab_block(model, slab);
#if defined(__SSE2__)
  // The three corners in three lanes: one unfold, one square root and one division for all.
  auto code = [](const SlabSample& p) noexcept {
    uint16_t c;
    std::memcpy(&c, p.h, 2);
    return int(c);
  };
  const __m128i c = _mm_setr_epi32(code(v[cell.la]), code(v[cell.lb]), code(v[cell.ld]), 0x8080);
  const __m128 sign = _mm_set1_ps(-0.0f), zero = _mm_setzero_ps();
  const __m128 x = _mm_cvtepi32_ps(_mm_srai_epi32(_mm_slli_epi32(c, 24), 24));  // h[0], sign-extended
  const __m128 y = _mm_cvtepi32_ps(_mm_srai_epi32(_mm_slli_epi32(c, 16), 24));  // h[1]
  const __m128 ax = _mm_andnot_ps(sign, x), ay = _mm_andnot_ps(sign, y);
  const __m128 z = _mm_sub_ps(_mm_sub_ps(_mm_set1_ps(127.0f), ax), ay);
  const __m128 t = _mm_max_ps(_mm_sub_ps(zero, z), zero);  // the lower half's unfold
  const __m128 ux = _mm_or_ps(_mm_sub_ps(ax, t), _mm_and_ps(sign, x));
  const __m128 uy = _mm_or_ps(_mm_sub_ps(ay, t), _mm_and_ps(sign, y));
  const __m128 len2 = _mm_add_ps(_mm_add_ps(_mm_mul_ps(ux, ux), _mm_mul_ps(uy, uy)), _mm_mul_ps(z, z));
  const __m128 none = _mm_castsi128_ps(_mm_cmpeq_epi32(c, _mm_set1_epi32(0x8080)));
  const __m128 w = _mm_div_ps(_mm_andnot_ps(none, _mm_setr_ps(float(cell.wa), float(cell.wb), float(cell.wd), 0.0f)),
                              _mm_sqrt_ps(len2));
  auto sum = [](__m128 p) noexcept {
    const __m128 s = _mm_add_ps(p, _mm_movehl_ps(p, p));
    return _mm_cvtss_f32(_mm_add_ss(s, _mm_shuffle_ps(s, s, 1)));
  };
  return {sum(_mm_mul_ps(w, ux)), sum(_mm_mul_ps(w, uy)), sum(_mm_mul_ps(w, z))};
#else
  return float(cell.wa) * v[cell.la].shading() + float(cell.wb) * v[cell.lb].shading() +
         float(cell.wd) * v[cell.ld].shading();
#endif
}

}  // namespace hdm::slab_query::detail
