// SPDX-License-Identifier: MIT
#include <hdm/core/encode_png.h>

#include <hdm/core/error.h>

// stb is compiled here with internal linkage, so it cannot clash with another copy of stb linked
// into the same program (tinygltf, the application, or Debian's libstb).
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#endif
#include <stb/stb_image_write.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

std::vector<uint8_t> hdm::encode_png(int width, int height, int channels, const std::vector<uint8_t>& pixels,
                                     const std::string& what) {
  const std::string size = std::to_string(width) + "x" + std::to_string(height);
  if (width <= 0 || height <= 0 || channels < 1 || channels > 4)
    throw InvalidInput(what + ": cannot encode a " + size + " image of " + std::to_string(channels) +
                       " channels as PNG (sizes must be positive, channels 1 to 4)");
  if (pixels.size() / static_cast<size_t>(width) / static_cast<size_t>(height) < static_cast<size_t>(channels))
    throw InvalidInput(what + ": a " + size + " image of " + std::to_string(channels) + " channels needs " +
                       std::to_string(static_cast<size_t>(width) * height * channels) + " bytes, got " +
                       std::to_string(pixels.size()));
  std::vector<uint8_t> png;
  png.reserve(pixels.size() / 4);
  auto append = [](void* context, void* data, int bytes) {
    auto* out = static_cast<std::vector<uint8_t>*>(context);
    const auto* b = static_cast<const uint8_t*>(data);
    out->insert(out->end(), b, b + bytes);
  };
  if (!stbi_write_png_to_func(append, &png, width, height, channels, pixels.data(), width * channels))
    throw IoError(what + ": PNG encoding failed (" + size + ")");
  return png;
}
