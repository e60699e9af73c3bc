// SPDX-License-Identifier: MIT
#pragma once
// Internal: the one rule for a *nearly closed* open surface (a bust open at its base, a scan with a
// cut neck), shared by orient_outward() (oriented by its capped volume) and the CGAL translation
// unit self_intersections.cpp (its holes filled for good). Each caller finds the boundary loops
// its own way (a TriangleMesh per component; a CGAL::Surface_mesh as a whole); the rule is the
// same: cap every loop with a fan about its centroid, and compare the fans' area with the surface's.

#include <hdm/core/types.h>

namespace hdm::mesh::detail {

// Largest area of the caps of an open surface's boundary loops, as a fraction of its area, for
// which it counts as nearly closed: a quarter, so a head with an open base or a body with a cut
// neck is a solid, while a terrain, a mask or a thin panel (caps about as large as the surface
// itself) stays a sheet.
inline constexpr double kNearlyClosedCapFraction = 0.25;

// Area of the cap triangle over the boundary edge (a, b) with apex c, the centroid of its loop
// (the fan about the centroid caps the loop). O(1).
inline double cap_triangle_area(const Vec3& a, const Vec3& b, const Vec3& c) {
  return 0.5 * (a - c).cross(b - c).norm();
}

// Whether caps of total area @p cap_area close a surface of area @p area (both in model units²)
// well enough for it to count as nearly closed; false when either is NaN. O(1).
inline bool nearly_closed(double cap_area, double area) { return cap_area < kNearlyClosedCapFraction * area; }

}  // namespace hdm::mesh::detail
