// SPDX-License-Identifier: MIT
// STL reader (binary and ASCII stereolithography): hdm's own, because assimp 5.2's ASCII reader
// only logs a facet of four vertices and drops the fourth one (a silently wrong mesh), and because
// an uninstrumented library's memory errors cannot be seen by our fuzzers.
//
// Binary: an 80-byte header, a uint32 triangle count n, then n records of 12 float32 (normal,
// three corners) and a uint16 attribute; the file must hold all n records (trailing bytes are
// ignored unless the file starts with "solid"). ASCII: one or more "solid [name] ... endsolid
// [name]" blocks of "facet normal nx ny nz / outer loop / vertex x y z (three times) / endloop /
// endfacet" (keywords in any case). A file is binary when its size is exactly 84 + 50·n, when it
// does not start with "solid", or when it does but holds control bytes (then its size must cover
// the n records). Normals and attributes are ignored.
#include "polygon_soup.h"
#include "text_cursor.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>

namespace hdm::io::detail {
namespace {

constexpr uint64_t header_bytes = 84, record_bytes = 50;

bool same_word(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (size_t k = 0; k < a.size(); ++k)
    if ((a[k] | 0x20) != b[k]) return false;  // b is lower case letters
  return true;
}

float float_at(std::string_view bytes, size_t pos) {
  uint32_t bits = 0;
  for (int k = 0; k < 4; ++k) bits |= uint32_t(static_cast<uint8_t>(bytes[pos + k])) << (8 * k);
  return std::bit_cast<float>(bits);
}

PolygonSoup parse_binary(std::string_view bytes, const std::string& name) {
  uint32_t n = 0;
  for (int k = 0; k < 4; ++k) n |= uint32_t(static_cast<uint8_t>(bytes[80 + k])) << (8 * k);
  const uint64_t need = header_bytes + record_bytes * uint64_t(n);
  if (bytes.size() < need)
    throw IoError(name + ": the binary STL header claims " + with_commas(n) + " triangles (" + with_commas(need) +
                  " bytes), but the file has " + with_commas(bytes.size()) + " bytes: truncated or corrupt");
  if (uint64_t(n) * 3 > uint64_t(std::numeric_limits<int32_t>::max()))
    throw IoError(name + ": " + with_commas(n) + " triangles: more than hdm's limit of 715,827,882");
  PolygonSoup soup;
  soup.positions.reserve(size_t(n) * 3);
  soup.corners.reserve(size_t(n) * 3);
  soup.polygon_end.reserve(size_t(n) + 1);
  for (uint64_t t = 0; t < n; ++t) {
    const size_t record = header_bytes + record_bytes * t;
    for (int c = 0; c < 3; ++c) {
      const size_t at = record + 12 + 12 * c;
      soup.corners.push_back(static_cast<int32_t>(soup.positions.size()));
      soup.positions.emplace_back(float_at(bytes, at), float_at(bytes, at + 4), float_at(bytes, at + 8));
    }
    soup.end_polygon();
  }
  return soup;
}

PolygonSoup parse_ascii(std::string_view bytes, const std::string& name) {
  TextCursor in(bytes, name);
  PolygonSoup soup;
  auto next = [&] {
    in.skip_space(false);
    return in.token();
  };
  auto expect = [&](std::string_view word, const char* where) {
    const std::string_view t = next();
    if (t.empty())
      in.fail(std::string("truncated (the file ends ") + where + ", expected \"" + std::string(word) + "\")");
    if (!same_word(t, word))
      in.fail(std::string("expected \"") + std::string(word) + "\" " + where + ", found " + quoted(t));
  };
  auto number = [&](const char* what) {
    const std::string_view t = next();
    double v = 0;
    if (t.empty()) in.fail(std::string("truncated (the file ends inside ") + what + ")");
    if (!parse_double(t, v)) in.fail(std::string(what) + ": " + quoted(t) + " is not a number");
    return v;
  };
  expect("solid", "at the start");
  in.next_line();  // the solid's name, if any
  for (;;) {
    const std::string_view key = next();
    if (key.empty()) in.fail("truncated (the file ends before endsolid)");
    if (same_word(key, "endsolid")) {
      in.next_line();  // the name, if any
      in.skip_space(false);
      if (in.at_end()) break;
      expect("solid", "after endsolid");  // another solid follows
      in.next_line();
      continue;
    }
    if (!same_word(key, "facet")) in.fail("expected \"facet\" or \"endsolid\", found " + quoted(key));
    const std::string facet = "facet " + with_commas(soup.polygon_count());
    expect("normal", "after \"facet\"");
    for (int k = 0; k < 3; ++k) number("a facet normal");
    expect("outer", ("in " + facet).c_str());
    expect("loop", ("in " + facet).c_str());
    for (int c = 0;; ++c) {
      const std::string_view t = next();
      if (t.empty()) in.fail("truncated (the file ends inside " + facet + ")");
      if (same_word(t, "endloop")) {
        if (c != 3) in.fail(facet + " has " + std::to_string(c) + " vertices, expected 3");
        break;
      }
      if (!same_word(t, "vertex")) in.fail("expected \"vertex\" or \"endloop\" in " + facet + ", found " + quoted(t));
      if (c >= 3) in.fail(facet + " has more than 3 vertices");
      const double x = number("a vertex"), y = number("a vertex"), z = number("a vertex");
      if (soup.positions.size() >= size_t(std::numeric_limits<int32_t>::max()))
        in.fail("more than hdm's limit of 2,147,483,647 vertices");
      soup.corners.push_back(static_cast<int32_t>(soup.positions.size()));
      soup.positions.emplace_back(x, y, z);
    }
    expect("endfacet", ("after " + facet).c_str());
    soup.end_polygon();
  }
  return soup;
}

}  // namespace

PolygonSoup parse_stl(std::string_view bytes, const std::string& name) {
  size_t first = 0;
  while (first < bytes.size() &&
         (bytes[first] == ' ' || bytes[first] == '\t' || bytes[first] == '\r' || bytes[first] == '\n'))
    ++first;
  const bool solid = bytes.size() - first >= 5 && same_word(bytes.substr(first, 5), "solid");
  if (bytes.size() >= header_bytes) {
    uint32_t n = 0;
    for (int k = 0; k < 4; ++k) n |= uint32_t(static_cast<uint8_t>(bytes[80 + k])) << (8 * k);
    if (!solid || bytes.size() == header_bytes + record_bytes * uint64_t(n)) return parse_binary(bytes, name);
  }
  if (!solid)
    throw IoError(name + ": not an STL file (" + with_commas(bytes.size()) +
                  " bytes: too short for a binary STL, and no \"solid\" keyword)");
  // Some exporters start a binary header with "solid": if the text holds control bytes, say that
  // its size does not match its triangle count rather than report an ASCII syntax error.
  if (bytes.size() >= header_bytes) {
    const std::string_view head = bytes.substr(0, std::min<size_t>(bytes.size(), 1024));
    const bool binary = std::any_of(head.begin(), head.end(), [](char c) {
      const auto u = static_cast<unsigned char>(c);
      return u < 0x09 || (u > 0x0d && u < 0x20) || u == 0x7f;
    });
    if (binary) return parse_binary(bytes, name);
  }
  return parse_ascii(bytes, name);
}

}  // namespace hdm::io::detail
