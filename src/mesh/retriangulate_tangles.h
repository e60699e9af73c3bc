// SPDX-License-Identifier: MIT
#pragma once
// Internal to resolve_open_self_intersections(): a sheet whose triangulation crosses itself in a few
// crumpled spots, repaired where it crumples.

#include <hdm/mesh/triangle_mesh.h>

#include <cstdint>

namespace hdm::mesh::detail {

// A sheet crumpled in a few places (faces folded over their neighbours, overlapping triangles of
// a bad triangulation: the surface is there, only its triangulation crosses itself): each
// crumpled spot, grown by 1 to 6 rings, is cut out and its boundary polygon triangulated again
// (CGAL's triangulate_hole_polyline, no new vertex), with the fewest rings that leave no crossing.
// Accepted only if every removed input vertex lies within @p tolerance [model units] of the new
// faces and every new face (corners, edge midpoints, centroid) within @p tolerance of the input:
// the surface a user sees is unchanged. Returns whether it succeeded; then @p out is the repaired
// mesh and @p removed_faces the faces cut out.
bool retriangulate_tangles(const TriangleMesh& mesh, double tolerance, TriangleMesh& out, int64_t& removed_faces);

}  // namespace hdm::mesh::detail
