// SPDX-License-Identifier: MIT
// The header of a PLY file: format, elements and their properties, up to end_header.
#include "ply_header.h"
#include "text_cursor.h"

#include <hdm/core/error.h>

namespace hdm::io::detail::ply {
namespace {

Type type_named(std::string_view t) {
  if (t == "char" || t == "int8") return Type::I8;
  if (t == "uchar" || t == "uint8") return Type::U8;
  if (t == "short" || t == "int16") return Type::I16;
  if (t == "ushort" || t == "uint16") return Type::U16;
  if (t == "int" || t == "int32") return Type::I32;
  if (t == "uint" || t == "uint32") return Type::U32;
  if (t == "float" || t == "float32") return Type::F32;
  if (t == "double" || t == "float64") return Type::F64;
  return Type::None;
}
}  // namespace

uint64_t size_of(Type t) {
  switch (t) {
    case Type::I8:
    case Type::U8:
      return 1;
    case Type::I16:
    case Type::U16:
      return 2;
    case Type::I32:
    case Type::U32:
    case Type::F32:
      return 4;
    case Type::F64:
      return 8;
    case Type::None:
      break;
  }
  return 0;
}

Header parse_header(std::string_view bytes, const std::string& name) {
  TextCursor in(bytes, name);
  if (in.token() != "ply" || !in.at_line_end())
    throw IoError(name + ": not a PLY file (the first line is not \"ply\")");
  // The header's end, found first so that binary data is never read as header.
  size_t header_end = 0;
  for (size_t at = bytes.find("\nend_header"); at != std::string_view::npos; at = bytes.find("\nend_header", at + 1)) {
    const size_t after = at + 11;
    size_t k = after;
    while (k < bytes.size() && (bytes[k] == ' ' || bytes[k] == '\t' || bytes[k] == '\r')) ++k;
    if (k >= bytes.size() || bytes[k] == '\n') {
      header_end = after;
      break;
    }
  }
  if (header_end == 0) throw IoError(name + ": truncated or corrupt (the PLY header has no end_header line)");
  Header h;
  std::vector<Element>& elements = h.elements;
  Format& format = h.format;
  bool have_format = false, ended = false;
  uint64_t skipped = 0;  // lines of no keyword
  while (in.next_line() && in.position() < header_end) {
    const std::string_view key = in.token();
    auto malformed = [&](const std::string& why) { in.fail("malformed PLY header line (" + why + ")"); };
    if (key == "end_header") {
      ended = true;
      break;
    } else if (key == "comment" || key == "obj_info" || key.empty()) {
      continue;
    } else if (key == "format") {
      const std::string_view f = in.token();
      if (f == "ascii")
        format = Format::Ascii;
      else if (f == "binary_little_endian")
        format = Format::BinaryLittle;
      else if (f == "binary_big_endian")
        format = Format::BinaryBig;
      else
        in.fail("unknown PLY format " + quoted(f) + " (ascii, binary_little_endian or binary_big_endian)");
      have_format = true;
    } else if (key == "element") {
      Element e;
      e.name = std::string(in.token());
      const std::string_view c = in.token();
      int64_t count = 0;
      if (e.name.empty() || !parse_int(c, count) || count < 0) malformed("element needs a name and a count");
      e.count = static_cast<uint64_t>(count);
      elements.push_back(std::move(e));
    } else if (key == "property") {
      if (elements.empty()) malformed("a property before any element");
      Property prop;
      const std::string_view t = in.token();
      if (t == "list") {
        prop.count_type = type_named(in.token());
        prop.type = type_named(in.token());
        if (prop.count_type == Type::None || !is_integer(prop.count_type) || prop.type == Type::None)
          malformed("a list needs an integer count type and an item type");
      } else {
        prop.type = type_named(t);
        if (prop.type == Type::None) malformed("unknown property type " + quoted(t));
      }
      prop.name = std::string(in.token());
      if (prop.name.empty()) malformed("a property without a name");
      elements.back().properties.push_back(std::move(prop));
    } else if (++skipped <= 5) {  // a line of another program's own, such as Blender 2.4's "Created by ..."
      std::string_view line = bytes.substr(static_cast<size_t>(key.data() - bytes.data()));
      line = line.substr(0, line.find('\n'));
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      h.warnings.push_back(name + ":" + std::to_string(in.line()) + ": skipped the PLY header line " + quoted(line) +
                           ": it starts with no keyword of the format");
    }
  }
  if (!ended) throw IoError(name + ": truncated (the PLY header has no end_header line)");
  if (!have_format) throw IoError(name + ": the PLY header has no format line");
  if (skipped > 5)
    h.warnings.push_back(name + ": skipped " + with_commas(skipped - 5) +
                         " more PLY header lines that start with no keyword of the format");
  in.next_line();
  h.body_start = in.position();
  h.body_line = in.line();
  return h;
}

}  // namespace hdm::io::detail::ply
