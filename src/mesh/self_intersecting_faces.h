// SPDX-License-Identifier: MIT
#pragma once
// Internal: which faces of a mesh intersect another (self-intersecting faces), shared by count_self_intersections() and
// the crumple repair of resolve_open_self_intersections() (defined in self_intersections.cpp, with CGAL).

#include <hdm/mesh/triangle_mesh.h>

#include <cstdint>
#include <vector>

namespace hdm::mesh::detail {

// Faces of @p mesh in intersecting face pairs, by CGAL's `Polygon_mesh_processing::self_intersections`
// (exact predicates, parallel; sharing a vertex or an edge is not a crossing) on
// to_surface_mesh(@p mesh), whose face k is face k of @p mesh: one flag per face (1: crosses), and
// the number of intersecting face pairs in @p pairs when given. @p mesh is not validated (callers do).
// O(#F log #F).
std::vector<char> self_intersecting_faces(const TriangleMesh& mesh, int64_t* pairs = nullptr);

}  // namespace hdm::mesh::detail
