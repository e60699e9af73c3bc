// SPDX-License-Identifier: MIT
#include "png_write.h"

#include <hdm/render/png.h>

#include <hdm/core/encode_png.h>
#include <hdm/core/error.h>
#include <hdm/core/write_file_atomic.h>

namespace hdm::render_detail {

void write_png_rgb(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb) {
  const std::vector<uint8_t> png = encode_png(width, height, 3, rgb, path);
  write_file_atomic(path, png.data(), png.size());
}

}  // namespace hdm::render_detail

void hdm::write_png(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb) {
  if (width <= 0 || height <= 0 || rgb.size() != static_cast<size_t>(width) * height * 3)
    throw InvalidInput(path + ": an image of " + std::to_string(width) + "x" + std::to_string(height) +
                       " pixels needs width·height·3 bytes, got " + std::to_string(rgb.size()));
  render_detail::write_png_rgb(path, width, height, rgb);
}
