// SPDX-License-Identifier: MIT
// PLY reader (Turk's Polygon File Format: ASCII, binary little- and big-endian): hdm's own,
// because assimp 5.2 crashes (SIGSEGV) on a binary PLY whose face list has another name than
// vertex_indices, loops forever on a header without end_header and reads past the end of a
// truncated body.
//
// Reads the x, y, z properties of element "vertex" (any scalar type), the list "vertex_indices"
// (or "vertex_index") of element "face" (integer types), and the same list of element "tristrips"
// (triangle strips, -1 or the unsigned type's largest value restarting a strip); every other
// element and property is skipped by its declared type. A header line that starts with no keyword
// of the format (as Blender 2.4's "Created by ...") is skipped with a warning.
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

namespace hdm::io::detail {
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

// The elements and list properties hdm reads.
struct Targets {
  const Element* vertex = nullptr;
  int xyz[3] = {-1, -1, -1};
  const Element* face = nullptr;  // polygons
  int face_list = -1;
  const Element* strips = nullptr;  // triangle strips
  int strip_list = -1;
};

// Appends the triangles of the strip @p ids (-1 restarts it): triangle j of a run is (j, j+1, j+2)
// with every other one turned around, so all keep the strip's winding; a triangle that repeats a
// corner (strips repeat corners to join runs) covers no area and is left out.
void append_strip(const std::vector<int64_t>& ids, PolygonSoup& soup) {
  size_t run = 0;  // corners since the last restart
  for (size_t k = 0; k < ids.size(); ++k) {
    if (ids[k] < 0) {
      run = 0;
      continue;
    }
    if (++run < 3) continue;
    const int64_t a = ids[k - 2], b = ids[k - 1], c = ids[k];
    if (a == b || b == c || a == c) continue;
    const bool odd = (run - 3) % 2 == 1;
    soup.corners.push_back(static_cast<int32_t>(odd ? b : a));
    soup.corners.push_back(static_cast<int32_t>(odd ? a : b));
    soup.corners.push_back(static_cast<int32_t>(c));
    soup.end_polygon();
  }
}

// Reads the @p n vertex ids of list @p prop of instance @p i of element @p e into @p ids, checked
// against the vertex count; with @p restarts, -1 (or the unsigned item type's largest value) is
// kept as -1.
template <class Body>
void read_ids(Body& body, const Property& prop, const Element& e, uint64_t i, uint64_t n, uint64_t vertices,
              bool restarts, const std::string& name, std::vector<int64_t>& ids) {
  const double restart = prop.type == Type::U8    ? 255.0
                         : prop.type == Type::U16 ? 65535.0
                         : prop.type == Type::U32 ? 4294967295.0
                                                  : -1.0;
  ids.clear();
  for (uint64_t k = 0; k < n; ++k) {
    const double id = body.read(prop.type, e, i);
    if (restarts && id == restart) {
      ids.push_back(-1);
    } else if (id >= 0 && id < double(vertices)) {
      ids.push_back(static_cast<int64_t>(id));
    } else {
      throw IoError(name + ": " + e.name + " " + with_commas(i) + " refers to vertex " + integer_text(id) +
                    ", the file has " + with_commas(vertices) + " vertices");
    }
  }
}

template <class Body>
void read_body(Body& body, const std::vector<Element>& elements, const Targets& t, PolygonSoup& soup,
               const std::string& name, uint64_t item_size) {
  std::vector<int64_t> ids;
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
          const bool polygon = &e == t.face && ip == t.face_list, strip = &e == t.strips && ip == t.strip_list;
          if (polygon || strip) {
            read_ids(body, prop, e, i, n, t.vertex->count, strip, name, ids);
            if (strip) {
              append_strip(ids, soup);
            } else {
              for (int64_t id : ids) soup.corners.push_back(static_cast<int32_t>(id));
              soup.end_polygon(body.line());
            }
          } else {
            body.skip(n, prop.type, e, i);
          }
        } else if (&e == t.vertex && (ip == t.xyz[0] || ip == t.xyz[1] || ip == t.xyz[2])) {
          position[ip == t.xyz[0] ? 0 : ip == t.xyz[1] ? 1 : 2] = body.read(prop.type, e, i);
        } else {
          body.skip(1, prop.type, e, i);
        }
      }
      if (&e == t.vertex) soup.positions.push_back(position);
    }
  }
}

