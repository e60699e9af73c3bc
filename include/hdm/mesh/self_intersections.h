// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Self-intersections of an input mesh and their local repair.

#include <hdm/mesh/triangle_mesh.h>

#include <cstdint>

namespace hdm {

/// @brief Pairs of faces of @p mesh that intersect, and faces whose corners are collinear (each
/// counted once). Faces that share vertices (by index) intersect only where they meet elsewhere:
/// two with an edge in common when they are coplanar and on the same side of it (a fold), two with
/// a vertex in common when the edge opposite it in either meets the other. This is the rule of
/// CGAL's `Polygon_mesh_processing::self_intersections`, applied to the faces as given: where
/// several fans meet at one vertex (a pinch), their faces touching there do not count.
///
/// Candidate pairs come from Embree's collision of the faces' boxes with themselves
/// (`rtcCollide`, a BVH against itself, in parallel), each decided with CGAL's exact predicates; no
/// halfedge mesh is built.
/// @param mesh  triangles [model units]; any connectivity.
/// @throws InvalidInput for invalid mesh data (validate_mesh_data()); NumericalError when Embree
///         cannot start.
/// @note O(#F log #F + candidate pairs); 13 s for 12.6 M faces on two cores.
int64_t count_self_intersections(const TriangleMesh& mesh);

/// What resolve_self_intersections() did.
struct SelfIntersectionReport {
  int64_t pairs_before = 0;    ///< self-intersecting face pairs of the input
  int64_t pairs_after = 0;     ///< self-intersecting face pairs left (the input's count when it was kept)
  int64_t faces_before = 0;    ///< faces of the input
  int64_t faces_after = 0;     ///< faces of the result
  int64_t interior_faces = 0;  ///< faces (after refinement) dropped as inside the union or of zero area
  int64_t closed_cracks = 0;   ///< boundary cycles of at most 12 edges left by stitching, triangulated flat
  int64_t filled_faces = 0;    ///< faces added to fill the holes of a nearly closed input (they stay)
  int64_t split_pinches = 0;   ///< vertices where parts of the union touch at a point, split in one copy per fan
  int64_t seam_vertices = 0;   ///< open input: boundary vertices stitched into a facing boundary edge or merged into a
                               ///< nearly coincident one (stitch_seams())
  int64_t retriangulated_faces = 0;  ///< open input: faces of crumpled spots cut out and triangulated again
                                     ///< (resolve_open_self_intersections())
  bool resolved = false;             ///< the result is the union's boundary; false: the input was kept
};

/// @brief The solid an open mesh nearly bounds: its holes filled (`triangulate_and_refine_hole`,
/// Liepa 2003), when it is nearly closed: holes of at most 256 edges whose fans about their
/// centroids cover less than a quarter of its area (a bust with an open base,
/// mannequin-devil.off), the rule resolve_self_intersections() fills open inputs by. For a mesh
/// that crosses itself, `hdm bake` and `hdm check` both measure against this closed surface.
/// @param mesh  edge-manifold triangles [model units].
/// @return the filled mesh (the input's faces first, unchanged, then the fills); an empty mesh
///         when @p mesh is closed, not nearly closed, or the fills leave it open.
/// @throws InvalidInput for invalid mesh data.
/// @note O(#F) plus O(h³) per hole of h edges.
TriangleMesh fill_nearly_closed(const TriangleMesh& mesh);

/// @brief The boundary of the solid a closed mesh that crosses itself bounds: the union of its
/// parts. The faces are split along every intersection curve with exact constructions (CGAL's
/// triangle-triangle `intersection` and a constrained Delaunay triangulation per face on the
/// Epeck kernel, each point rounded once, so a point reached from two faces is one vertex;
/// Attene 2014). The split faces form patches between the curves; each patch is classified
/// at its largest face. It stays when the generalized winding number of the input
/// (WindingNumber, Jacobson et al. 2013) crosses 1/2 through it, 10⁻⁹ of the diagonal off its
/// centroid, and it is turned so that the material is behind it. So pieces inside one, two or more
/// other parts go (ray parity would keep those inside an even number), and so do faces where
/// parts touch face to face. The pieces are joined as a
/// polygon soup (coincident points merged, `repair_polygon_soup`) and stitched along the curves
/// (`stitch_borders`). Faces away from the crossings are unchanged, so the result is the input's
/// own exposed surface, cut exactly where the parts meet. Where parts touch along an edge or a
/// vertex, stitching leaves cracks of a few edges (man.off: 7 of 3 to 4 edges); those of at most
/// 12 edges, or at most 64 within 1% of the diagonal, are triangulated flat (`triangulate_hole`).
/// Where they touch at a vertex (a pinch: its faces form several fans, cow.off), the vertex gets
/// one copy per fan (`duplicate_non_manifold_vertices`), each moved by 1% towards the centroid of
/// its own fan's ring: the copies no longer coincide, so each part gets a shell of its own (two
/// coincident corners leave no room for one) and the result is a manifold surface. Faces that
/// still meet (parts touching along an edge; pieces crossing by a double's spacing after the
/// rounding), up to 256 pairs, are removed and their holes refilled by CGAL's
/// `experimental::remove_self_intersections` when that leaves a closed surface with fewer pairs.
/// Inputs with more than 20,000 crossing pairs are kept as they are (the exact work costs about
/// 0.5 ms per pair where crossings pile up on collinear points).
///
/// An open mesh that crosses itself is resolved the same way when it is nearly closed (holes of
/// at most 256 edges whose fans about their centroids cover less than a quarter of its area, as
/// orient_outward() counts nearly closed: a bust with an open base, mannequin-devil.off): its
/// holes are filled (`triangulate_and_refine_hole`, Liepa 2003) and stay filled, so the result is
/// closed (report->filled_faces). Other open meshes, and nearly closed ones this fails on, go to
/// resolve_open_self_intersections() (sheets pushed into each other, pig.stl).
/// @param mesh  edge-manifold triangles, oriented by orient_outward() [model units].
/// @param[out] report  counts (optional).
/// @return the union's boundary; @p mesh itself when it does not cross itself, or the
///         refinement fails or leaves a surface that is not closed (report->resolved false).
/// @throws InvalidInput for invalid mesh data.
/// @note O((#F + k) log #F) for k crossings, plus O(h³) per filled hole of h edges;
///       single-threaded refinement (mannequin-devil.off: 1,643 pairs in 0.26 s).
TriangleMesh resolve_self_intersections(const TriangleMesh& mesh, SelfIntersectionReport* report = nullptr);

}  // namespace hdm
