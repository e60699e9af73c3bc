// SPDX-License-Identifier: MIT
#pragma once
// Internal to repair_mesh(): hole filling on a CGAL polygon soup. Included by CGAL translation
// units only.

#include <hdm/mesh/repair_mesh.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>

#include <cstddef>
#include <vector>

namespace hdm::mesh::detail {

using Point = CGAL::Exact_predicates_inexact_constructions_kernel::Point_3;
using Soup = std::vector<std::vector<std::size_t>>;
using SurfaceMesh = CGAL::Surface_mesh<Point>;

// Fills the chosen boundary cycles of a consistently oriented, vertex-manifold soup (@p points,
// @p polygons; copies of a position are merged again): small holes (RepairOptions::max_hole_edges,
// max_hole_size of @p diag) and every hole of a component closed but for holes. Each fill is a
// minimal-area triangulation (Liepa 2003), refined and faired, kept only where it crosses no other
// face; a cycle no fill leaves uncrossed stays open. Sets the report's open_boundaries,
// filled_holes, added_faces and split_vertices. Returns the mesh.
SurfaceMesh fill_holes(std::vector<Point>& points, Soup& polygons, double diag, const RepairOptions& options,
                       RepairReport& rep);

}  // namespace hdm::mesh::detail
