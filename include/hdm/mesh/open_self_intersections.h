// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Self-intersections of an open mesh resolved: the exposed surface of an input made of sheets
/// that intersect each other. resolve_self_intersections() (self_intersections.h) resolves closed
/// and nearly closed meshes into the boundary of their union and hands every other open mesh to
/// resolve_open_self_intersections().

#include <hdm/mesh/self_intersections.h>
#include <hdm/mesh/triangle_mesh.h>

namespace hdm {

/// @brief The surface a user touches from outside on an open mesh whose parts (connected sheets:
/// a body, limbs pushed into it, each open where it enters another) cross each other.
///
/// Patches that meet along T-junctions are first stitched into one surface (stitch_seams()); when
/// that closes it, it is resolved as a closed mesh (resolve_self_intersections()).
/// Every connected component (faces joined by edges) is one sheet. When a sheet crosses itself
/// (CGAL's `does_self_intersect`), the crossings are taken as a crumpled triangulation of one
/// surface (faces folded over or overlapping their neighbours, as in polygon_mesh.off): the faces
/// of the intersecting face pairs, grown by 1 to 6 vertex rings (the fewest that work; plus the islands they
/// enclose, and every face around a vertex their boundary passes twice), are cut out, and each
/// boundary loop of the cut that is not a loop of the input's own border is triangulated again
/// without new vertices (CGAL's `triangulate_hole_polyline`). The result is kept only if nothing
/// crosses any more, no edge is doubled, every removed input vertex lies within 0.1 % of the
/// diagonal of the new faces and every new face (corners, edge midpoints, centroid) within 0.1 %
/// of the input; else the input is kept. Otherwise sheets whose boxes meet are split along their
/// intersection curves with CGAL's `Polygon_mesh_processing::corefine` (exact intersection points, the same rounded
/// point in both sheets). The curves and the sheets' own boundaries cut every sheet into patches; a patch is interior,
/// and dropped, when the generalized winding number (WindingNumber, of the whole input) just in front of its faces is
/// at least ½ (area-weighted vote of its faces): the front of an interior face is inside material. The kept patches are
/// welded at equal points along the curves. This is the rule `interior_faces()` uses to leave input faces out of the
/// fidelity, so the bake and `hdm check` agree on what the surface is.
///
/// Sheets where "inside" is not defined (an open mask with a cone through its nose: the cone's
/// part behind the mask is in front of nothing) keep both sides of a curve; the result would have
/// an edge with more than two faces, and the input is kept (report->resolved false).
/// @param mesh  edge-manifold triangles, oriented by orient_outward() [model units].
/// @param[out] report  counts (optional); interior_faces counts faces after the split,
///                     retriangulated_faces the input faces cut out of crumpled spots.
/// @return the welded exposed surface (open where the sheets' exposed boundaries are), or
///         @p mesh itself when it is closed, does not cross itself, has a sheet that crosses
///         itself where retriangulation fails, CGAL throws, or the result is not an edge-manifold consistently oriented
///         surface free of crossings.
/// @throws InvalidInput for invalid mesh data.
/// @note O(#F log #F + k) for k intersecting face pairs, single-threaded corefinement; pig.stl (16,848
///       faces, 17 sheets): well under a second.
TriangleMesh resolve_open_self_intersections(const TriangleMesh& mesh, SelfIntersectionReport* report = nullptr);

}  // namespace hdm
