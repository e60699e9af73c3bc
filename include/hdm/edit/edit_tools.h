// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Sculpting and painting: carve, add material and paint with a spherical tool, by flood fill over
/// the global sample (or texel) graph, which crosses slab edges and corners by construction
/// (paper §4-5; design notes §5).

#include <hdm/query/slab_query.h>

#include <array>
#include <cstdint>
#include <vector>

namespace hdm {

/// Caller-owned buffers for edits, sized once for a model so that edits never allocate (they may
/// run in the servo loop). One per editing thread.
struct EditScratch {
  /// @brief Sizes every buffer for @p model. Allocates O(#samples + #texels + #S): about
  /// 12 bytes per sample, 8 per texel, 1 per slab, plus a fixed ~120 KB (face-normal memo).
  explicit EditScratch(const SlabModel& model);
  std::vector<uint32_t> sample_stamp, texel_stamp;  ///< visit marks of the current edit
  uint32_t stamp = 0;                               ///< current edit's mark
  std::vector<int32_t> queue;                       ///< flood-fill queue (samples or texels)
  std::vector<int32_t> changed;                     ///< samples changed by the last edit
  std::vector<int32_t> ring;                        ///< changed samples plus their neighbours
  std::vector<uint8_t> dirty_slabs;                 ///< #S flags set by edits; the renderer clears them
  FaceNormalCache faces;                            ///< per-triangle normals, each computed once per edit
  /// per_slab entries: barycentrics (wR, wS, wT) of each grid index of the displacement grid, as
  /// projection_line() computes them (same bits), so the flood fill does not divide per sample.
  std::vector<std::array<double, 3>> grid_weights;
};

/// What one edit did.
struct EditResult {
  int32_t visited = 0;  ///< samples (texels for paint) the flood fill visited
  int32_t changed = 0;  ///< samples whose displacement (texels whose colour) changed
};

/// @brief Carve: remove material inside a sphere of radius @p radius centred at
/// hip + n·(radius + resilience), n the contact normal (paper §4.1, Fig. 7).
/// @param contact     current contact (must be in a slab; nothing happens otherwise).
/// @param hip         haptic interaction point [model units].
/// @param radius      tool radius [model units], > 0.
/// @param resilience  resilient band k [model units], >= 0: carving starts once the depth exceeds it.
/// @note No allocation. Displacement of a sample whose projection line enters the sphere below its
///       surface is lowered to the sphere's entry point; a sphere buried below the surface leaves
///       the column unchanged (no cavities); δ stays in [0,1]. Never raises a sample. Updates the
///       positions and normals of the changed samples and their one-ring, marks dirty slabs.
///       Cost O(visited·valence).
EditResult carve(SlabModel& model, EditScratch& scratch, const Contact& contact, const Vec3& hip, double radius,
                 double resilience) noexcept;

/// @brief Add material: a cone of height @p height and radius @p radius centred at the surface
/// contact point: δ += height·max(0, 1 - d/r)/|P1 - P0|, clamped to 1 (paper §4.2; the cone falls
/// linearly with distance, design notes §5.2).
/// @note Never lowers a sample. No allocation; O(visited·valence).
EditResult add_material(SlabModel& model, EditScratch& scratch, const Contact& contact, double radius,
                        double height) noexcept;

/// @brief Paint: texels within @p radius of the surface contact point blend towards @p colour with
/// intensity k = pressure·(1 - d/r): c ← k·colour + (1-k)·c (paper §5).
/// @param pressure  in [0,1] (clamped), from the penetration depth (see paint_pressure()).
/// @note Texel positions are taken on the displaced surface. No allocation; O(visited).
EditResult paint(SlabModel& model, EditScratch& scratch, const Contact& contact, double radius, const Vec3f& colour,
                 double pressure) noexcept;

/// @brief Paint pressure from penetration depth: clamp((depth - d0)/(d1 - d0), 0, 1) (design notes §5.3).
/// @param d0  dead zone [model units]: lighter touches do not paint. @param d1 depth of full pressure.
double paint_pressure(double depth, double d0, double d1) noexcept;

}  // namespace hdm
