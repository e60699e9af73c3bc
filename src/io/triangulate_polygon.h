// SPDX-License-Identifier: MIT
#pragma once
// Internal to hdm::io: one polygon of a mesh file -> triangles on its own corners, keeping the
// file's winding (triangulate_polygon.cpp, the one translation unit of hdm::io that includes CGAL).

#include <hdm/mesh/triangle_mesh.h>

#include <array>
#include <cstdint>
#include <vector>

namespace hdm::io::detail {

/// What triangulate_polygon() made of a polygon.
enum class PolygonTriangles {
  Done,           ///< its triangles were appended
  CrossesItself,  ///< its outline crosses itself in its best-fit plane: nothing appended
};

/// @brief Appends triangles covering the polygon @p ids [0, k) of @p positions to @p out, each
/// wound as the polygon is (its normal along the polygon's Newell normal).
///
/// The polygon is projected into its best-fit plane (the plane through its centroid normal to its
/// Newell normal). A convex polygon (every turn to the same side, one turn around in all) is fanned
/// from its first corner; a four-corner polygon with one reflex corner is split at that corner;
/// any other polygon is triangulated with CGAL's 2D constrained Delaunay triangulation of its
/// edges, keeping the faces of odd nesting (inside an odd number of the outline's loops; an edge
/// the outline runs along twice, such as the bridge of a polygon with a hole written as one
/// outline, bounds nothing). Corners at one point of the plane become one vertex, the first
/// corner's. A polygon with no plane (its Newell normal is zero or not finite: its
/// corners are collinear, or coordinates overflow) is fanned: its triangles have no area either
/// way, and repair removes them; one whose Newell normal is zero although its corners span an
/// area (a symmetric bowtie) crosses itself.
/// @param positions  the file's vertices [file units], finite.
/// @param ids        k >= 3 corner ids into positions, no two consecutive ones equal (cyclically).
/// @param out        triangles of corner ids, appended.
/// @param plane      scratch for the corners' plane coordinates, reused between calls.
/// @return Done, or CrossesItself when two of its edges cross or overlap in the plane (nothing
///         appended): its triangles would need corners where they cross, which the file does not
///         have.
/// @note O(k) for a convex polygon; otherwise O(k log k) expected, O(k²) at worst (each edge
///       inserted into the triangulation costs the triangles it crosses); allocates.
/// @see Newell's method (Sutherland, Sproull, Schumacker, "A characterization of ten
///      hidden-surface algorithms", 1974); CGAL's 2D triangulations (Yvinec),
///      Constrained_Delaunay_triangulation_2.
PolygonTriangles triangulate_polygon(const std::vector<Vec3>& positions, const int32_t* ids, size_t k,
                                     std::vector<Tri>& out, std::vector<std::array<double, 2>>& plane);

}  // namespace hdm::io::detail
