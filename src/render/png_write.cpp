// SPDX-License-Identifier: MIT
#include "png_write.h"

#include <hdm/render/png.h>

#include <hdm/core/error.h>
#include <hdm/core/write_file_atomic.h>

// stb is compiled here with internal linkage, so it cannot clash with another copy of stb linked
// into the same program (hdm::io, the application, or Debian's libstb).
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-function"
#endif
#include <stb/stb_image_write.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

namespace hdm::render_detail {

void write_png_rgb(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb) {
  std::vector<uint8_t> png;
  png.reserve(rgb.size() / 4);
  auto append = [](void* context, void* data, int size) {
    auto* out = static_cast<std::vector<uint8_t>*>(context);
    const auto* bytes = static_cast<const uint8_t*>(data);
    out->insert(out->end(), bytes, bytes + size);
  };
  if (!stbi_write_png_to_func(append, &png, width, height, 3, rgb.data(), width * 3))
    throw IoError(path + ": PNG encoding failed (" + std::to_string(width) + "x" + std::to_string(height) + ")");
  write_file_atomic(path, png.data(), png.size());
}

}  // namespace hdm::render_detail

void hdm::write_png(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb) {
  if (width <= 0 || height <= 0 || rgb.size() != static_cast<size_t>(width) * height * 3)
    throw InvalidInput(path + ": an image of " + std::to_string(width) + "x" + std::to_string(height) +
                       " pixels needs width·height·3 bytes, got " + std::to_string(rgb.size()));
  render_detail::write_png_rgb(path, width, height, rgb);
}
