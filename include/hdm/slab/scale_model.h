// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// A slab model scaled by a power of two: what undoes hdm::scale_mesh()'s normalisation after a
/// bake (docs/reliability.md#scale).

#include <hdm/slab/slab_model.h>

namespace hdm {

/// @brief Multiplies the model's coarse vertices (inner and outer) and its source diagonal by
/// 2^@p exponent, exactly, and rebuilds its derived data when it had any.
///
/// Displacements are fractions of each projection line and fields are unitless, so nothing else
/// changes: the scaled model is the model of the scaled input.
/// @param model    the model, changed in place [model units].
/// @param exponent power of two; 0 leaves the model as it is (no rebuild).
/// @throws InvalidInput what rebuild_derived() throws on inconsistent stored data.
/// @note O(#C) for the vertices; with derived data, rebuild_derived()'s cost (allocates).
void scale_model(SlabModel& model, int exponent);

}  // namespace hdm
