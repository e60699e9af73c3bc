// SPDX-License-Identifier: MIT
#pragma once
// Internal: PNG writing for render_png.

#include <cstdint>
#include <string>
#include <vector>

namespace hdm::render_detail {

/// Encodes 8-bit RGB pixels (top row first, width·height·3 bytes) as PNG and writes them to
/// @p path with hdm::write_file_atomic (temporary file renamed into place, so readers never see a
/// half-written image). Throws IoError "<path>: <reason>".
void write_png_rgb(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb);

}  // namespace hdm::render_detail
