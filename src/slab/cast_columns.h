// SPDX-License-Identifier: MIT
#pragma once
// Internal to the bake: the displacement of each sample, from its column's ray against the input
// (docs/design.md#casting-the-displacements).

#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/slab/bake.h>
#include <hdm/slab/slab_model.h>

#include "ray_frames.h"

#include <cstdint>
#include <vector>

namespace hdm::slab::detail {

// Casts one ray per sample whose home slab has a corner flagged in @p stale (one flag per coarse
// vertex), from the column's outer end inward, and sets its displacement to the outward-facing
// input hit nearest the coarse surface. Per sample, @p missed is set when no outward-facing hit
// was found and @p undercut when the column crosses the input more than once (both sized to the
// sample count). O(columns · log #F), parallel (TBB), in 20 blocks reported to BakeOptions::progress.
void cast_columns(SlabModel& model, const CoarseMesh& coarse, const ExactMeshQuery& input,
                  const std::vector<uint8_t>& stale, std::vector<uint8_t>& missed, std::vector<uint8_t>& undercut,
                  const BakeOptions& o);

// Counts the @p missed columns and flags the corners of their home slabs for a thicker shell:
// @p grow_out where the column's outer end is inside the input (the surface lies beyond it), else
// @p grow_in (both one flag per coarse vertex, set to 0 first). Three long rays per missed column.
int64_t flag_missed_columns(const SlabModel& model, const ExactMeshQuery& input, const std::vector<uint8_t>& missed,
                            std::vector<uint8_t>& grow_in, std::vector<uint8_t>& grow_out);

// Sets each @p missed column's displacement to the point of its line nearest the input (sampled,
// then golden-section search), so the filled surface stays on the input where the shell passes
// beside it. About 50 closest-point queries per missed column, parallel (TBB).
void fill_missed_columns(SlabModel& model, const ExactMeshQuery& input, const std::vector<uint8_t>& missed);

}  // namespace hdm::slab::detail
