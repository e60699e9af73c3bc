// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Closing T-junction seams: patches tessellated at different rates along a shared curve.

#include <hdm/mesh/triangle_mesh.h>

#include <cstdint>

namespace hdm {

/// What stitch_seams() did.
struct SeamReport {
  int64_t boundary_edges_before = 0;  ///< edges used by one face, vertices welded by position
  int64_t boundary_edges_after = 0;   ///< the same after stitching
  int64_t inserted = 0;               ///< boundary vertices inserted into a facing boundary edge
  int64_t snapped = 0;                ///< boundary vertices merged into a nearly coincident one of another sheet
};

/// @brief Closes seams where patches meet with T-junctions: one side of a curve has a vertex
/// half-way along an edge of the other (subdivided CAD or game patches at different levels:
/// pig.stl's 17 patches, 432 such vertices up to 9% of the edge length off it). Vertices are
/// welded by exact position; a boundary vertex v that lies within a quarter of the length of a
/// boundary edge ab, projects strictly inside it, and is nearer to it than half its distance to
/// a and to b, is inserted into ab: the face of ab is split into a fan through v (at v's own
/// position, so the edge kinks to meet it), and after the weld the two sides share edges.
/// Before that, seams whose vertices nearly coincide (patches written with rounded coordinates:
/// ALSTOM_TEST4.off's six CAD patches) are merged: boundary vertices of different sheets (faces
/// joined by edges) within 5% of the shortest boundary edge at either become one vertex (the
/// lower index's position; nearest pairs first, never two vertices of one sheet), kept only if
/// every edge still has at most two faces. Faces are kept in their order and orientation; no
/// vertex moves farther than that 5%.
/// @param mesh  triangles [model units].
/// @param[out] report  counts (optional).
/// @return the stitched mesh, vertices welded by position (unused ones dropped); @p mesh's
///         triangles welded by position when no vertex is inserted or stitching would make an
///         edge with three or more faces.
/// @throws InvalidInput for invalid mesh data (validate_mesh_data()).
/// @note O(#F log #F + B·k) for B boundary vertices and k boundary edges per grid cell (cells of
///       the median boundary edge length).
TriangleMesh stitch_seams(const TriangleMesh& mesh, SeamReport* report = nullptr);

}  // namespace hdm
