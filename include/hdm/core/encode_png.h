// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// PNG encoding in memory: the one encoder behind every picture hdm writes (renders, the studio's
/// screenshots, the colour atlas of `.obj` and `.glb` exports).

#include <cstdint>
#include <string>
#include <vector>

namespace hdm {

/// @brief Encodes 8-bit pixels as a PNG file's bytes (stb_image_write, zlib level 8).
/// @param width, height  image size [pixels], each > 0.
/// @param channels       bytes per pixel: 1 (grey), 2 (grey, alpha), 3 (RGB) or 4 (RGBA).
/// @param pixels         width·height·channels bytes, rows top first, no padding.
/// @param what           names the image in errors (e.g. the file it is for).
/// @return the PNG's bytes.
/// @throws InvalidInput "<what>: ..." for a size or channel count out of range or too few pixels;
///         IoError "<what>: PNG encoding failed ..." when the encoder fails.
/// @note O(width·height·channels); allocates the output.
std::vector<uint8_t> encode_png(int width, int height, int channels, const std::vector<uint8_t>& pixels,
                                const std::string& what);

}  // namespace hdm
