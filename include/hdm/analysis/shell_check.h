// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Independent checks of a slab shell: slab validity, overlap between slabs, undercut columns.

#include <hdm/analysis/exact_mesh_query.h>
#include <hdm/slab/slab_model.h>

#include <cstdint>
#include <utility>
#include <vector>

namespace hdm {

/// @brief Slabs whose Jacobian is not positive everywhere (exact test, design notes §3.7).
/// @note O(#S).
int count_invalid_slabs(const SlabModel& model);

/// @brief Pairs of slabs that share no coarse vertex and whose boundaries intersect.
///
/// Each slab boundary is its inner and outer triangle plus its three side patches, each patch split
/// into two triangles along the diagonal from the lower-id inner corner (exact for planar patches; a
/// bilinear patch deviates from its two triangles by at most its twist). Two triangles intersect
/// iff an edge of one crosses the other (non-coplanar case), so every boundary edge is cast as a
/// segment against an Embree BVH of all boundary triangles.
/// @note Parallel; O(#S log #S).
int64_t count_overlapping_pairs(const SlabModel& model);

/// @brief The pairs counted by count_overlapping_pairs(), (smaller id, larger id), sorted. Uses only
/// the stored corners and slabs of @p model (derived data may be stale).
std::vector<std::pair<int32_t, int32_t>> overlapping_pairs(const SlabModel& model);

/// @brief Sample columns whose projection line crosses the input surface more than once
/// (undercuts a height field cannot hold), cast against @p input.
int64_t count_undercut_columns(const SlabModel& model, const ExactMeshQuery& input);

}  // namespace hdm
