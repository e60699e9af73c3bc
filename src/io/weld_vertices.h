// SPDX-License-Identifier: MIT
#pragma once
// Internal to hdm::io: the welding step shared by hdm's own readers (weld_vertices.cpp).

#include <hdm/mesh/triangle_mesh.h>

#include <vector>

namespace hdm::io::detail {

/// @brief The mesh of @p triangles (corner ids into @p positions) with the vertices at identical
/// positions welded (the first in file order keeps its place; not where the weld would put more
/// than two faces on an edge whose faces the file's own ids pair, see keep_file_pairing in
/// weld_vertices.cpp), the vertices no triangle uses dropped and the rest numbered in file order.
/// Faces keep their order and winding.
/// @note O(#V log #V), plus the faces around the welds it undoes.
TriangleMesh weld_vertices(const std::vector<Vec3>& positions, const std::vector<Tri>& triangles);

}  // namespace hdm::io::detail
