// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Analytic test geometry for the tool scenarios of `hdm feel` (tool_scenarios.h): blocks, slots
/// and steps as unions of grid cubes, whose faces, edges and corners are exact planes and lines.

#include <hdm/mesh/triangle_mesh.h>

#include <functional>

namespace hdm {

/// @brief The boundary of a union of grid cubes of edge @p h: a closed manifold mesh whose faces are
/// the cubes' faces that no other cube covers, two triangles each, counter-clockwise seen from outside.
/// @param nx, ny, nz  cells along x, y, z (>= 1).
/// @param h           the cubes' edge [model units], > 0.
/// @param origin      the corner of cell (0, 0, 0) [model units]; cell (i, j, k) spans origin + h·[i, i+1] × ...
/// @param solid       solid(i, j, k): whether cell (i, j, k) is filled.
/// @return the mesh (vertices shared between faces); no faces when no cell is solid.
/// @throws InvalidInput for a non-positive cell count or a non-positive or non-finite @p h.
/// @note O(nx·ny·nz); allocates. Two solid cells that share only an edge give a non-manifold edge.
TriangleMesh voxel_surface(int nx, int ny, int nz, double h, const Vec3& origin,
                           const std::function<bool(int, int, int)>& solid);

}  // namespace hdm
