// SPDX-License-Identifier: MIT
// OFF reader (Geomview's Object File Format, as written by CGAL, MeshLab and Geomview): hdm's own,
// because assimp 5.2 allocates whatever the header claims (a 66-byte file claiming 4,999,999,999
// faces took 38 s and 11 GB), clamps out-of-range vertex ids to the last vertex and silently drops
// faces of more than nine corners.
//
// Accepted: an optional header keyword [ST][C][N][4][n]OFF (the prefixes add per-vertex texture
// coordinates, colours, normals, a homogeneous coordinate, a dimension line), the counts
// "#V #F [#E]", then one vertex per line (x y z [w], anything after is ignored) and one face per
// line ("k i1 ... ik", anything after, e.g. a colour, is ignored); '#' starts a comment.
#include "polygon_soup.h"
#include "text_cursor.h"

#include <algorithm>
#include <cstdint>
#include <limits>

namespace hdm::io::detail {
namespace {

// Smallest number of bytes a vertex line ("x y z" and its line end) and a face line ("k i" and
// its line end) take: no header can claim more elements than the rest of the file can hold.
constexpr uint64_t min_vertex_bytes = 6, min_face_bytes = 4;

int64_t read_count(TextCursor& in, const char* what) {
  const std::string_view t = in.token(true);
  int64_t n = 0;
  if (t.empty()) in.fail(std::string("the OFF header ends before its ") + what + " count");
  if (!parse_int(t, n) || n < 0)
    in.fail(std::string("the OFF header's ") + what + " count " + quoted(t) + " is not a non-negative integer");
  return n;
}

}  // namespace

PolygonSoup parse_off(std::string_view bytes, const std::string& name) {
  TextCursor in(bytes, name);
  if (!in.next_content_line()) throw IoError(name + ": empty file (no OFF header)");

  // Header keyword: [ST][C][N][4][n]OFF, optional.
  bool homogeneous = false, dimension_line = false;
  std::string_view key = in.token(true);
  std::string_view k = key;
  if (k.substr(0, 2) == "ST") k.remove_prefix(2);
  if (!k.empty() && k[0] == 'C') k.remove_prefix(1);
  if (!k.empty() && k[0] == 'N') k.remove_prefix(1);
  if (!k.empty() && k[0] == '4') homogeneous = true, k.remove_prefix(1);
  if (!k.empty() && k[0] == 'n') dimension_line = true, k.remove_prefix(1);
  if (k == "OFF") {
    if (in.at_line_end()) {
      if (!in.next_line() || !in.next_content_line()) in.fail("the file ends after the OFF keyword (no counts)");
    } else {
      const std::string_view rest = in.token(true);
      if (rest == "BINARY") in.fail("binary OFF is not supported (write it as text OFF, PLY or STL)");
      in.unread(rest);
    }
  } else {
    int64_t ignored = 0;
    if (!parse_int(key, ignored)) in.fail("not an OFF file (expected the keyword OFF, found " + quoted(key) + ")");
    in.unread(key);  // no keyword: the counts come first
    homogeneous = dimension_line = false;
  }
  if (dimension_line) {
    const int64_t dim = read_count(in, "dimension");
    if (dim != 3) in.fail("nOFF with dimension " + std::to_string(dim) + " (hdm reads 3-dimensional meshes)");
    if (in.at_line_end() && (!in.next_line() || !in.next_content_line())) in.fail("the file ends before the counts");
  }
  const int64_t nv = read_count(in, "vertex");
  if (in.at_line_end() && (!in.next_line() || !in.next_content_line()))
    in.fail("the OFF header ends before its face count");
  const int64_t nf = read_count(in, "face");
  in.next_line();  // the edge count, if any, is not used

  // Refuse, before reading further, a header that claims more than the file can hold.
  const uint64_t left = in.bytes_left();
  const uint64_t need_v = static_cast<uint64_t>(nv), need_f = static_cast<uint64_t>(nf);
  if (need_v > (left + 1) / min_vertex_bytes || need_f > (left + 1) / min_face_bytes ||
      need_v * min_vertex_bytes + need_f * min_face_bytes > left + 2)
    throw IoError(name + ": the OFF header claims " + with_commas(need_v) + " vertices and " + with_commas(need_f) +
                  " faces, but only " + with_commas(left) + " bytes follow it (a vertex line takes at least " +
                  std::to_string(min_vertex_bytes) + " bytes, a face line " + std::to_string(min_face_bytes) +
                  "): the file is truncated or its header is corrupt");
  if (nv > std::numeric_limits<int32_t>::max())
    throw IoError(name + ": " + with_commas(need_v) + " vertices: more than hdm's limit of 2,147,483,647");

  PolygonSoup soup;
  soup.positions.reserve(static_cast<size_t>(nv));
  soup.polygon_end.reserve(static_cast<size_t>(nf) + 1);
  for (int64_t v = 0; v < nv; ++v) {
    if (!in.next_content_line())
      in.fail("the file ends after " + with_commas(v) + " of the " + with_commas(need_v) +
              " vertices its header claims");
    double c[4] = {0, 0, 0, 1};
    for (int d = 0; d < (homogeneous ? 4 : 3); ++d) {
      const std::string_view t = in.token(true);
      if (t.empty())
        in.fail("vertex " + std::to_string(v) + " has " + std::to_string(d) + " coordinates, expected " +
                (homogeneous ? "4" : "3"));
      if (!parse_double(t, c[d])) in.fail("vertex " + std::to_string(v) + ": " + quoted(t) + " is not a number");
    }
    soup.positions.emplace_back(c[0] / c[3], c[1] / c[3], c[2] / c[3]);
    in.next_line();
  }
  for (int64_t f = 0; f < nf; ++f) {
    if (!in.next_content_line())
      in.fail("the file ends after " + with_commas(f) + " of the " + with_commas(need_f) + " faces its header claims");
    const std::string_view count = in.token(true);
    int64_t corners = 0;
    if (!parse_int(count, corners) || corners < 0)
      in.fail("face " + std::to_string(f) + ": its corner count " + quoted(count) + " is not a non-negative integer");
    if (corners == 0) in.fail("face " + std::to_string(f) + " has no corners");
    if (static_cast<uint64_t>(corners) > in.bytes_left() / 2)
      in.fail("face " + std::to_string(f) + " claims " + with_commas(static_cast<uint64_t>(corners)) +
              " corners, more than the rest of the file can hold");
    for (int64_t j = 0; j < corners; ++j) {
      const std::string_view t = in.token(true);
      int64_t id = 0;
      if (t.empty())
        in.fail("face " + std::to_string(f) + " lists " + std::to_string(j) + " of its " + std::to_string(corners) +
                " corners");
      if (!parse_int(t, id)) in.fail("face " + std::to_string(f) + ": corner " + quoted(t) + " is not an integer");
      if (id < 0 || id >= nv)
        in.fail("face " + std::to_string(f) + " refers to vertex " + std::to_string(id) + ", the file has " +
                with_commas(need_v) + " vertices (0 to " + std::to_string(nv - 1) + ")");
      soup.corners.push_back(static_cast<int32_t>(id));
    }
    soup.end_polygon(in.line());
    in.next_line();
  }
  return soup;
}

}  // namespace hdm::io::detail
