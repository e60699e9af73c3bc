// SPDX-License-Identifier: MIT
#pragma once
// Brute-force distances for tests: written here, not taken from the library, so that a check of the
// library's closest-point queries (Embree, CGAL, the fidelity analyzers) does not share the
// primitive they are built on.

#include <hdm/mesh/triangle_mesh.h>

namespace hdm::test {

/// The closest point of triangle abc to @p p, by its Voronoi regions (Ericson, Real-Time Collision
/// Detection, §5.1.5); a triangle of nonzero area, model units.
Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

/// Distance from @p p to the nearest face of @p m, by trying every face: O(faces). 1e300 when @p m
/// has no face.
double brute_distance(const Vec3& p, const TriangleMesh& m);

}  // namespace hdm::test