// The list of vertex ids of element @p e ("vertex_indices" or "vertex_index"), checked.
int id_list(const Element& e, const std::string& name) {
  int list = find(e, "vertex_indices");
  if (list < 0) list = find(e, "vertex_index");
  if (list < 0 || !e.properties[list].is_list())
    throw IoError(name + ": the PLY " + e.name + " element has no vertex_indices list");
  if (!is_integer(e.properties[list].type))
    throw IoError(name + ": the PLY " + e.name + " list vertex_indices has non-integer items");
  return list;
}

// The elements hdm reads: vertices, and faces or triangle strips (refused when there are neither).
Targets find_targets(const std::vector<Element>& elements, const std::string& name) {
  Targets t;
  for (const Element& e : elements) {
    if (e.name == "vertex" && !t.vertex) t.vertex = &e;
    if (e.name == "face" && !t.face) t.face = &e;
    if (e.name == "tristrips" && !t.strips) t.strips = &e;
  }
  const uint64_t faces = t.face ? t.face->count : 0, strips = t.strips ? t.strips->count : 0;
  if (faces + strips == 0)
    throw InvalidInput(name + ": holds no triangles: " +
                       (t.face     ? std::string("0 faces")
                        : t.strips ? "0 triangle strips"
                                   : "no face element") +
                       " (" + with_commas(t.vertex ? t.vertex->count : 0) + " vertices)");
  if (!t.vertex) throw IoError(name + ": the PLY header declares faces but no vertex element");
  if (faces > 0) t.face_list = id_list(*t.face, name);
  if (strips > 0) t.strip_list = id_list(*t.strips, name);
  for (int a = 0; a < 3; ++a) {
    t.xyz[a] = find(*t.vertex, std::string(1, char('x' + a)));
    if (t.xyz[a] < 0 || t.vertex->properties[t.xyz[a]].is_list())
      throw IoError(name + ": the PLY vertex element has no scalar property " + std::string(1, char('x' + a)));
  }
  if (t.vertex->count > uint64_t(std::numeric_limits<int32_t>::max()))
    throw IoError(name + ": " + with_commas(t.vertex->count) + " vertices: more than hdm's limit of 2,147,483,647");
  return t;
}

// Refuses a header that claims more than the @p left bytes after it can hold, before reading on.
void check_claims(const Header& h, uint64_t left, const std::string& name) {
  uint64_t need = 0;
  for (const Element& e : h.elements) {
    uint64_t least = 0;  // bytes an instance takes at least: its scalars and list counts
    for (const Property& p : e.properties)
      least += h.format == Format::Ascii ? 2 : size_of(p.is_list() ? p.count_type : p.type);
    if (least == 0) continue;
    if (e.count > (left + 1) / least || need + e.count * least > left + 1)
      throw IoError(name + ": the PLY header claims " + with_commas(e.count) + " " + e.name + " elements of at least " +
                    std::to_string(least) + " bytes each, but only " + with_commas(left) +
                    " bytes follow the header: the file is truncated or its header is corrupt");
    need += e.count * least;
  }
}

}  // namespace

PolygonSoup parse_ply(std::string_view bytes, const std::string& name) {
  Header header = parse_header(bytes, name);
  const Targets targets = find_targets(header.elements, name);
  check_claims(header, bytes.size() - header.body_start, name);

  PolygonSoup soup;
  soup.warnings = std::move(header.warnings);
  soup.positions.reserve(targets.vertex->count);
  if (targets.face) soup.polygon_end.reserve(targets.face->count + 1);
  if (header.format == Format::Ascii) {
    AsciiBody body(bytes, header.body_start, header.body_line, name);
    read_body(body, header.elements, targets, soup, name, 2);  // a list item takes a digit and a space
  } else {
    BinaryBody body(bytes, header.body_start, header.format == Format::BinaryBig, name);
    read_body(body, header.elements, targets, soup, name, 0);  // 0: the item type's size
  }
  return soup;
}

}  // namespace hdm::io::detail
