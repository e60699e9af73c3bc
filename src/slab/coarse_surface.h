// SPDX-License-Identifier: MIT
#pragma once
// Internal to the bake: the coarse surface whose triangles become slabs.

#include <hdm/mesh/triangle_mesh.h>

#include "ray_frames.h"

namespace hdm::slab::detail {

// The coarse surface of @p mesh with about @p target triangles: checked edge collapses
// (decimate_mesh(), so it keeps the input's topology and orientation), near-degenerate caps
// flipped (flip_slivers()), then every vertex star made visible from one direction (untangle(),
// then fix_empty_dual_cones() for what that leaves), since a star no direction sees whole has no valid
// slabs at any thickness. O(#F log #F) for the decimation.
CoarseMesh coarse_surface(const TriangleMesh& mesh, int target);

// Moves each vertex whose star is not seen from any direction (its face normals fit in no open
// hemisphere) towards its one-ring's centroid, alone first and then with its ring, keeping a move
// only when the worst star around it is seen better. At most 20 sweeps over the vertices.
void untangle(CoarseMesh& c);

}  // namespace hdm::slab::detail
