// SPDX-License-Identifier: MIT
// Polygon soup -> TriangleMesh: coordinates rounded to float, polygons cleaned and triangulated
// (triangulate_polygon.h), what was skipped reported once per kind, vertices welded
// (weld_vertices.h). Shared by hdm's own OFF, PLY, OBJ and STL readers.
#include "polygon_soup.h"
#include "text_cursor.h"
#include "triangulate_polygon.h"
#include "weld_vertices.h"

#include <hdm/core/error.h>

#include <algorithm>
#include <array>

namespace hdm::io::detail {
namespace {

// Drops consecutive repeats of a corner (cyclically: the last corner repeating the first too) from
// ids[0, k), in place, then reads a cycle of corners repeated r times ("f 1 2 3 4 1 2 3 4 ...") as
// that cycle once. O(k).
struct CleanCorners {
  size_t corners = 0;  // corners left
  size_t repeats = 1;  // how often the cycle left was written
  bool dropped = false;
};
CleanCorners clean_corners(int32_t* ids, size_t k, std::vector<size_t>& border) {
  CleanCorners c;
  size_t w = 0;
  for (size_t i = 0; i < k; ++i)
    if (w == 0 || ids[i] != ids[w - 1]) ids[w++] = ids[i];
  while (w > 1 && ids[w - 1] == ids[0]) --w;
  c.dropped = w != k;
  // Shortest period of the sequence, from its longest proper prefix that is also a suffix (KMP).
  border.assign(w, 0);
  for (size_t i = 1; i < w; ++i) {
    size_t b = border[i - 1];
    while (b > 0 && ids[i] != ids[b]) b = border[b - 1];
    border[i] = b + (ids[i] == ids[b] ? 1 : 0);
  }
  const size_t period = w > 0 ? w - border[w - 1] : 0;
  if (period > 0 && period < w && w % period == 0) c.repeats = w / period, w = period;
  c.corners = w;
  return c;
}

// Polygons of one kind that were changed or skipped: how many, and the first.
struct Tally {
  uint64_t count = 0, first = 0;
  size_t first_corners = 0, first_cycle = 0, first_repeats = 0;
  bool add(uint64_t polygon) {
    if (count++ == 0) first = polygon;
    return count == 1;
  }
};

std::string plural(uint64_t n, const char* one, const char* many) {
  return with_commas(n) + " " + (n == 1 ? one : many);
}

// What to_triangle_mesh() skipped or read otherwise, by kind.
struct Skipped {
  Tally short_faces, repeated_corners, repeated_cycles, crossing;
};

// One warning per kind of polygon skipped or changed, pointing at the first: the line a text
// reader found it at, else its number.
void report_skipped(const PolygonSoup& soup, const Skipped& s, const std::string& name,
                    std::vector<std::string>& warnings) {
  auto where = [&](uint64_t p) {
    const auto it =
        std::lower_bound(soup.polygon_lines.begin(), soup.polygon_lines.end(), std::pair<uint64_t, int64_t>(p, 0));
    if (it != soup.polygon_lines.end() && it->first == p) return name + ":" + std::to_string(it->second);
    return name + ": face " + with_commas(p);
  };
  auto first_here = [](const Tally& t) { return t.count > 1 ? std::string(" (the first here)") : std::string(); };
  if (s.short_faces.count > 0)
    warnings.push_back(where(s.short_faces.first) + ": skipped " + plural(s.short_faces.count, "face", "faces") +
                       " of fewer than three distinct corners" + first_here(s.short_faces) + ": they bound no area");
  if (s.repeated_corners.count > 0)
    warnings.push_back(where(s.repeated_corners.first) + ": " +
                       plural(s.repeated_corners.count, "polygon repeats", "polygons repeat") + " a corner in a row" +
                       first_here(s.repeated_corners) + ": read without the repeats");
  if (s.repeated_cycles.count > 0)
    warnings.push_back(
        where(s.repeated_cycles.first) + ": a polygon of " + with_commas(s.repeated_cycles.first_corners) +
        " corners is a cycle of " + with_commas(s.repeated_cycles.first_cycle) + " corners written " +
        with_commas(s.repeated_cycles.first_repeats) + " times" +
        (s.repeated_cycles.count > 1 ? " (and " + with_commas(s.repeated_cycles.count - 1) + " more)" : std::string()) +
        ": read as that cycle");
  if (s.crossing.count == 1)
    warnings.push_back(where(s.crossing.first) + ": skipped a polygon of " + with_commas(s.crossing.first_corners) +
                       " corners whose edges cross or overlap in its best-fit plane: its triangles would need corners "
                       "the file does not have");
  else if (s.crossing.count > 1)
    warnings.push_back(where(s.crossing.first) + ": skipped " + with_commas(s.crossing.count) +
                       " polygons whose edges cross or overlap in their best-fit planes (the first here, of " +
                       with_commas(s.crossing.first_corners) +
                       " corners): their triangles would need corners the file does not have");
}

}  // namespace

TriangleMesh to_triangle_mesh(PolygonSoup&& soup, const std::string& name, std::vector<std::string>& warnings) {
  // Coordinates are rounded to float, as hdm has always read them (assimp's ai_real), so a mesh
  // gives the same bake whatever its format; then widened exactly to double. The float goes
  // through a volatile: GCC 12's vectorizer drops a double -> float -> double round trip at -O2
  // (Eigen's cast) and -O3 (a plain loop), which left some coordinates unrounded in release builds
  // only, so builds of the same source baked different models.
  std::vector<Vec3>& positions = soup.positions;
  for (size_t v = 0; v < positions.size(); ++v) {
    if (!positions[v].allFinite())
      throw InvalidInput(name + ": vertex " + std::to_string(v) + " has a non-finite coordinate");
    for (int a = 0; a < 3; ++a) {
      const volatile float rounded = static_cast<float>(positions[v][a]);
      positions[v][a] = rounded;
    }
    if (!positions[v].allFinite())  // finite as read, beyond float's range once rounded
      throw InvalidInput(name + ": vertex " + std::to_string(v) +
                         " has a coordinate out of range (beyond ±3.4e38, the largest float hdm stores)");
  }

  std::vector<Tri> triangles;
  triangles.reserve(soup.corners.size() / 3 + 1);
  std::vector<std::array<double, 2>> plane;
  std::vector<size_t> border;
  Skipped skipped;
  auto& [short_faces, repeated_corners, repeated_cycles, crossing] = skipped;
  for (size_t p = 0; p < soup.polygon_count(); ++p) {
    int32_t* ids = soup.corners.data() + soup.polygon_end[p];
    size_t k = soup.polygon_end[p + 1] - soup.polygon_end[p];
    if (k > 3) {  // a triangle stays as written (one with a repeated corner is left to repair)
      const CleanCorners c = clean_corners(ids, k, border);
      if (c.dropped) repeated_corners.add(p);
      if (c.repeats > 1 && repeated_cycles.add(p))
        repeated_cycles.first_corners = k, repeated_cycles.first_cycle = c.corners,
        repeated_cycles.first_repeats = c.repeats;
      k = c.corners;
    }
    if (k < 3) {
      short_faces.add(p);
    } else if (triangulate_polygon(positions, ids, k, triangles, plane) == PolygonTriangles::CrossesItself) {
      if (crossing.add(p)) crossing.first_corners = k;
    }
  }

  warnings.insert(warnings.end(), soup.warnings.begin(), soup.warnings.end());
  report_skipped(soup, skipped, name, warnings);

  if (triangles.empty()) {  // say what the file holds instead
    std::string held;
    auto part = [&](uint64_t n, const char* one, const char* many) {
      if (n > 0) held += (held.empty() ? "" : ", ") + plural(n, one, many);
    };
    part(soup.lines, "line element", "line elements");
    part(soup.points, "point element", "point elements");
    part(short_faces.count, "face of fewer than three corners", "faces of fewer than three corners");
    part(crossing.count, "polygon that crosses itself", "polygons that cross themselves");
    if (held.empty()) held = "no faces";
    throw InvalidInput(name + ": holds no triangles: " + held + " (" + plural(positions.size(), "vertex", "vertices") +
                       ")");
  }
  return weld_vertices(positions, triangles);
}

}  // namespace hdm::io::detail
