// SPDX-License-Identifier: MIT
#pragma once
// Internal to the bake: how thick the shell may and should be at each coarse vertex
// (docs/design.md#shell-thickness).

#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/slab/bake.h>

#include "ray_frames.h"

#include <vector>

namespace hdm::slab::detail {

// Per coarse vertex, offsets along its ray [model units], inward (in) and outward (out).
struct ShellTargets {
  std::vector<double> cap_in, cap_out;  // never thicker: clearance to other parts, max_thickness
  std::vector<double> min_off;          // the thin shell growth starts from
  std::vector<double> tgt_in, tgt_out;  // wanted: the input's deviation and the edit headroom, within the caps
};

// The offsets each coarse vertex of @p coarse should and may take so that its slabs cover the
// input @p mesh (@p input its BVH): the input's deviation from the coarse surface near the vertex
// and along the slabs' own lines, dilated over the one-ring, plus the edit headroom
// (BakeOptions::headroom, min_thickness); capped at 0.45 of the free distance to the coarse
// surface along the ray and of the clearance to parts beyond the 2-ring, and at max_thickness.
// @p coarse_query is a BVH over @p coarse, @p diag the input's bounding-box diagonal.
// O(#V_input log #F + #F·28 rays), parallel (TBB) but for the caps.
ShellTargets shell_targets(const TriangleMesh& mesh, const ExactMeshQuery& input, const CoarseMesh& coarse,
                           const ExactMeshQuery& coarse_query, const VertexFrame& fr, const BakeOptions& o,
                           double diag);

}  // namespace hdm::slab::detail
