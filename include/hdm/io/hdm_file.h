// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// The `.hdm` file: a slab model's stored data in a versioned little-endian binary format
/// (docs/design.md#file-format).
///
/// Format version 7, all integers and floats little-endian, IEEE-754:
///
/// | bytes | content |
/// | --- | --- |
/// | 4 | magic `"HDM\0"` |
/// | 4 | uint32 format version (= 7) |
/// | ... | 17 sections, in the order below (version 1: the first 12; versions 2 and 3: the first 15) |
/// | 8 | uint64 FNV-1a (64-bit) hash of every byte before it |
///
/// Each section is a 4-byte tag, a uint64 element count `k`, then `k` elements. From version 7, a
/// per-sample field (`FRST`, `FRDY`, `STIF`, `LAYD`, `HARD`) or texel field (`COLR`, `RUFF`) whose
/// codes are all equal is written as one element, which every sample or texel takes (SampleField:
/// a baked model's fields are one value each until painted; 2 bytes per sample, 3 and 1 per texel
/// less).
///
/// | tag | elements | element |
/// | --- | --- | --- |
/// | `GRID` | 2 | int32: grid_n, texel_density |
/// | `INNR` | #C | 3 float64: inner position [model units] |
/// | `OUTR` | #C | 3 float64: outer position [model units] |
/// | `SLAB` | #S | 3 int32: coarse vertex ids R, S, T |
/// | `DISP` | #samples | uint16: displacement δ as unorm16, code/65535 (versions 1-5: float32) |
/// | `COLR` | #texels | 3 uint8: 8-bit sRGB R, G, B (SlabModel::colour; versions 1 and 2: 3 float32 linear RGB) |
/// | `FRST` | #samples | uint16: friction_static as IEEE binary16 bits (versions 1-4: float32) |
/// | `FRDY` | #samples | uint16: friction_dynamic as IEEE binary16 bits (versions 1-4: float32) |
/// | `STIF` | #samples | uint16: stiffness_scale as unorm16, code/65535 (versions 1-4: float32) |
/// | `SRCN` | bytes | uint8: source name (no terminator) |
/// | `SRCT` | 1 | int64 source_triangles |
/// | `SRCD` | 1 | float64 source_diagonal [model units] |
/// | `RUFF` | #texels | uint8 roughness as unorm8, code/255 (version 2: float32 in [0,1]; from version 2) |
/// | `LAYD` | #samples | uint16: layer_displacement as unorm16 (versions 2-4: float32; from version 2) |
/// | `LAYM` | 1 | 7 float32: under_layer colour RGB, stiffness_scale, friction_static, friction_dynamic, roughness
/// (from version 2) |
/// | `HARD` | #samples | uint16: hardness [HV] as IEEE binary16 bits (version 4: float32; from version 4) |
/// | `LAYH` | 1 | float32 under_layer.hardness_hv [HV] (from version 4) |
///
/// Version 1 files (without `RUFF`, `LAYD` and `LAYM`) load with the defaults of those fields.
/// Version 1 and 2 files' float colours and roughness are encoded to 8 bits on load (rounded once,
/// so colours move by at most half an sRGB code step). Files before version 4 load with the default
/// hardness (default_hardness_hv per sample, UnderLayer's default for the under-layer). Files before
/// version 5 store the per-sample fields as float32: load_model() rounds each once to the model's
/// 16-bit field (hdm/core/field16.h), refusing a value the field cannot hold (outside [0, 1] for
/// unorm16, beyond ±65,504 for binary16, not finite); files before version 6 store the
/// displacements so too, and are rounded and refused alike. save_model() always writes version 7,
/// whose 16-bit sections hold the model's codes bit for bit (a save and a load give the same model).
/// Derived members of SlabModel are not stored; load_model() rebuilds them. #samples and #texels
/// follow from the counts (#C + (k-1)·#E + (k-1)(k-2)/2·#S for k = grid_n and grid_n·texel_density,
/// #E the distinct slab edges); `DISP` must hold exactly that many, `COLR` that many or one
/// (version 7), and `FRST`, `FRDY`, `STIF`, `RUFF`, `LAYD` and `HARD` that many, one (version 7) or
/// none (defaults); `LAYM` one.

#include <hdm/io/read_file.h>
#include <hdm/core/write_file_atomic.h>
#include <hdm/slab/slab_model.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

namespace hdm {

/// Largest coordinate magnitude load_model() accepts for a coarse vertex [model units]: sample
/// positions, boxes and normals are float, and their differences and cross products must stay
/// finite.
inline constexpr double max_model_coordinate = 1e15;

/// Version of the `.hdm` format that save_model() writes and load_model() reads.
inline constexpr uint32_t hdm_format_version = 7;

/// @brief Writes the stored members of @p model to @p path (format in this file's header).
/// @param model  slab model; its stored arrays have the sizes rebuild_derived() checks.
/// @param path   output file; written to a temporary in its directory, then renamed over @p path
///               (write_file_atomic()).
/// @pre rebuild_derived(model) has run since the last structural change (it fills the optional
///      per-sample and per-texel arrays, so save, load and save again give identical bytes).
/// @throws IoError "<path>: <reason>" when the file cannot be written; the previous content of
///         @p path is then left untouched and the temporary file is removed.
/// @note O(stored bytes); streams the file in 1 MiB pieces (write_file_atomic()'s streaming form),
///       so a save takes 1 MiB beside the model, not the file's size.
void save_model(const SlabModel& model, const std::string& path);

/// Limits of load_model().
struct ModelLoadOptions {
  /// Largest file accepted [bytes]; a larger file is refused before it is read. Default 1 GiB;
  /// the `hdm` program raises it with `--max-input-mb`.
  uint64_t max_file_bytes = default_max_input_bytes;
};

/// @brief Reads a model written by save_model() and rebuilds its derived members.
/// @param path     `.hdm` file.
/// @param options  size limit.
/// @return the model; every stored member equals the saved one bit for bit (a version 1 or 2
///         file: its colours and roughness encoded to 8 bits, see the header).
/// @throws IoError "<path>: <reason>" when the file is missing or unreadable, larger than
///         options.max_file_bytes, is not an `.hdm` file, has another format version ("<path>:
///         format version 8, this hdm reads
///         versions 1 to 7"), is truncated ("<path>: truncated ..."),
///         has a count larger than the remaining bytes allow (checked before anything is
///         allocated), or fails the checksum ("<path>: checksum mismatch (file corrupt)").
/// @throws InvalidInput "<path>: ..." when the content is inconsistent: grid sizes out of range,
///         invalid slab corners, a coarse vertex beyond ±max_model_coordinate, a version 1 or 2
///         colour that is not finite or roughness outside [0,1], `DISP` or `COLR`
///         not of the layout's size (checked before the
///         layouts are built, so no allocation follows grid_n or texel_density alone), or what
///         rebuild_derived() refuses.
/// @note O(file size + rebuild_derived()); reads the whole file into memory, and frees it before
///       the derived arrays (a bounded multiple of the file's size) are built: `hdm info` of a
///       100,000-slab model peaks at 1,046 MiB for its 1,004 MiB.
SlabModel load_model(const std::string& path, const ModelLoadOptions& options = {});

/// @brief Reads a model from the bytes of an `.hdm` file held in memory, as load_model() reads a
/// file; @p name starts every error message.
/// @throws IoError, InvalidInput as load_model().
SlabModel load_model_from_memory(std::span<const uint8_t> bytes, const std::string& name,
                                 const ModelLoadOptions& options = {});

}  // namespace hdm
