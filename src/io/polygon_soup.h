// SPDX-License-Identifier: MIT
#pragma once
// Internal to hdm::io: what hdm's own mesh readers (read_off.cpp, read_ply.cpp, read_obj.cpp,
// read_stl.cpp) produce, and the one step that turns it into a TriangleMesh (triangulation,
// welding, unused vertices dropped), so every format gives the same mesh for the same surface.

#include <hdm/mesh/triangle_mesh.h>

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace hdm::io::detail {

/// The file's vertices and polygons, as written. Corner ids index `positions` and are checked by
/// the reader (in [0, positions.size())); positions keep the file's precision until
/// to_triangle_mesh(); polygons of fewer than three corners are kept here and skipped by
/// to_triangle_mesh().
struct PolygonSoup {
  std::vector<Vec3> positions;           ///< file vertices, in file order [file units]
  std::vector<int32_t> corners;          ///< corner vertex ids of every polygon, concatenated
  std::vector<uint64_t> polygon_end{0};  ///< polygon p owns corners [polygon_end[p], polygon_end[p + 1])
  /// (polygon, line) of every polygon of other than three corners that a text reader read at a
  /// known line, in polygon order: where to_triangle_mesh()'s warnings about it point.
  std::vector<std::pair<uint64_t, int64_t>> polygon_lines;
  /// @{ OBJ's point ("p") and line ("l") statements, skipped: only counted, for the message when no
  /// triangle is left.
  uint64_t points = 0, lines = 0;
  /// @}
  std::vector<std::string> warnings;  ///< what the reader skipped: "<name>[:<line>]: <what and why>"

  size_t polygon_count() const { return polygon_end.size() - 1; }
  /// Closes the polygon whose corners were appended since the last call; @p line (> 0) is where a
  /// text reader found it.
  void end_polygon(int64_t line = 0) {
    if (line > 0 && corners.size() - polygon_end.back() != 3) polygon_lines.emplace_back(polygon_count(), line);
    polygon_end.push_back(corners.size());
  }
};

/// @brief Rounds the coordinates of @p soup to float (hdm's input precision), cleans and
/// triangulates its polygons (triangulate_polygon.h: consecutive repeated corners dropped, a corner
/// cycle repeated k times read once, polygons of fewer than three corners and polygons that cross
/// themselves skipped), welds vertices with identical positions (weld_vertices.h), drops vertices
/// no triangle uses and numbers the rest in file order. Appends the soup's warnings and its own
/// ("<name>[:<line>]: ...", one per kind of thing skipped) to @p warnings.
/// @throws InvalidInput "<name>: ..." when a coordinate is not finite, or when no triangle is left
///         (the message says what the file holds instead).
TriangleMesh to_triangle_mesh(PolygonSoup&& soup, const std::string& name, std::vector<std::string>& warnings);

/// Readers of hdm's own: each parses the whole file held in @p bytes in O(bytes.size()) and throws
/// IoError "<name>[:<line>]: <reason>" when it is malformed, truncated, refers to a vertex it does
/// not have, or claims more elements than it can hold (checked before anything is allocated for
/// them); PLY throws InvalidInput when it holds neither faces nor triangle strips. Non-finite
/// coordinates are refused by to_triangle_mesh().
PolygonSoup parse_off(std::string_view bytes, const std::string& name);
PolygonSoup parse_ply(std::string_view bytes, const std::string& name);
PolygonSoup parse_obj(std::string_view bytes, const std::string& name);
PolygonSoup parse_stl(std::string_view bytes, const std::string& name);

}  // namespace hdm::io::detail
