// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Writing pictures: the PNG encoder hdm's renderer uses, for programs that read pixels back
/// themselves (the studio's screenshots).

#include <cstdint>
#include <string>
#include <vector>

namespace hdm {

/// @brief Writes 8-bit RGB pixels as a PNG file, atomically (a temporary file renamed into place:
/// an existing file is replaced only on success).
/// @param path    destination file.
/// @param width   image width [pixels], > 0.
/// @param height  image height [pixels], > 0.
/// @param rgb     width·height·3 bytes, top row first.
/// @throws InvalidInput when the size and @p rgb disagree; IoError "<path>: <reason>" when the
///         file cannot be written.
/// @note O(pixels); stb_image_write's encoder.
void write_png(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb);

}  // namespace hdm
