// SPDX-License-Identifier: MIT
#pragma once
// Internal to hdm::io: what hdm's own mesh readers (read_off.cpp, read_ply.cpp, read_obj.cpp,
// read_stl.cpp) produce, and the one step that turns it into a TriangleMesh (triangulation,
// welding, unused vertices dropped), so every format gives the same mesh for the same surface.

#include <hdm/mesh/triangle_mesh.h>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace hdm::detail {

/// The file's vertices and polygons, as written. Corner ids index `positions` and are checked by
/// the reader (in [0, positions.size())); positions keep the file's precision until
/// to_triangle_mesh(); polygons of one or two corners are kept here and
/// refused by to_triangle_mesh().
struct PolygonSoup {
  std::vector<Vec3> positions;           ///< file vertices, in file order [file units]
  std::vector<int32_t> corners;          ///< corner vertex ids of every polygon, concatenated
  std::vector<uint64_t> polygon_end{0};  ///< polygon p owns corners [polygon_end[p], polygon_end[p + 1])
  uint64_t points_and_lines = 0;         ///< point and line elements (OBJ "p", "l"): refused like short polygons

  size_t polygon_count() const { return polygon_end.size() - 1; }
  void end_polygon() { polygon_end.push_back(corners.size()); }
};

/// Largest concave polygon that is triangulated (ear clipping costs O(k²) to O(k³) in its corner
/// count k); convex polygons of any size are fanned in O(k).
inline constexpr size_t max_concave_polygon_corners = 64;

/// @brief Rounds the coordinates of @p soup to float (hdm's input precision), triangulates its
/// polygons (convex ones as fans, concave ones by ear clipping in their best-fit plane, keeping
/// the winding), welds vertices with identical positions (the first in file order keeps its
/// place; not where the weld would put more than two faces on an edge the file pairs, see
/// keep_file_pairing in weld_vertices.cpp), drops vertices no triangle uses and numbers the rest in file order.
/// @throws InvalidInput "<name>: ..." when a polygon has fewer than three corners, a concave
///         polygon has more than max_concave_polygon_corners corners, or no triangle is left.
TriangleMesh to_triangle_mesh(PolygonSoup&& soup, const std::string& name);

/// Readers of hdm's own: each parses the whole file held in @p bytes in O(bytes.size()) and throws
/// IoError "<name>[:<line>]: <reason>" when it is malformed, truncated, refers to a vertex it does
/// not have, or claims more elements than it can hold (checked before anything is allocated for
/// them); PLY throws InvalidInput when it holds no faces. Non-finite coordinates are refused by
/// to_triangle_mesh().
PolygonSoup parse_off(std::string_view bytes, const std::string& name);
PolygonSoup parse_ply(std::string_view bytes, const std::string& name);
PolygonSoup parse_obj(std::string_view bytes, const std::string& name);
PolygonSoup parse_stl(std::string_view bytes, const std::string& name);

}  // namespace hdm::detail
