// SPDX-License-Identifier: MIT
// The PNG encoder behind renders, screenshots and exported colour atlases: what it writes decodes
// (stb_image, a separate decoder) to the same pixels, and bad sizes are refused by name.
#include <hdm/core/encode_png.h>
#include <hdm/core/error.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <random>

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#endif
#include <stb/stb_image.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

namespace hdm {

TEST(EncodePng, DecodesToTheSamePixelsForEveryChannelCount) {
  std::mt19937 rng(7);
  for (int channels = 1; channels <= 4; ++channels) {
    const int w = 37, h = 23;  // odd sizes: no row padding
    std::vector<uint8_t> pixels(static_cast<size_t>(w) * h * channels);
    for (uint8_t& p : pixels) p = static_cast<uint8_t>(rng());
    const std::vector<uint8_t> png = encode_png(w, h, channels, pixels, "test image");
    int dw = 0, dh = 0, dc = 0;
    uint8_t* decoded = stbi_load_from_memory(png.data(), static_cast<int>(png.size()), &dw, &dh, &dc, 0);
    ASSERT_NE(decoded, nullptr) << channels << " channels: " << stbi_failure_reason();
    EXPECT_EQ(dw, w);
    EXPECT_EQ(dh, h);
    EXPECT_EQ(dc, channels);
    EXPECT_EQ(std::vector<uint8_t>(decoded, decoded + pixels.size()), pixels) << channels << " channels";
    std::free(decoded);
  }
}

TEST(EncodePng, RefusesBadSizesNamingTheImage) {
  const std::vector<uint8_t> four(4 * 4 * 3, 0);
  const auto message = [&](int w, int h, int c, const std::vector<uint8_t>& px) {
    try {
      encode_png(w, h, c, px, "shot.png");
    } catch (const InvalidInput& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(0, 4, 3, four).find("shot.png: cannot encode a 0x4 image"), std::string::npos);
  EXPECT_NE(message(4, -1, 3, four).find("shot.png"), std::string::npos);
  EXPECT_NE(message(4, 4, 5, four).find("channels 1 to 4"), std::string::npos);
  EXPECT_NE(message(4, 4, 4, four).find("needs 64 bytes, got 48"), std::string::npos);
  EXPECT_EQ(message(4, 4, 3, four), "no error");
}

}  // namespace hdm
