// SPDX-License-Identifier: MIT
#pragma once
// Internal, for the bake's translation units: the search for the direction that sees a set of unit
// normals best, shared by the decimation's fold test and the bake's ray directions.

#include <hdm/core/types.h>

#include <vector>

namespace hdm::mesh::detail {

// |x| of the hull's nearest point to the origin at or below which the hull is taken to hold the
// origin (unit normals): no direction sees them all by more than this.
inline constexpr double kHullHoldsOrigin = 1e-6;

// The point @p x of the convex hull of @p points nearest the origin, by Wolfe's algorithm
// (Math. Programming 11, 1976): O(k) per cycle, a few cycles. Returns false when rounding stalls
// it (then @p x is a point of the hull, not the nearest); |x| <= kHullHoldsOrigin: the hull holds
// the origin.
bool nearest_hull_point(const std::vector<Vec3>& points, Vec3& x);

// Improves @p best_value, the smallest dot product of a unit direction with @p normals, towards
// the max-min optimum (the centre of the smallest spherical cap holding them). The optimum is fixed
// by one, two or three active normals: every normal, every pair's bisector and, up to 24 normals,
// every triple's circumcentre are tried. @p best_direction (may be null) gets the direction of an
// improvement. O(k^3) dot products for k <= 24 normals, O(k^2) candidates above, each ruled out
// by the normal that ruled out the last one in most cases (one product, no root): the same result,
// bit for bit, as checking every candidate against every normal in order.
void improve_max_min(const std::vector<Vec3>& normals, double& best_value, Vec3* best_direction);

// Where the origin lies with respect to the convex hull of a star's unit normals.
enum class HullOrigin : int8_t {
  Outside,    // a direction sees every normal by more than kHullHoldsOrigin (x: the hull's nearest point)
  Holds,      // the hull's nearest point is within kHullHoldsOrigin of the origin: no direction sees them all
  Undecided,  // rounding stalled nearest_hull_point()
};

// nearest_hull_point()'s verdict on @p normals, the nearest point in @p x. O(k) per Wolfe cycle.
HullOrigin hull_origin(const std::vector<Vec3>& normals, Vec3& x);

// improve_max_min() for callers that want the figure alone (the decimation's fold test, the
// coarse mesh's untangling and empty-cone smoothing): for up to 24 normals that a direction sees
// by more than kHullHoldsOrigin, the figure of the hull's nearest point to the origin
// (nearest_hull_point(), a few O(k) cycles; the candidates' optimum, to rounding); elsewhere
// improve_max_min()'s. The ray directions keep improve_max_min(): they become the
// model's geometry, and its candidates' directions are exact to the last bit.
void improve_max_min_figure(const std::vector<Vec3>& normals, double& best_value);

// improve_max_min_figure() with hull_origin()'s verdict @p where and point @p x on @p normals
// already known (a caller that decided on it first): the same figure, without a second hull.
void improve_max_min_figure(const std::vector<Vec3>& normals, double& best_value, HullOrigin where, const Vec3& x);

}  // namespace hdm::mesh::detail
