// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Reading triangle meshes from OBJ, PLY (ASCII and binary), OFF and STL files.

#include <hdm/io/read_file.h>
#include <hdm/mesh/triangle_mesh.h>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace hdm {

/// Limits of read_mesh() and read_mesh_from_memory().
struct MeshReadOptions {
  /// Largest input accepted [bytes]; a larger file is refused before it is read. Default 1 GiB
  /// (about 20 million triangles as binary STL or PLY, 10 million as OBJ or OFF text); the `hdm`
  /// program raises it with `--max-input-mb`.
  uint64_t max_file_bytes = default_max_input_bytes;
};

/// @brief What read_mesh() and read_mesh_from_memory() skipped or read otherwise than written,
/// for the caller to show (the library never prints).
struct MeshReadReport {
  /// One line per kind of thing skipped, "<file>[:<line>]: <what was skipped and why>", appended
  /// by every read that is given this report: first the format's own (PLY header lines, OBJ
  /// points and lines), then those about polygons; a kind met many times is one line that counts
  /// them and points at the first. The warnings of hdm's own readers (docs/readers.md lists them
  /// all):
  /// - a PLY header line that starts with no keyword of the format (the first five, then a count);
  /// - OBJ point (`p`) and line (`l`) elements, counted;
  /// - faces of fewer than three distinct corners;
  /// - polygons with a corner repeated in a row (read without the repeats), and polygons whose
  ///   corners are one cycle written several times (read as that cycle once);
  /// - polygons whose edges cross or overlap in their best-fit plane (skipped: their triangles
  ///   would need corners the file does not have);
  /// - for formats read by assimp: faces that are points or line segments, counted.
  std::vector<std::string> warnings;
};

/// @brief Reads the triangle mesh stored in @p path.
///
/// The format is chosen by the extension (case-insensitive); a file without an extension is
/// recognised by its first bytes ("ply", an OFF keyword, "solid" or a binary STL's exact size, an
/// OBJ statement). OBJ, PLY (ASCII, binary little- and big-endian), OFF and STL (ASCII and binary)
/// are read by hdm's own checked readers, one file per format in src/io (read_obj.cpp,
/// read_ply.cpp, read_off.cpp, read_stl.cpp); any other file goes to assimp (glTF, FBX, COLLADA,
/// 3DS, ...), with the size limit and the scene checks below but no guarantee beyond assimp's own.
///
/// The checked readers refuse, before reading further, a header that claims more elements than the
/// rest of the file can hold, and never size an allocation by an unchecked field. They read PLY
/// triangle strips (element `tristrips`, -1 restarting a strip) as triangles, and OBJ written in
/// UTF-16 (either byte order, with or without a byte-order mark) as its UTF-8 text. They
/// triangulate polygons: convex ones as fans; any other one, of any size, by CGAL's 2D constrained
/// Delaunay triangulation in its best-fit plane, covering the points of odd nesting (so a polygon
/// with a hole written as one outline keeps its hole) and keeping the polygon's winding; a polygon
/// whose edges cross or overlap in that plane is skipped. Before that, consecutive repeats of a corner are
/// dropped and a cycle of corners written k times is read once. Points, lines and faces of fewer
/// than three distinct corners are skipped. Every skip is reported in @p report. They then weld
/// vertices with identical positions (except where welding would put more than two faces on an
/// edge whose faces the file's own ids pair: those vertices are welded only as far as each keeps
/// one fan, so a closed manifold file stays one; docs/readers.md), drop the vertices no triangle
/// uses and number the rest in file order; faces keep the file's order and winding. Coordinates
/// are rounded to float, as hdm has always read them (so an OFF and its binary STL give the same
/// mesh and the same bake), then widened exactly to double. STL's per-face normals, OBJ's texture
/// coordinates and normals, and colours are ignored. Each reader's header comment lists what it
/// accepts.
///
/// @param path     file name; its extension selects the reader.
/// @param options  size limit.
/// @param report   when not null, the warnings of this read are appended to it.
/// @return the mesh [file units].
/// @throws IoError "<path>[:<line>]: <reason>" when the file is missing, unreadable, larger than
///         options.max_file_bytes, truncated, malformed, or claims more elements than it holds
///         (for example "<path>: the OFF header claims 4 vertices and 4,999,999,999 faces, but only
///         48 bytes follow it ...").
/// @throws InvalidInput "<path>: <reason>" when the file holds a non-finite coordinate, or no
///         triangle, saying what it holds instead (for example "<path>: holds no triangles: 6 line
///         elements, 6 point elements (8 vertices)").
/// @note O(file size) time for triangles and convex polygons, O(k log k) expected (O(k²) at
///       worst) for any other polygon of k corners, plus O(#V log #V) for welding; O(file size)
///       memory; allocates.
/// @see Turk, "The PLY polygon file format" (1994); Geomview's OFF(5) manual page; Wavefront's
///      OBJ specification (Appendix B1 of the Advanced Visualizer manual); CGAL's 2D
///      triangulations (Constrained_Delaunay_triangulation_2); docs/design.md#sample-layout-and-seams
///      (shared vertices).
TriangleMesh read_mesh(const std::string& path, const MeshReadOptions& options = {}, MeshReadReport* report = nullptr);

/// @brief Reads a mesh file held in memory, as read_mesh() reads a file.
/// @param bytes    the file's content.
/// @param name     the file's name: its extension (or, without one, the content) selects the
///                 format, and it starts every error message and warning.
/// @param options  size limit (checked against bytes.size()).
/// @param report   when not null, the warnings of this read are appended to it.
/// @return the mesh [file units].
/// @throws IoError, InvalidInput as read_mesh().
/// @note Formats that refer to other files (OBJ's material library, glTF's buffers) are read
///       without them; hdm reads only positions and faces. Cost as read_mesh().
TriangleMesh read_mesh_from_memory(std::string_view bytes, const std::string& name,
                                   const MeshReadOptions& options = {}, MeshReadReport* report = nullptr);

}  // namespace hdm
