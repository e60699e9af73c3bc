// SPDX-License-Identifier: MIT
#pragma once
// Internal: the render layer's precondition check on a SlabModel.

namespace hdm {
struct SlabModel;
}

namespace hdm::render_detail {

/// Throws InvalidInput unless @p model has slabs and derived data that match its stored data
/// (sizes only; O(1)). Everything the renderer indexes is covered, so a stale model fails here
/// instead of reading out of bounds.
void check_renderable(const SlabModel& model);

}  // namespace hdm::render_detail
