// SPDX-License-Identifier: MIT
// PLY reader (Turk's Polygon File Format: ASCII, binary little- and big-endian): hdm's own,
// because assimp 5.2 crashes (SIGSEGV) on a binary PLY whose face list has another name than
// vertex_indices, loops forever on a header without end_header and reads past the end of a
// truncated body.
//
// Reads the x, y, z properties of element "vertex" (any scalar type) and the list "vertex_indices"
// (or "vertex_index") of element "face" (integer types); every other element and property is
// skipped by its declared type. A header line that starts with no keyword of the format (as
// Blender 2.4's "Created by ...") is skipped with a warning.
#include "ply_header.h"
#include "polygon_soup.h"
#include "text_cursor.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace hdm::detail {
namespace {

using namespace ply;

// Binary body: reads scalars of the declared types and endianness, never past the end.
class BinaryBody {
 public:
  BinaryBody(std::string_view bytes, size_t start, bool big, const std::string& name)
      : bytes_(bytes), pos_(start), big_(big), name_(name) {}
  uint64_t left() const { return bytes_.size() - pos_; }
  int64_t line() const { return 0; }  // no lines in binary data
  void skip(uint64_t n, Type t, const Element& e, uint64_t i) {
    if (n > left() / size_of(t)) truncated(e, i);
    pos_ += n * size_of(t);
  }
  // The value of a scalar of type @p t, as double (exact for every PLY integer type).
  double read(Type t, const Element& e, uint64_t i) {
    const uint64_t n = size_of(t);
    if (n > left()) truncated(e, i);
    uint64_t bits = 0;
    for (uint64_t k = 0; k < n; ++k)
      bits |= uint64_t(static_cast<uint8_t>(bytes_[pos_ + (big_ ? n - 1 - k : k)])) << (8 * k);
    pos_ += n;
    switch (t) {
      case Type::I8:
        return static_cast<int8_t>(bits);
      case Type::U8:
        return static_cast<uint8_t>(bits);
      case Type::I16:
        return static_cast<int16_t>(bits);
      case Type::U16:
        return static_cast<uint16_t>(bits);
      case Type::I32:
        return static_cast<int32_t>(bits);
      case Type::U32:
        return static_cast<uint32_t>(bits);
      case Type::F32:
        return std::bit_cast<float>(static_cast<uint32_t>(bits));
      case Type::F64:
        return std::bit_cast<double>(bits);
      case Type::None:
        break;
    }
    return 0;
  }
  [[noreturn]] void truncated(const Element& e, uint64_t i) const {
    throw IoError(name_ + ": truncated (the PLY data ends inside " + e.name + " " + with_commas(i) + " of " +
                  with_commas(e.count) + ")");
  }

 private:
  std::string_view bytes_;
  size_t pos_;
  bool big_;
  const std::string& name_;
};

// ASCII body: whitespace-separated numbers.
class AsciiBody {
 public:
  AsciiBody(std::string_view bytes, size_t start, int64_t first_line, const std::string& name)
      : in_(bytes.substr(start), name), first_line_(first_line) {}
  uint64_t left() const { return in_.bytes_left(); }
  int64_t line() const { return first_line_ + in_.line() - 1; }
  double read(Type t, const Element& e, uint64_t i) {
    in_.skip_space(false);
    const std::string_view token = in_.token();
    if (token.empty())
      throw IoError(in_.name() + ": truncated (the PLY data ends inside " + e.name + " " + with_commas(i) + " of " +
                    with_commas(e.count) + ")");
    double v = 0;
    if (!parse_double(token, v) || (is_integer(t) && v != std::floor(v)))
      throw IoError(in_.name() + ": " + e.name + " " + with_commas(i) + ": " + quoted(token) + " is not " +
                    (is_integer(t) ? "an integer" : "a number"));
    return v;
  }
  void skip(uint64_t n, Type t, const Element& e, uint64_t i) {
    for (uint64_t k = 0; k < n; ++k) read(t, e, i);
  }

