// SPDX-License-Identifier: MIT
#pragma once
// Internal to hdm::io: the header of a PLY file (Turk's Polygon File Format), parsed by
// ply_header.cpp for read_ply.cpp.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace hdm::io::detail::ply {

/// A scalar type of the format; None for a name that is not one.
enum class Type : uint8_t { None, I8, U8, I16, U16, I32, U32, F32, F64 };
/// Bytes of a binary scalar of type @p t (0 for None).
uint64_t size_of(Type t);
/// Whether @p t is one of the integer types.
inline bool is_integer(Type t) { return t != Type::F32 && t != Type::F64 && t != Type::None; }

struct Property {
  std::string name;
  Type type = Type::None;        ///< scalar type, or the list's item type
  Type count_type = Type::None;  ///< the list's count type; None for a scalar
  bool is_list() const { return count_type != Type::None; }
};
struct Element {
  std::string name;
  uint64_t count = 0;
  std::vector<Property> properties;
};

enum class Format { Ascii, BinaryLittle, BinaryBig };

struct Header {
  std::vector<Element> elements;  ///< in file order
  Format format = Format::Ascii;
  size_t body_start = 0;              ///< offset of the first byte after the end_header line
  int64_t body_line = 0;              ///< the file's line number there (for ASCII bodies)
  std::vector<std::string> warnings;  ///< header lines skipped: "<name>:<line>: ..."
};

/// @brief Parses the header of the PLY file @p bytes, up to its end_header line (found first, so
/// binary data is never read as header). Lines "comment" and "obj_info" and blank lines are
/// skipped; a line that starts with no keyword of the format is skipped with a warning (the first
/// five each, the rest counted in one).
/// @throws IoError "<name>[:<line>]: <reason>" when the file does not start with "ply", has no
/// end_header or format line, or a format, element or property line is malformed.
/// @note O(header size).
Header parse_header(std::string_view bytes, const std::string& name);

}  // namespace hdm::io::detail::ply
