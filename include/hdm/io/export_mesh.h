// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Export of a slab model's reconstructed (displaced) surface to OBJ, PLY and binary glTF.

#include <hdm/slab/slab_model.h>

#include <string>
#include <vector>

namespace hdm {

/// @brief Writes the displaced surface of @p model to @p path, in the format of its extension.
///
/// The surface has one vertex per global displacement sample s at sample_position(model, s) with
/// normal sample_normal(model, s), and the faces `model.samples.triangles` (counter-clockwise from
/// outside; paper §3.2). Formats, by extension (case-insensitive):
/// - `.obj`: OBJ with `v` and `vn` per sample, `vt` per (slab, grid point) from the texture
///   atlas (v flipped: OBJ's v = 0 is the image's bottom row), faces `f v/vt/vn`; plus
///   "<stem>.mtl" (material `hdm_colour`, map_Kd) and "<stem>.png" (build_texture_atlas()) next
///   to it.
/// - `.ply`: binary little-endian PLY: float x y z, float nx ny nz, uchar red green blue (the
///   sRGB-encoded colour of the texel at the sample's grid point), faces as uchar-counted int
///   lists.
/// - `.glb`: binary glTF 2.0: one mesh whose vertices are duplicated per slab (so each slab has its
///   own atlas coordinates): POSITION, NORMAL, TEXCOORD_0, uint32 indices, and a PBR material
///   (metallic 0, roughness 1) whose baseColorTexture is the atlas, embedded as PNG.
///
/// @param model  slab model with derived data (rebuild_derived()).
/// @param path   output file; every file is written as "<file>.tmp" and renamed.
/// @throws InvalidInput naming @p path when the extension is not .obj, .ply or .glb.
/// @throws IoError "<file>: <reason>" when a file cannot be written.
/// @note O(#S·n² + #S·(n·m)²) time; builds each file in memory first.
/// @see export_files() for the names of the files written.
void export_mesh(const SlabModel& model, const std::string& path);

/// @brief The files export_mesh(model, @p path) writes: @p path, and for `.obj` also the `.mtl`
/// and `.png` beside it.
/// @throws InvalidInput naming @p path when the extension is not supported.
std::vector<std::string> export_files(const std::string& path);

}  // namespace hdm
