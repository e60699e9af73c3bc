// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Independent checks of a slab shell: slab validity, overlap between slabs, undercut columns.

#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/slab/slab_model.h>

#include <cstdint>
#include <utility>
#include <vector>

namespace hdm {

/// @brief Slabs whose Jacobian is not positive everywhere (exact test, docs/design.md#slab-validity).
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

/// @brief Brings @p pairs, the result of overlapping_pairs() on an earlier state of @p model, up to
/// date after the corners of some slabs moved (the bake's shell iterations move few slabs at a time).
///
/// Pairs with a moved member are dropped and recomputed: every slab whose corner box overlaps a
/// moved slab's box is a candidate, and the boundary edges of the moved slabs and candidates are
/// cast against the boundary triangles of the same set, with the test of count_overlapping_pairs().
/// Pairs of two unmoved slabs are kept as they were (their boundaries did not change).
/// @param model  slabs and stored corners (derived data may be stale); the slab list and the
///               corners of unmoved slabs must be those @p pairs was computed for.
/// @param moved  #S flags: 1 for every slab with a corner that moved since @p pairs was computed.
/// @param[in,out] pairs  sorted (smaller id, larger id) pairs; replaced by the current ones.
/// @throws InvalidInput if @p moved does not have one flag per slab.
/// @note Parallel. O(#S) for the boxes plus O(#moved·#S) box tests and O(k log k) casts for the k
///       moved and candidate slabs; falls back to overlapping_pairs() when more than 1/8 of the
///       slabs moved.
void update_overlapping_pairs(const SlabModel& model, const std::vector<uint8_t>& moved,
                              std::vector<std::pair<int32_t, int32_t>>& pairs);

/// @brief Sample columns whose projection line crosses the input surface more than once
/// (undercuts a height field cannot hold), cast against @p input.
int64_t count_undercut_columns(const SlabModel& model, const ExactMeshQuery& input);

}  // namespace hdm
