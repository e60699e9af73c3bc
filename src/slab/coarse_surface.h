// SPDX-License-Identifier: MIT
#pragma once
// Internal to the bake: the coarse surface whose triangles become slabs.

#include <hdm/mesh/triangle_mesh.h>

#include "ray_frames.h"

#include <cmath>
#include <vector>

namespace hdm::slab::detail {

// The coarse surface of @p mesh with about @p target triangles: checked edge collapses
// (decimate_mesh(), so it keeps the input's topology and orientation), near-degenerate caps
// flipped (flip_slivers()), then every vertex star made visible from one direction (untangle(),
// then fix_empty_dual_cones() for what that leaves), since a star no direction sees whole has no valid
// slabs at any thickness. O(#F log #F) for the decimation.
// The coarse mesh of about @p target faces (fewer where @p max_cost stops the decimation first,
// more where @p max_edge, per input vertex or empty, keeps it finer); @p last_cost gets the
// decimation's DecimateReport::last_cost.
CoarseMesh coarse_surface(const TriangleMesh& mesh, int target, const std::vector<double>& max_edge = {},
                          double max_cost = INFINITY, double* last_cost = nullptr);

// Moves each vertex whose star is not seen from any direction (its face normals fit in no open
// hemisphere) towards its one-ring's centroid, alone first and then with its ring, keeping a move
// only when the worst star around it is seen better. At most 20 sweeps over the vertices; a star's
// figure is searched again only after a kept move shifts one of its vertices, and a trial move is
// judged up to its first star that is not seen better.
void untangle(CoarseMesh& c);

}  // namespace hdm::slab::detail
