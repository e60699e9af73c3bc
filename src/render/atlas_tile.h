// SPDX-License-Identifier: MIT
#pragma once
// Internal: one slab's tile of a TextureAtlas, for re-uploading a single slab's colours.

#include <hdm/io/texture_atlas.h>

#include <cstdint>
#include <vector>

namespace hdm::render_detail {

/// Fills @p tile with the tile×tile RGBA8 pixels of slab @p slab (padding included, row 0 first),
/// exactly as build_texture_atlas() lays them out at (origin(slab) − (1, 1)). The rule for
/// padding and for pixels beyond the hypotenuse is the one texture_atlas.h documents; the render
/// tests check bit-equality with build_texture_atlas(). Resizes @p tile on first use only.
void fill_atlas_tile(const SlabModel& model, const TextureAtlas& layout, int slab, std::vector<uint8_t>& tile);

}  // namespace hdm::render_detail
