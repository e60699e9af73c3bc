// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Edge flips that remove cap slivers (a vertex lying on the opposite edge) from a coarse mesh.

#include <hdm/mesh/triangle_mesh.h>

#include <cstdint>

namespace hdm {

/// @brief Removes cap slivers by edge flips: a face whose largest angle exceeds 150 degrees and
/// whose smallest angle is below @p min_angle_deg (its apex lies on or near its longest edge, as
/// input vertices left at a T-junction do) has that edge flipped when the flip leaves both faces
/// of the quad with a larger smallest angle than the pair had, turns neither away from the
/// neighbour it splits by more than 30 degrees, and does not make an edge that already exists.
/// Vertices do not move, so the topology (genus, boundaries, components, orientation) is kept.
/// Why: a cap's normal is fixed by a height far below its edges, so the slab over it folds at any
/// shell thickness (triceratops.off: one such face, one invalid slab at every resolution).
/// @param[in,out] mesh  edge-manifold, consistently oriented triangles [model units].
/// @param min_angle_deg  faces with a smaller smallest angle are candidates [degrees], in (0, 60).
/// @return the number of flips.
/// @throws InvalidInput for a @p min_angle_deg outside (0, 60).
/// @note O(#F) per pass, at most 4 passes; deterministic. The cleaning pass of Botsch et al.,
///       "Polygon Mesh Processing" (2010) §6.5, restricted to caps.
int64_t flip_slivers(TriangleMesh& mesh, double min_angle_deg = 2.0);

}  // namespace hdm
