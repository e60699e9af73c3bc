// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Reading triangle meshes from OBJ, PLY (ASCII and binary), OFF and STL files.

#include <hdm/io/read_file.h>
#include <hdm/mesh/triangle_mesh.h>

#include <cstdint>
#include <string>
#include <string_view>

namespace hdm {

/// Limits of read_mesh() and read_mesh_from_memory().
struct MeshReadOptions {
  /// Largest input accepted [bytes]; a larger file is refused before it is read. Default 1 GiB
  /// (about 20 million triangles as binary STL or PLY, 10 million as OBJ or OFF text); the `hdm`
  /// program raises it with `--max-input-mb`.
  uint64_t max_file_bytes = default_max_input_bytes;
};

/// @brief Reads the triangle mesh stored in @p path.
///
/// The format is chosen by the extension (case-insensitive). OBJ, PLY (ASCII, binary little- and
/// big-endian), OFF and STL (ASCII and binary) are read by hdm's own checked readers, one file per
/// format in src/io (read_obj.cpp, read_ply.cpp, read_off.cpp, read_stl.cpp); any other extension
/// goes to assimp (glTF, FBX, COLLADA, 3DS, ...), with the size limit and the scene checks below
/// but no guarantee beyond assimp's own.
///
/// The checked readers refuse, before reading further, a header that claims more elements than the
/// rest of the file can hold, never size an allocation by an unchecked field, and run in time
/// linear in the file size. They triangulate polygons (convex ones as fans, concave ones of up to
/// 64 corners by ear clipping in their best-fit plane, keeping the winding), weld vertices with
/// identical positions (except where welding would put more than two faces on an edge whose faces
/// the file's own ids pair: those vertices are welded only as far as each keeps one fan, so a
/// closed manifold file stays one; docs/readers.md), drop the vertices no triangle uses and number the rest in file
/// order; faces keep the file's order and winding. Coordinates are rounded to float, as hdm has always read them (so an
/// OFF and its binary STL give the same mesh and the same bake), then widened exactly to double. STL's per-face
/// normals, OBJ's texture coordinates and normals, and colours are ignored. Each reader's header comment lists what it
/// accepts.
///
/// @param path     file name; its extension selects the reader.
/// @param options  size limit.
/// @return the mesh [file units].
/// @throws IoError "<path>[:<line>]: <reason>" when the file is missing, unreadable, larger than
///         options.max_file_bytes, truncated, malformed, or claims more elements than it holds
///         (for example "<path>: the OFF header claims 4 vertices and 4,999,999,999 faces, but only
///         48 bytes follow it ...").
/// @throws InvalidInput "<path>: <reason>" when the file holds no triangles, a non-finite
///         coordinate, faces that are points or line segments, or a concave polygon of more than
///         64 corners.
/// @note O(file size) time (plus O(#V log #V) for welding) and memory; allocates.
/// @see Turk, "The PLY polygon file format" (1994); Geomview's OFF(5) manual page; Wavefront's
///      OBJ specification (Appendix B1 of the Advanced Visualizer manual); docs/design.md#sample-layout-and-seams
///      (shared vertices).
TriangleMesh read_mesh(const std::string& path, const MeshReadOptions& options = {});

/// @brief Reads a mesh file held in memory, as read_mesh() reads a file.
/// @param bytes    the file's content.
/// @param name     the file's name: its extension selects the format, and it starts every error
///                 message.
/// @param options  size limit (checked against bytes.size()).
/// @throws IoError, InvalidInput as read_mesh().
/// @note Formats that refer to other files (OBJ's material library, glTF's buffers) are read
///       without them; hdm reads only positions and faces.
TriangleMesh read_mesh_from_memory(std::string_view bytes, const std::string& name,
                                   const MeshReadOptions& options = {});

}  // namespace hdm
