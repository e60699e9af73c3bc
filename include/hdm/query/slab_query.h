// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// The haptic query: from a point to its slab, the displacement under it, the penetration depth,
/// the interpolated normal and the surface contact point (paper §3).

#include <hdm/query/slab_locator.h>

namespace hdm {

/// Answer of a haptic query, model units and model frame.
struct Contact {
  int32_t slab = -1;       ///< slab holding the point, -1 outside the shell (or NaN point)
  SlabCoordinates coords;  ///< α and barycentrics of the point in that slab
  double delta = 0;        ///< displacement δ in [0,1] on the point's projection line
  double depth = 0;  ///< (δ - α)·max(D(w)·n, 0.1|D(w)|), the distance to the surface's tangent plane: > 0 inside
                     ///< material (penetration), < 0 above
  Vec3 surface_point = Vec3::Zero();  ///< point at δ on the point's projection line [model units]
  Vec3 normal = Vec3::UnitZ();        ///< interpolated unit normal of the displaced surface (outward)
  Vec3 ray = Vec3::Zero();            ///< projection-line direction D(w) = P1(w) - P0(w) [model units]
  /// True when the point lies in a slab.
  bool in_shell() const noexcept { return slab >= 0; }
  /// True when the point lies in a slab below the displaced surface (depth > 0).
  bool penetrating() const noexcept { return slab >= 0 && depth > 0; }
  /// The paper's depth (§3.3): (δ - α)·|D(w)|, measured along the projection line [model units].
  double ray_depth() const noexcept { return (delta - coords.alpha) * ray.norm(); }
};

/// Per-thread coherence cache (after OpenVDB's ValueAccessor): the last slab found. Not shared
/// between threads.
struct QueryCache {
  int32_t last_slab = -1;  ///< slab of the previous query, the first one tried next time
  double last_alpha = -1;  ///< α of the previous query: the α solver's starting guess (-1: none)
};

/// @brief Evaluates the displaced surface at slab coordinates @p c of slab @p slab.
/// @param model  slab model with derived data.
/// @param slab   slab id in [0, #S).
/// @param c      coordinates in that slab (α and barycentrics).
/// @param[out] out  delta, depth, surface_point, normal, ray (slab and coords are set too).
/// @note noexcept, no allocation, O(1). The displacement and normal are interpolated over the grid
///       triangle that holds (hx, hy) = (n·wT, n·wS), with the same up/down split the renderer draws
///       (docs/design.md#query).
/// @see Jagnow & Dorsey 2002 §3.2-3.4.
void evaluate_surface(const SlabModel& model, int slab, const SlabCoordinates& c, Contact& out) noexcept;

/// @brief The full haptic query for point @p p.
/// @param model    slab model (derived data built).
/// @param locator  search structure of @p model.
/// @param p        haptic interaction point [model units, model frame].
/// @param cache    the calling thread's coherence cache, updated.
/// @param solver   alpha-plane root finder (Newton by default, Bisection as in the paper).
/// @return the contact; `slab == -1` when @p p is in no slab or not finite (never NaN fields).
/// @note noexcept, no allocation, no locks: safe in the servo loop. Cost: one slab test when the
///       point stays in the cached slab, a few more across slab edges, otherwise one cell of the
///       locator's uniform grid and the slabs it lists (a short list: O(1) for slabs of similar
///       size).
Contact query(const SlabModel& model, const SlabLocator& locator, const Vec3& p, QueryCache& cache,
              AlphaSolver solver = AlphaSolver::Newton) noexcept;

}  // namespace hdm
