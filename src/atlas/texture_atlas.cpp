// SPDX-License-Identifier: MIT
#include <hdm/core/error.h>
#include <hdm/atlas/texture_atlas.h>
#include <hdm/query/slab_query.h>
#include <hdm/slab/triangle_grid.h>

#include <hdm/query/detail/surface_eval.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace hdm {
namespace {

// The under-layer's top δ at barycentrics (·, wS, wT) of a slab, over the grid triangle that
// evaluate_surface() interpolates δ on.
double interpolate_layer(const SlabModel& m, int slab, double wS, double wT) noexcept {
  const SampleField<Unorm16>& L = m.layer_displacement;
  if (L.uniform()) return L.uniform_value();
  const slab_query::detail::GridCell c = slab_query::detail::grid_cell(m, slab, wS, wT);
  return c.wa * L[c.a] + c.wb * L[c.b] + c.wd * L[c.d];
}

}  // namespace

Vec3f surface_colour(const SlabModel& m, int texel) noexcept {
  const SampleLayout& T = m.texels;
  if (m.layer_displacement.size() != static_cast<size_t>(m.samples.count)) return decode_srgb8(m.colour[texel]);
  const int local = T.home(texel).index, slab = T.home(texel).slab;
  const double wS = double(T.point_j[local]) / T.n, wT = double(T.point_i[local]) / T.n;
  SlabCoordinates c;
  c.bary = Vec3(1 - wS - wT, wS, wT);
  Contact at;
  evaluate_surface(m, slab, c, at);
  const double layer = interpolate_layer(m, slab, wS, wT);
  return layer > at.delta ? m.under_layer.colour : decode_srgb8(m.colour[texel]);
}

namespace {

// Walks the tile's pixels (padding included) and writes pixel (c, b) from texel (i, j) of the slab
// (grid::index(N, i, j)) with rgba(index, px): the pixel itself inside the triangle, the nearest
// valid texel (Euclidean) beyond the hypotenuse and in the padding.
template <class Rgba>
void walk_tile(int N, uint8_t* out, int stride, Rgba&& rgba) noexcept {
  for (int b = -1; b <= N + 1; ++b)
    for (int c = -1; c <= N + 1; ++c) {
      // For each row j the best column is c clamped to [0, N-j]; scan the rows only for pixels
      // outside the triangle.
      int i = c, j = b;
      if (c < 0 || b < 0 || c + b > N) {
        long best = std::numeric_limits<long>::max();
        for (int r = 0; r <= N; ++r) {
          const int q = std::clamp(c, 0, N - r);
          const long d = long(q - c) * (q - c) + long(r - b) * (r - b);
          if (d < best) best = d, i = q, j = r;
        }
      }
      rgba(grid::index(N, i, j), out + (static_cast<size_t>(b + 1) * stride + (c + 1)) * 4);
    }
}

}  // namespace

void fill_atlas_tile(const SlabModel& model, const TextureAtlas& a, int slab, uint8_t* out, int stride,
                     AtlasContent content) noexcept {
  const SlabIds ids = model.texels.slab_ids(slab);
  const bool paint = content == AtlasContent::PaintAndRoughness;
  walk_tile(a.texel_n, out, stride, [&](int local, uint8_t* px) {
    const int32_t texel = ids[local];
    // The stored codes as they are where the painted colour shows: no decode and re-encode.
    const Srgb8 c = paint ? model.colour[texel] : encode_srgb8(surface_colour(model, texel));
    px[0] = c.r, px[1] = c.g, px[2] = c.b;
    px[3] = paint && texel < static_cast<int32_t>(model.roughness.size()) ? model.roughness[texel] : 255;
  });
}

void fill_atlas_tile(const TextureAtlas& a, const uint8_t* texels, uint8_t* out, int stride) noexcept {
  walk_tile(a.texel_n, out, stride, [&](int local, uint8_t* px) {
    const uint8_t* t = texels + static_cast<size_t>(local) * 4;
    px[0] = t[0], px[1] = t[1], px[2] = t[2], px[3] = t[3];
  });
}

TextureAtlas build_texture_atlas(const SlabModel& model, AtlasContent content) {
  const int S = model.slab_count();
  const int N = model.grid_n * model.texel_density;
  const SampleLayout& L = model.texels;
  if (S == 0) throw InvalidInput("build_texture_atlas: the model has no slabs");
  if (L.n != N || L.slot_count() != static_cast<size_t>(S) * L.per_slab || model.colour.size() != size_t(L.count))
    throw InvalidInput("build_texture_atlas: texel layout or colours missing (call rebuild_derived first)");

  TextureAtlas a;
  a.texel_n = N;
  a.tile = N + 3;
  a.columns = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(S))));
  const int rows = (S + a.columns - 1) / a.columns;
  a.width = a.columns * a.tile;
  a.height = rows * a.tile;
  a.rgba.assign(static_cast<size_t>(a.width) * a.height * 4, 0);

  for (int s = 0; s < S; ++s) {
    const Eigen::Vector2i o = a.origin(s);
    fill_atlas_tile(model, a, s, &a.rgba[(static_cast<size_t>(o.y() - 1) * a.width + (o.x() - 1)) * 4], a.width,
                    content);
  }
  return a;
}

}  // namespace hdm
