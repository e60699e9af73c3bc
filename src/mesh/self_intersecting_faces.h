// SPDX-License-Identifier: MIT
#pragma once
// Internal: which faces of a mesh intersect another (self-intersecting faces), shared by count_self_intersections() and
// the crumple repair of resolve_open_self_intersections() (defined in self_intersecting_faces.cpp, with CGAL).

#include <hdm/mesh/triangle_mesh.h>

#include <cstdint>
#include <utility>
#include <vector>

namespace hdm::mesh::detail {

// The intersecting face pairs of @p mesh, each (a, b) with a <= b, sorted: pairs of faces whose
// triangles meet elsewhere than in the vertices they share by index (the rule of CGAL's
// `Polygon_mesh_processing::self_intersections`, for which faces sharing a vertex or an edge do
// not cross; candidates from Embree's `rtcCollide` over the faces' boxes, decided with CGAL's exact
// predicates), and (f, f) for each face f whose corners are collinear. @p mesh is not validated
// (callers do). O(#F log #F + candidate pairs), on every core (Embree's TBB tasks).
std::vector<std::pair<int32_t, int32_t>> self_intersecting_pairs(const TriangleMesh& mesh);

// Faces of @p mesh in self_intersecting_pairs(): one flag per face (1: crosses), and the number of
// pairs in @p pairs when given.
std::vector<char> self_intersecting_faces(const TriangleMesh& mesh, int64_t* pairs = nullptr);

}  // namespace hdm::mesh::detail
