// SPDX-License-Identifier: MIT
// Which reader a mesh file goes to: by its extension, or, without one, by its first bytes.
#include "mesh_format.h"

#include <cctype>
#include <cstdint>
#include <filesystem>

namespace hdm::io::detail {
namespace {

bool blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

// The first word of @p s after blanks, and where it ends.
std::string_view first_word(std::string_view s) {
  size_t a = 0;
  while (a < s.size() && blank(s[a])) ++a;
  size_t b = a;
  while (b < s.size() && !blank(s[b])) ++b;
  return s.substr(a, b - a);
}

bool is_off_keyword(std::string_view k) {
  if (k.substr(0, 2) == "ST") k.remove_prefix(2);
  for (char prefix : {'C', 'N', '4', 'n'})
    if (!k.empty() && k[0] == prefix) k.remove_prefix(1);
  return k == "OFF";
}

bool is_obj_statement(std::string_view k) {
  for (std::string_view s : {"v", "vt", "vn", "f", "o", "g", "s", "mtllib", "usemtl"})
    if (k == s) return true;
  return false;
}

}  // namespace

MeshFormat format_by_extension(const std::string& name) {
  std::string ext = std::filesystem::path(name).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".obj") return MeshFormat::Obj;
  if (ext == ".ply") return MeshFormat::Ply;
  if (ext == ".off") return MeshFormat::Off;
  if (ext == ".stl") return MeshFormat::Stl;
  return MeshFormat::Other;
}

bool has_no_extension(const std::string& name) { return std::filesystem::path(name).extension().empty(); }

MeshFormat format_by_content(std::string_view bytes) {
  if (bytes.substr(0, 4) == "ply\n" || bytes.substr(0, 5) == "ply\r\n") return MeshFormat::Ply;
  const std::string_view word = first_word(bytes.substr(0, 4096));
  if (is_off_keyword(word)) return MeshFormat::Off;
  std::string lower(word.substr(0, 5));
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (lower == "solid") return MeshFormat::Stl;
  if (bytes.size() >= 84) {
    uint64_t n = 0;
    for (int k = 0; k < 4; ++k) n |= uint64_t(static_cast<uint8_t>(bytes[80 + k])) << (8 * k);
    if (bytes.size() == 84 + 50 * n) return MeshFormat::Stl;
  }
  // OBJ: the first line that holds something other than blanks and a comment.
  for (size_t at = 0; at < bytes.size() && at < 65536;) {
    size_t end = bytes.find('\n', at);
    if (end == std::string_view::npos) end = bytes.size();
    std::string_view line = bytes.substr(at, end - at);
    line = line.substr(0, line.find('#'));
    const std::string_view w = first_word(line);
    if (!w.empty()) return is_obj_statement(w) ? MeshFormat::Obj : MeshFormat::Other;
    at = end + 1;
  }
  return MeshFormat::Other;
}

}  // namespace hdm::io::detail
