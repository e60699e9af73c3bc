// SPDX-License-Identifier: MIT
// Wavefront OBJ reader for polygon meshes: hdm's own, because assimp 5.2's OBJ parser has open
// heap overflows found by OSS-Fuzz (assimp issues #4770, #4923 in ObjFileParser::getFace, #4925 in
// ObjFileImporter::createVertexArray), which an uninstrumented library cannot show us.
//
// Reads "v x y z" (a fourth value or a vertex colour after x y z is ignored) and "f" corners
// "v", "v/vt", "v//vn", "v/vt/vn" with 1-based or negative (relative) vertex indices; "l" and "p"
// elements (lines and points) are skipped, with one warning giving their counts; every other
// statement (vt, vn, g, o, s, usemtl, mtllib, ...) is skipped. A line ending in '\' continues on
// the next line; '#' starts a comment. UTF-16 text (with or without a byte-order mark) is read as
// its UTF-8 transcoding, and a UTF-8 byte-order mark is skipped.
#include "polygon_soup.h"
#include "text_cursor.h"
#include "text_encoding.h"

#include <cstdint>
#include <limits>
#include <optional>
#include <string>

namespace hdm::io::detail {
namespace {

// Splits @p line into whitespace-separated tokens, one at a time.
struct Tokens {
  std::string_view rest;
  std::string_view next() {
    size_t a = 0;
    while (a < rest.size() &&
           (rest[a] == ' ' || rest[a] == '\t' || rest[a] == '\r' || rest[a] == '\v' || rest[a] == '\f'))
      ++a;
    size_t b = a;
    while (b < rest.size() &&
           !(rest[b] == ' ' || rest[b] == '\t' || rest[b] == '\r' || rest[b] == '\v' || rest[b] == '\f'))
      ++b;
    const std::string_view t = rest.substr(a, b - a);
    rest.remove_prefix(b);
    return t;
  }
};

[[noreturn]] void obj_fail(const std::string& name, int64_t line, const std::string& reason) {
  throw IoError(name + ":" + std::to_string(line) + ": " + reason);
}

// The logical lines of an OBJ file: physical lines joined while they end in '\', without
// comments and trailing blanks.
class LogicalLines {
 public:
  explicit LogicalLines(std::string_view bytes) : bytes_(bytes) {}
  // The next logical line, false at the end; @p first_line is where it starts (1-based).
  bool next(std::string_view& line, int64_t& first_line) {
    if (pos_ >= bytes_.size()) return false;
    first_line = line_no_ + 1;
    line = physical();
    if (!line.empty() && line.back() == '\\') {
      joined_.assign(line.substr(0, line.size() - 1));
      while (pos_ < bytes_.size()) {
        const std::string_view more = physical();
        const bool again = !more.empty() && more.back() == '\\';
        joined_ += ' ';
        joined_.append(again ? more.substr(0, more.size() - 1) : more);
        if (!again) break;
      }
      line = joined_;
    }
    return true;
  }

 private:
  std::string_view physical() {
    ++line_no_;
    size_t end = bytes_.find('\n', pos_);
    if (end == std::string_view::npos) end = bytes_.size();
    std::string_view line = bytes_.substr(pos_, end - pos_);
    pos_ = end + 1;
    if (const size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t')) line.remove_suffix(1);
    return line;
  }

  std::string_view bytes_;
  size_t pos_ = 0;
  int64_t line_no_ = 0;
  std::string joined_;  // a logical line made of continued physical lines
};

}  // namespace

PolygonSoup parse_obj(std::string_view file_bytes, const std::string& name) {
  const std::optional<std::string> utf8 = utf16_to_utf8(file_bytes, name);
  LogicalLines lines(without_utf8_bom(utf8 ? std::string_view(*utf8) : file_bytes));
  PolygonSoup soup;
  int64_t first_line = 0, max_ref = -1, max_ref_line = 0, first_skipped_line = 0;
  auto fail = [&](int64_t line, const std::string& reason) { obj_fail(name, line, reason); };
  std::string_view line;
  while (lines.next(line, first_line)) {
    Tokens tokens{line};
    const std::string_view key = tokens.next();
    if (key == "v") {
      double c[3] = {0, 0, 0};
      for (int d = 0; d < 3; ++d) {
        const std::string_view t = tokens.next();
        if (t.empty())
          fail(first_line, "vertex " + std::to_string(soup.positions.size()) + " has " + std::to_string(d) +
                               " coordinates, expected 3");
        if (!parse_double(t, c[d]))
          fail(first_line, "vertex " + std::to_string(soup.positions.size()) + ": " + quoted(t) + " is not a number");
      }
      if (soup.positions.size() >= size_t(std::numeric_limits<int32_t>::max()))
        fail(first_line, "more than hdm's limit of 2,147,483,647 vertices");
      soup.positions.emplace_back(c[0], c[1], c[2]);
    } else if (key == "f" || key == "fo") {
      const int64_t nv = static_cast<int64_t>(soup.positions.size());
      for (std::string_view t = tokens.next(); !t.empty(); t = tokens.next()) {
        const std::string_view v = t.substr(0, t.find('/'));
        int64_t id = 0;
        if (!parse_int(v, id) || id == 0)
          fail(first_line, "face corner " + quoted(t) + " is not a vertex index (1-based, or negative to count back)");
        if (id < 0) {
          if (id < -nv)
            fail(first_line, "face corner " + std::to_string(id) + " counts back past the first vertex (" +
                                 std::to_string(nv) + " vertices so far)");
          id += nv;
        } else {
          id -= 1;  // 1-based; may refer to a vertex defined further on, checked at the end
          if (id >= std::numeric_limits<int32_t>::max())
            fail(first_line,
                 "face refers to vertex " + std::to_string(id + 1) + ", more than hdm's limit of 2,147,483,647");
          if (id > max_ref) max_ref = id, max_ref_line = first_line;
        }
        soup.corners.push_back(static_cast<int32_t>(id));
      }
      soup.end_polygon(first_line);
    } else if (key == "l" || key == "p") {
      ++(key == "l" ? soup.lines : soup.points);
      if (first_skipped_line == 0) first_skipped_line = first_line;
    }
  }
  if (soup.lines + soup.points > 0) {
    std::string what;
    if (soup.lines > 0) what = with_commas(soup.lines) + (soup.lines == 1 ? " line element (l)" : " line elements (l)");
    if (soup.lines > 0 && soup.points > 0) what += " and ";
    if (soup.points > 0)
      what += with_commas(soup.points) + (soup.points == 1 ? " point element (p)" : " point elements (p)");
    soup.warnings.push_back(name + ":" + std::to_string(first_skipped_line) + ": skipped " + what +
                            (soup.lines + soup.points > 1 ? " (the first here)" : "") +
                            ": they bound no area, hdm reads faces");
  }
  if (max_ref >= static_cast<int64_t>(soup.positions.size()))
    fail(max_ref_line, "face refers to vertex " + std::to_string(max_ref + 1) + ", the file has " +
                           with_commas(soup.positions.size()) + " vertices");
  return soup;
}

}  // namespace hdm::io::detail
