// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Refinement of a triangle mesh that keeps its surface exactly: every face split in four at its
/// edge midpoints. The bake refines a low-poly input this way when its error bound asks for more
/// slabs than the input has triangles (a decimation cannot make more faces than it starts from).

#include <hdm/mesh/triangle_mesh.h>

#include <vector>

namespace hdm {

/// @brief Splits every face of @p mesh into four at the midpoints of its edges (1-to-4 midpoint
/// subdivision with no smoothing: the same surface, point for point, up to the rounding of a
/// midpoint).
/// @param mesh  triangles [model units], vertex ids in range (validate_mesh_data()).
/// @param[in,out] vertex_values  optional, #V of @p mesh: one value per vertex, extended to the
///              new vertices with the smaller value of the edge's two ends (a per-vertex bound
///              such as DecimateOptions::max_edge).
/// @return the split mesh: the input's vertices first, with their ids, then one vertex per
///         undirected edge; face f's four faces at 4f..4f+3 (corner faces, then the middle one),
///         wound as f is.
/// @note O(#F) time, with a hash map over the edges; allocates the result.
/// @see Loop, "Smooth subdivision surfaces based on triangles" (1987), its splitting step alone.
TriangleMesh split_faces(const TriangleMesh& mesh, std::vector<double>* vertex_values = nullptr);

}  // namespace hdm
