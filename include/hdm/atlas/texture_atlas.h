// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// One texture image holding the colour texels of every slab (paper §6: colour is a texture per
/// slab; docs/design.md#texture-atlas: texel centres on the grid points, padding against bilinear bleeding).

#include <hdm/slab/slab_model.h>

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace hdm {

/// Colour texels of a slab model packed into one RGBA8 image, one square tile per slab.
///
/// Layout: the texel grid has N = grid_n·texel_density intervals. Slab s owns a tile of
/// (N+3)×(N+3) pixels at column s % columns and row s / columns of a near-square tile grid: the
/// (N+1)×(N+1) square of texels with one pixel of padding on every side. Texel (i, j) of slab s
/// (barycentrics wT = i/N, wS = j/N) is the pixel (x0 + i, y0 + j), where (x0, y0) = origin(s).
/// Pixels with i + j > N (beyond the hypotenuse) and padding pixels copy the nearest valid texel,
/// so bilinear filtering near the slab's edges reads only the slab's own colours.
///
/// Pixels are 8-bit sRGB-encoded RGBA (alpha 255), row-major, row 0 first ("top").
/// Texture coordinates (uv()) follow glTF: u grows with x, v grows with the row index, and v = 0
/// is the edge of row 0, the first row stored. OpenGL sampling of `rgba` uploaded as-is with
/// glTexImage2D uses the same coordinates. (OBJ's vt has v = 0 at the bottom: use 1 - v there.)
struct TextureAtlas {
  int width = 0;              ///< image width [pixels]
  int height = 0;             ///< image height [pixels]
  int texel_n = 0;            ///< N: texel intervals per slab edge (grid_n·texel_density)
  int tile = 0;               ///< tile side N + 3 [pixels]
  int columns = 0;            ///< tiles per image row
  std::vector<uint8_t> rgba;  ///< width·height·4 bytes, sRGB-encoded RGBA8, row 0 = top

  /// Pixel (x0, y0) of texel (0, 0) (corner R) of slab @p slab.
  Eigen::Vector2i origin(int slab) const { return {(slab % columns) * tile + 1, (slab / columns) * tile + 1}; }

  /// @brief Texture coordinates of the point with barycentrics (wR, wS, wT) of slab @p slab.
  /// @param slab  slab id in [0, #S).
  /// @param wT    barycentric of corner T (= i/N at texel (i, j)).
  /// @param wS    barycentric of corner S (= j/N at texel (i, j)).
  /// @return (u, v) in [0,1]²; at grid points it is the exact centre of the texel's pixel.
  /// @note O(1), noexcept.
  Eigen::Vector2f uv(int slab, double wT, double wS) const noexcept {
    const Eigen::Vector2i o = origin(slab);
    return {static_cast<float>((o.x() + wT * texel_n + 0.5) / width),
            static_cast<float>((o.y() + wS * texel_n + 0.5) / height)};
  }
};

/// What the pixels of an atlas hold.
enum class AtlasContent : uint8_t {
  /// The colour the surface shows: the painted colour, or the under-layer's where carving
  /// exposed it at the texel (SlabModel::layer_displacement above the surface); alpha 255.
  /// For exports.
  Surface,
  /// The painted colour whatever lies under it, and the roughness in alpha (0 → 0, 1 → 255):
  /// for a renderer that shows the under-layer per fragment (SlabRenderer).
  PaintAndRoughness,
};

/// @brief Packs the colour texels of @p model into a texture atlas (layout: see TextureAtlas).
/// @param model    slab model with derived data (rebuild_derived()); `colour` holds linear RGB.
/// @param content  what the pixels hold (see AtlasContent).
/// @return the atlas; colours are clamped to [0,1] and encoded with the sRGB transfer function.
/// @throws InvalidInput if the model has no slabs or its texel layout is missing.
/// @note O(#S·N²) time and memory.
TextureAtlas build_texture_atlas(const SlabModel& model, AtlasContent content = AtlasContent::Surface);

/// @brief The colour the surface shows at texel @p texel: its painted colour, or the under-layer's
/// where the surface lies below the layer's top there (δ and the layer's δ interpolated at the
/// texel like evaluate_surface() does). Linear RGB.
/// @note noexcept, O(1).
Vec3f surface_colour(const SlabModel& model, int texel) noexcept;

/// @brief Writes the tile×tile RGBA8 pixels of slab @p slab's tile (padding included, row 0
/// first) of @p layout into @p out, whose rows are @p stride pixels apart. build_texture_atlas()
/// uses it for every slab; a renderer uses it to re-upload one edited slab's colours.
/// @param model    slab model with derived data.
/// @param layout   an atlas of @p model (only its layout fields are read).
/// @param slab     slab id in [0, #S).
/// @param out      first pixel of the tile in the destination (RGBA8).
/// @param stride   distance between destination rows [pixels].
/// @param content  what the pixels hold (see AtlasContent).
/// @note O(tile²) plus O(N) per padding pixel; no allocation.
void fill_atlas_tile(const SlabModel& model, const TextureAtlas& layout, int slab, uint8_t* out, int stride,
                     AtlasContent content = AtlasContent::Surface) noexcept;

/// @brief fill_atlas_tile() with AtlasContent::PaintAndRoughness from one slab's texels as a
/// snapshot holds them (hdm::SlabView::texels): @p texels has texels_per_slab × 4 bytes, the
/// colour's sRGB8 codes and the roughness's unorm8 code, in grid::index order of the slab's texel
/// grid. Lets a renderer thread re-upload a slab from a snapshot while another thread edits the
/// live model.
/// @param layout  an atlas of the model (only its layout fields are read).
/// @param texels  texels_per_slab × 4 bytes (see above).
/// @param out     first pixel of the tile in the destination (RGBA8).
/// @param stride  distance between destination rows [pixels].
/// @note O(tile²) plus O(N) per padding pixel; no allocation. Same pixels as the model overload
///       for the same data.
void fill_atlas_tile(const TextureAtlas& layout, const uint8_t* texels, uint8_t* out, int stride) noexcept;

}  // namespace hdm
