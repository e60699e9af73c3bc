// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Reading triangle meshes from OBJ, PLY (ASCII and binary), OFF and STL files through assimp.

#include <hdm/mesh/triangle_mesh.h>

#include <string>

namespace hdm {

/// @brief Reads the triangle mesh stored in @p path.
///
/// The format is chosen by assimp from the extension and content (OBJ, PLY ASCII/binary, OFF,
/// STL ASCII/binary). Polygons are triangulated (aiProcess_Triangulate) and vertices with
/// identical positions are welded (aiProcess_JoinIdenticalVertices after dropping normals,
/// colours and texture coordinates, so an STL's per-face normals or an OBJ's UV seams do not keep
/// shared corners apart; vertices are then also welded across the scene's meshes). No other
/// processing changes the geometry: node transforms are not applied, and each coordinate is
/// assimp's float widened exactly to double. Vertices that no face uses are dropped and the rest
/// are renumbered compactly (in assimp's order); faces keep the file's order and winding.
/// Before assimp parses a PLY file, its header and body sizes are checked here, because assimp
/// 5.2 hangs on a PLY header without end_header and reads past the end of a truncated body.
///
/// @param path  file name; its extension selects the reader.
/// @return the mesh [file units].
/// @throws IoError "<path>: <reason>" when the file is missing, unreadable, truncated or cannot be
///         parsed (assimp's own error string is the reason).
/// @throws InvalidInput "<path>: <reason>" when the file holds no triangles, a non-finite
///         coordinate, or faces that are still not triangles after triangulation (points or
///         line segments).
/// @note O(#V + #F) after assimp's parse; allocates. Coordinates stored as double in a PLY are
///       rounded to float by assimp.
/// @see assimp's aiPostProcessSteps (postprocess.h); design notes §1.4 (shared vertices).
TriangleMesh read_mesh(const std::string& path);

}  // namespace hdm
