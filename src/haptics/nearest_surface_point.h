// SPDX-License-Identifier: MIT
#pragma once
// Internal: the point of the displaced surface nearest a point, searched locally over the slabs'
// grid triangles (what the renderer draws), for the sphere proxy.

#include <hdm/slab/slab_model.h>

namespace hdm::haptics_detail {

/// A point of the displaced surface with where it lies and its force-shading normal.
struct SurfacePoint {
  Vec3 point = Vec3::Zero();   ///< on the displaced surface [model units]
  Vec3 normal = Vec3::UnitZ(); ///< force-shading normal there (unit)
  Vec3 facet = Vec3::UnitZ();  ///< normal of the grid triangle that holds it (unit)
  int32_t slab = -1;           ///< slab that holds it
  double wS = 0, wT = 0;       ///< barycentrics in that slab: the centroid of its grid triangle
  int32_t cell_i = 0, cell_j = 0;  ///< its grid cell in that slab (i along wT, j along wS)
  bool down = false;  ///< the cell's "down" triangle (i+1, j+1), (i+1, j), (i, j+1), else its "up" one
  float corner[3] = {1, 0, 0};  ///< its barycentrics in that grid triangle
};

/// The point of the displaced surface nearest @p c, by descent from (wS, wT) in @p slab: windows of
/// 3 × 3 grid cells recentred on the best cell until it stays, then on across each slab edge the
/// best cell touches to the neighbour with a nearer point (at most 6 slabs). A local minimum of
/// the distance: the nearest point of the surface near the start.
/// @pre @p model has derived data; @p slab in [0, #S); (wS, wT) barycentrics in it.
/// @note noexcept, no allocation; 18 triangle tests per window, one window when the start is in
///       the nearest point's cell.
SurfacePoint nearest_surface_point(const SlabModel& model, int slab, double wS, double wT, const Vec3& c) noexcept;

/// @brief How fast the force-shading normal turns at @p p [rad per model unit, as chords]: at each
/// corner of its grid triangle the largest |h_u − h| over the corner's grid neighbours in the slab,
/// over the slab's mean grid spacing at δ = 1/2, interpolated by p's barycentrics. A property of
/// the grid points, so it is continuous within a slab (the neighbours of a point on a slab edge are
/// those in p's slab).
/// @pre @p p from nearest_surface_point() on @p model.
/// @note noexcept, no allocation; at most 12 force-shading normals decoded.
double shading_turn(const SlabModel& model, const SurfacePoint& p) noexcept;

}  // namespace hdm::haptics_detail