 private:
  TextCursor in_;
  int64_t first_line_;  // the file's line of the body's first line
};

// Index of the property @p name in @p e, or -1.
int find(const Element& e, std::string_view name) {
  for (size_t k = 0; k < e.properties.size(); ++k)
    if (e.properties[k].name == name) return static_cast<int>(k);
  return -1;
}

template <class Body>
void read_body(Body& body, const std::vector<Element>& elements, const Element* vertex, const int xyz[3],
               const Element* face, int indices, PolygonSoup& soup, const std::string& name, uint64_t item_size) {
  for (const Element& e : elements) {
    if (e.properties.empty()) continue;  // nothing to read, whatever the count
    for (uint64_t i = 0; i < e.count; ++i) {
      Vec3 position = Vec3::Zero();
      for (size_t p = 0; p < e.properties.size(); ++p) {
        const Property& prop = e.properties[p];
        const int ip = static_cast<int>(p);
        if (prop.is_list()) {
          const double count = body.read(prop.count_type, e, i);
          const uint64_t item_bytes = item_size ? item_size : size_of(prop.type);
          if (!(count >= 0) || count > double(body.left() / item_bytes))
            throw IoError(name + ": " + e.name + " " + with_commas(i) + " has a list of " + integer_text(count) +
                          " items, more than the rest of the file can hold (truncated or corrupt)");
          const auto n = static_cast<uint64_t>(count);
          if (&e == face && ip == indices) {
            for (uint64_t k = 0; k < n; ++k) {
              const double id = body.read(prop.type, e, i);
              if (!(id >= 0 && id < double(vertex->count)))
                throw IoError(name + ": face " + with_commas(i) + " refers to vertex " + integer_text(id) +
                              ", the file has " + with_commas(vertex->count) + " vertices");
              soup.corners.push_back(static_cast<int32_t>(id));
            }
            soup.end_polygon(body.line());
          } else {
            body.skip(n, prop.type, e, i);
          }
        } else if (&e == vertex && (ip == xyz[0] || ip == xyz[1] || ip == xyz[2])) {
          position[ip == xyz[0] ? 0 : ip == xyz[1] ? 1 : 2] = body.read(prop.type, e, i);
        } else {
          body.skip(1, prop.type, e, i);
        }
      }
      if (&e == vertex) soup.positions.push_back(position);
    }
  }
}

}  // namespace

PolygonSoup parse_ply(std::string_view bytes, const std::string& name) {
  Header header = parse_header(bytes, name);
  const std::vector<Element>& elements = header.elements;
  const Format format = header.format;
  const size_t body_start = header.body_start;

  // ---- the elements hdm reads ----
  const Element* vertex = nullptr;
  const Element* face = nullptr;
  int xyz[3] = {-1, -1, -1}, indices = -1;
  for (const Element& e : elements) {
    if (e.name == "vertex" && !vertex) vertex = &e;
    if (e.name == "face" && !face) face = &e;
  }
  if (!face || face->count == 0) {
    for (const Element& e : elements)
      if (e.name == "tristrips" && e.count > 0)
        throw InvalidInput(name + ": holds triangle strips (element tristrips), which hdm does not read; only faces");
    throw InvalidInput(name + ": holds no triangles: " + std::string(face ? "0 faces" : "no face element") + " (" +
                       with_commas(vertex ? vertex->count : 0) + " vertices)");
  }
  indices = find(*face, "vertex_indices");
  if (indices < 0) indices = find(*face, "vertex_index");
  if (indices < 0 || !face->properties[indices].is_list())
    throw IoError(name + ": the PLY face element has no vertex_indices list");
  if (!is_integer(face->properties[indices].type))
    throw IoError(name + ": the PLY face list vertex_indices has non-integer items");
  if (!vertex) throw IoError(name + ": the PLY header declares faces but no vertex element");
  for (int a = 0; a < 3; ++a) {
    xyz[a] = find(*vertex, std::string(1, char('x' + a)));
    if (xyz[a] < 0 || vertex->properties[xyz[a]].is_list())
      throw IoError(name + ": the PLY vertex element has no scalar property " + std::string(1, char('x' + a)));
  }
  if (vertex->count > uint64_t(std::numeric_limits<int32_t>::max()))
    throw IoError(name + ": " + with_commas(vertex->count) + " vertices: more than hdm's limit of 2,147,483,647");

  // ---- refuse a header that claims more than the file can hold, before reading further ----
  const uint64_t left = bytes.size() - body_start;
  uint64_t need = 0;
  for (const Element& e : elements) {
    uint64_t least = 0;  // bytes an instance takes at least: its scalars and list counts
    for (const Property& p : e.properties)
      least += format == Format::Ascii ? 2 : size_of(p.is_list() ? p.count_type : p.type);
    if (least == 0) continue;
    if (e.count > (left + 1) / least || need + e.count * least > left + 1)
      throw IoError(name + ": the PLY header claims " + with_commas(e.count) + " " + e.name + " elements of at least " +
                    std::to_string(least) + " bytes each, but only " + with_commas(left) +
                    " bytes follow the header: the file is truncated or its header is corrupt");
    need += e.count * least;
  }

  PolygonSoup soup;
  soup.warnings = std::move(header.warnings);
  soup.positions.reserve(vertex->count);
  soup.polygon_end.reserve(face->count + 1);
  if (format == Format::Ascii) {
    AsciiBody body(bytes, body_start, header.body_line, name);
    read_body(body, elements, vertex, xyz, face, indices, soup, name, 2);  // a list item takes a digit and a space
  } else {
    BinaryBody body(bytes, body_start, format == Format::BinaryBig, name);
    read_body(body, elements, vertex, xyz, face, indices, soup, name, 0);  // 0: the item type's size
  }
  return soup;
}

}  // namespace hdm::detail
