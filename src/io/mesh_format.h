// SPDX-License-Identifier: MIT
#pragma once
// Internal to hdm::io: which reader a mesh file goes to (mesh_format.cpp).

#include <string>
#include <string_view>

namespace hdm::io::detail {

enum class MeshFormat { Obj, Ply, Off, Stl, Other };

/// The format named by the extension of @p name (case-insensitive); Other for any other or none.
MeshFormat format_by_extension(const std::string& name);

/// Whether @p name has no extension (then the content decides, format_by_content()).
bool has_no_extension(const std::string& name);

/// @brief The format of a file without an extension, by its first bytes: "ply" on the first line
/// (PLY), an OFF keyword ([ST][C][N][4][n]OFF) as the first word (OFF), "solid" or a size of
/// exactly 84 + 50 n bytes with n the count at byte 80 (STL), an OBJ statement (v, vt, vn, f, o,
/// g, s, mtllib, usemtl) beginning the first line that is not blank or a comment (OBJ); else Other.
/// @note O(1): looks at the first 64 KiB at most.
MeshFormat format_by_content(std::string_view bytes);

}  // namespace hdm::io::detail
