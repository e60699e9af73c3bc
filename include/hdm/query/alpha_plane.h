// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Point inversion inside one slab: the alpha-plane cubic (paper §3.1, eq. 1-2) and barycentrics in
/// a local frame (docs/design.md#barycentrics; the paper's H·M⁻¹ is singular when an alpha-plane passes
/// through the origin).

#include <hdm/slab/slab_model.h>

namespace hdm {

/// Root finder for the alpha-plane cubic f(α) = 0 on [0, 1].
enum class AlphaSolver {
  Bisection,  ///< the paper's reference: 15 bisection steps, α error about 2⁻¹⁵ (paper §3.1)
  Newton,     ///< bracketed Newton-type iteration (Halley's third-order step on the cubic; falls back to
              ///< bisection when a step leaves the bracket), |Δα| < 1e-12; 2-3 steps from a warm start
};

/// Position of a point inside a slab.
struct SlabCoordinates {
  double alpha = 0;          ///< alpha-plane parameter in [0,1] (0 inner face, 1 outer face)
  Vec3 bary = Vec3::Zero();  ///< barycentrics (wR, wS, wT) on the alpha-triangle, sum 1
};

/// @brief Finds α and the barycentrics of point @p p in slab @p g.
/// @param g       slab constants (make_slab_geometry); the slab must be valid (positive Jacobian).
/// @param p       point [model units, model frame].
/// @param solver  root finder for the cubic.
/// @param[out] c  coordinates, written only when the point is inside.
/// @return true iff @p p lies in the slab (α in [0,1] and every barycentric >= -1e-9); a NaN point
///         is never inside.
/// @note noexcept, no allocation, O(1): cubic coefficients (6 dot products), 2-4 Halley steps or
///       15 bisection steps, one cross-product solve. When the cubic has several roots in [0,1]
///       (possible only in strongly curved slabs), each monotone interval is tried. There is no
///       box test: a caller trying many slabs filters them by their boxes first (SlabLocator
///       does, slab_bounds() gives them), since a point beside the slab but between the planes of
///       its faces is rejected only after the solve.
/// @see Jagnow & Dorsey 2002 §3.1 eq. 1-2; docs/design.md#alpha-plane and #barycentrics.
bool locate_in_slab(const SlabGeometry& g, const Vec3& p, AlphaSolver solver, SlabCoordinates& c) noexcept;

/// @brief locate_in_slab() with a starting guess for α and a hint where to look next.
/// @param g            slab constants, as for locate_in_slab().
/// @param p            point [model units, model frame].
/// @param solver       root finder for the cubic.
/// @param alpha_guess  starting point of the Newton iteration (e.g. the previous tick's α); used
///                     when inside (0,1), otherwise the secant of the bracket is used. Ignored by
///                     Bisection. The root found does not depend on it beyond rounding.
/// @param[out] c       coordinates, written only when the point is inside.
/// @param[out] exit_edge  when @p p is between the slab's inner and outer faces but outside its
///                     triangle: the edge it lies beyond (0: RS, 1: ST, 2: TR, the order of
///                     SlabModel::edge_neighbour); otherwise -1.
/// @note noexcept, no allocation, O(1); same result as locate_in_slab().
bool locate_in_slab(const SlabGeometry& g, const Vec3& p, AlphaSolver solver, double alpha_guess, SlabCoordinates& c,
                    int& exit_edge) noexcept;

/// @brief The point of slab @p g with coordinates (@p bary, @p alpha): X(w, α) = Σ wV·(V0 + α·dV).
/// @note noexcept, O(1); the inverse of locate_in_slab.
Vec3 slab_point(const SlabGeometry& g, const Vec3& bary, double alpha) noexcept;

}  // namespace hdm
