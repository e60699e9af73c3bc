// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// What a slab model holds in memory, by kind of data: the figure behind "bytes per displacement
/// sample" and "bytes per colour texel", every field and cache counted.

#include <hdm/slab/slab_model.h>

#include <cstdint>

namespace hdm {

/// Heap bytes of a SlabModel's arrays, by group. Each array counts its capacity (what it holds
/// allocated), so the sum is the model's share of the heap, allocator overhead aside.
struct ModelMemory {
  /// Stored per sample: displacement, and friction μs and μd, stiffness, layer top and hardness
  /// where they are not one value everywhere (SampleField: a uniform field takes no array).
  int64_t sample_fields = 0;
  int64_t texel_fields = 0;   ///< stored per texel: colour (8-bit sRGB, 3 B) and roughness (unorm8, 1 B)
  int64_t coarse = 0;         ///< stored per coarse vertex and slab: inner, outer, slabs
  int64_t sample_layout = 0;  ///< derived: the samples' SampleLayout (ids, neighbours, homes, shared slots)
  int64_t texel_layout = 0;   ///< derived: the texels' SampleLayout
  /// Derived cache of the query, the proxy and the edits: the slab-major copy `slab_samples`
  /// (displacement, normal and force-shading normal per slot). Surface points are not cached.
  int64_t caches = 0;
  int64_t slab_constants = 0;  ///< derived per slab: geometry, edge neighbours
  /// Bytes the fields held as one value (SampleField::uniform()) would take as arrays: what
  /// materialise_fields(), which every editor calls, adds to total(). Not part of total().
  int64_t uniform_fields = 0;
  int64_t samples = 0;  ///< distinct displacement samples (SampleLayout::count)
  int64_t texels = 0;   ///< distinct colour texels

  /// Every group summed [bytes].
  int64_t total() const noexcept {
    return sample_fields + texel_fields + coarse + sample_layout + texel_layout + caches + slab_constants;
  }
  /// Bytes per colour texel: the texel fields and layout over the texels (0 without texels).
  double per_texel() const noexcept { return texels > 0 ? double(texel_fields + texel_layout) / double(texels) : 0; }
  /// Bytes per displacement sample: everything but the texel side over the samples (0 without samples).
  double per_sample() const noexcept {
    return samples > 0 ? double(total() - texel_fields - texel_layout) / double(samples) : 0;
  }
};

/// @brief Counts the heap bytes of @p model's arrays by group (ModelMemory).
/// @note O(1): reads each array's capacity; no allocation. The strings (`source`) are left out.
/// Source: hdm's own accounting; the groups follow SlabModel's stored / derived split.
ModelMemory model_memory(const SlabModel& model) noexcept;

}  // namespace hdm
