// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Self-intersections of an input mesh and their local repair.

#include <hdm/mesh/triangle_mesh.h>

#include <cstdint>

namespace hdm {

/// @brief Pairs of faces of @p mesh that intersect (sharing a vertex or an edge is not an
/// intersection), with CGAL's `Polygon_mesh_processing::self_intersections` (exact predicates,
/// parallel).
/// @param mesh  edge-manifold triangles (as after repair_mesh()).
/// @throws InvalidInput for invalid mesh data (validate_mesh_data()).
/// @note O(#F log #F) (box intersection); about 0.1 s per 100,000 faces on two cores.
int64_t count_self_intersections(const TriangleMesh& mesh);

/// What resolve_self_intersections() did.
struct SelfIntersectionReport {
  int64_t pairs_before = 0;   ///< crossing face pairs of the input
  int64_t pairs_after = 0;    ///< crossing face pairs left (the input's count when it was kept)
  int64_t faces_before = 0;   ///< faces of the input
  int64_t faces_after = 0;    ///< faces of the result
  int64_t buried_faces = 0;   ///< faces (after refinement) dropped as inside the union
  int64_t closed_cracks = 0;  ///< boundary cycles of at most 12 edges left by stitching, triangulated flat
  int64_t split_pinches = 0;  ///< vertices where parts of the union touch at a point, split in one copy per fan
  int64_t seam_vertices = 0;  ///< open input: boundary vertices stitched into a facing boundary edge or merged into a
                              ///< nearly coincident one (stitch_seams())
  int64_t retriangulated_faces = 0;  ///< open input: faces of crumpled spots cut out and triangulated again
                                     ///< (resolve_crossing_sheets())
  bool resolved = false;             ///< the result is the union's boundary; false: the input was kept
};

/// @brief The boundary of the solid a closed mesh that crosses itself bounds: the union of its
/// parts. CGAL's `Polygon_mesh_processing::experimental::autorefine` splits the faces along
/// every intersection curve; a piece stays when the winding number (ExactMeshQuery::inside on the
/// input) is zero just outside it and not zero just inside, so buried pieces go; the pieces are
/// stitched along the curves (`stitch_borders`). Faces away from the crossings are unchanged, so
/// the result is the input's own exposed surface, cut exactly where the parts meet. Where parts
/// touch along an edge or a vertex, stitching leaves cracks of a few edges (man.off: 7 of 3 to 4
/// edges); those of at most 12 edges are triangulated flat (`triangulate_hole`). Where they touch
/// at a vertex (a pinch: its faces form several fans, cow.off), the vertex gets one copy per fan
/// (`duplicate_non_manifold_vertices`), each moved by 1% towards the centroid of its own fan's
/// ring: the copies no longer coincide, so each part gets a shell of its own (two coincident
/// corners leave no room for one) and the result is a manifold surface.
/// @param mesh  edge-manifold triangles, oriented by orient_outward() [model units].
/// @param[out] report  counts (optional).
/// An open mesh that crosses itself goes to resolve_crossing_sheets() (sheets pushed into each
/// other, pig.stl).
/// @return the union's boundary; @p mesh itself when it does not cross itself, or the
///         refinement fails or leaves a surface that is not closed (report->resolved false).
/// @throws InvalidInput for invalid mesh data.
/// @note O((#F + k) log #F) for k crossings; single-threaded refinement.
TriangleMesh resolve_self_intersections(const TriangleMesh& mesh, SelfIntersectionReport* report = nullptr);

}  // namespace hdm
