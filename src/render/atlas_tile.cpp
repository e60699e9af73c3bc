// SPDX-License-Identifier: MIT
#include "atlas_tile.h"

#include <hdm/slab/triangle_grid.h>

#include <algorithm>

namespace hdm::render_detail {

void fill_atlas_tile(const SlabModel& model, const TextureAtlas& layout, int slab, std::vector<uint8_t>& tile) {
  const int N = layout.texel_n, side = layout.tile;
  const SampleLayout& L = model.texels;
  const int32_t* ids = &L.ids[static_cast<size_t>(slab) * L.per_slab];
  tile.resize(static_cast<size_t>(side) * side * 4);
  for (int b = -1; b <= N + 1; ++b)
    for (int c = -1; c <= N + 1; ++c) {
      // Nearest valid texel: clamp into the square, then fold points beyond the hypotenuse onto
      // it, rounding down on ties (same rule as build_texture_atlas()).
      int i = std::clamp(c, 0, N), j = std::clamp(b, 0, N);
      if (i + j > N) {
        i = std::clamp((i - j + N) / 2, 0, N);
        j = N - i;
      }
      const Vec3f& colour = model.colour[ids[grid::index(N, i, j)]];
      uint8_t* px = &tile[(static_cast<size_t>(b + 1) * side + (c + 1)) * 4];
      px[0] = linear_to_srgb8(colour.x());
      px[1] = linear_to_srgb8(colour.y());
      px[2] = linear_to_srgb8(colour.z());
      px[3] = 255;
    }
}

}  // namespace hdm::render_detail
