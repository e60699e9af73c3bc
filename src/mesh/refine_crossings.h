// SPDX-License-Identifier: MIT
#pragma once
// Internal: the crossings of a triangle soup turned into shared edges, with exact constructions.
//
// Why own code: CGAL 5.5's refinement (`experimental::autorefine`) takes closed meshes only,
// refuses triple intersections in one point ("non-handled triple intersection": parts sharing face
// planes) and, on inputs whose rounded intersection points move an input vertex, can crash. Its
// soup version (`autorefine_triangle_soup`) came with CGAL 5.6, after Debian 12's. The steps below
// are the textbook ones (Attene 2014, "Direct repair of self-intersecting meshes"; the same as
// CGAL 5.6's), each done by a CGAL primitive with an exact kernel.

#include <hdm/mesh/triangle_mesh.h>

#include <cstdint>
#include <utility>
#include <vector>

namespace hdm::mesh::detail {

/// What refine_crossings() did.
struct RefineReport {
  int64_t pairs = 0;         ///< intersecting face pairs refined
  int64_t faces_split = 0;   ///< input faces cut into more than one
  int64_t faces_after = 0;   ///< faces of the result
};

// The same surface as @p mesh with every crossing of two faces made an edge of both: for each face
// in @p pairs (ids of @p mesh's faces that intersect, as CGAL's `self_intersections` reports them),
// the exact intersection with each partner (a point, a segment, or a coplanar polygon; CGAL's
// `intersection` with the Epeck kernel) constrains a 2D constrained Delaunay triangulation of the
// face in the plane of its two largest normal coordinates, whose crossings of constraints are
// exact too; the triangles are lifted onto the face's plane exactly and rounded once, so that a
// point computed from two faces is one vertex. Faces not in @p pairs are copied; zero-area faces
// are dropped; each piece keeps its face's orientation. Vertices at equal rounded positions are
// one. The rounding can leave crossings of the order of a double's spacing where pieces meet at a
// grazing angle. Cost: O(#F) plus the exact work per pair (microseconds each).
TriangleMesh refine_crossings(const TriangleMesh& mesh, const std::vector<std::pair<int, int>>& pairs,
                              RefineReport* report = nullptr);

// Patches of @p mesh: faces joined across every edge that exactly two faces use, in opposite
// directions. Where refine_crossings() cut a surface along its crossings, an edge of the
// intersection curves has four or more uses, so a patch lies in one cell of the arrangement on
// each side, and what holds for one of its faces (the winding number in front and behind) holds for
// all. Returns the patch id of each face; @p count is set to the number of patches. O(#F log #F).
std::vector<int32_t> patches_between_crossings(const TriangleMesh& mesh, int32_t& count);

}  // namespace hdm::mesh::detail
