// SPDX-License-Identifier: MIT
// Texture atlas: every texel lands at uv(), padding copies the nearest valid texel, bilinear
// footprints stay inside a slab's tile, and tiles do not overlap.
#include "io/io_test_util.h"

#include <hdm/atlas/texture_atlas.h>
#include <hdm/slab/triangle_grid.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace hdm {
namespace {

std::array<int, 3> pixel(const TextureAtlas& a, int x, int y) {
  const uint8_t* p = &a.rgba[(size_t(y) * a.width + x) * 4];
  EXPECT_EQ(p[3], 255);
  return {p[0], p[1], p[2]};
}

std::array<int, 3> expected(const Vec3f& c) { return {test::srgb8(c.x()), test::srgb8(c.y()), test::srgb8(c.z())}; }

class Atlas : public ::testing::TestWithParam<std::pair<int, int>> {};

TEST_P(Atlas, TexelsSitAtTheirUvAndPaddingCopiesTheNearestTexel) {
  const auto [n, m] = GetParam();
  const SlabModel model = test::octahedron_model(n, m);
  const TextureAtlas a = build_texture_atlas(model);
  const int N = n * m;
  ASSERT_EQ(a.rgba.size(), size_t(a.width) * a.height * 4);
  EXPECT_LE(std::max(a.width, a.height), 2 * std::min(a.width, a.height)) << "near-square";

  std::vector<int> owner(size_t(a.width) * a.height, -1);  // which slab's tile a pixel belongs to
  for (int s = 0; s < model.slab_count(); ++s) {
    const SlabIds ids = model.texels.slab_ids(s);
    // Texel (i, j) is at uv(s, i/N, j/N), exactly at the centre of a pixel.
    int x0 = -1, y0 = -1;
    for (int j = 0; j <= N; ++j)
      for (int i = 0; i + j <= N; ++i) {
        const Eigen::Vector2f uv = a.uv(s, double(i) / N, double(j) / N);
        ASSERT_TRUE(uv.x() > 0 && uv.x() < 1 && uv.y() > 0 && uv.y() < 1);
        const double x = uv.x() * a.width, y = uv.y() * a.height;
        EXPECT_NEAR(x - std::floor(x), 0.5, 1e-3);
        EXPECT_NEAR(y - std::floor(y), 0.5, 1e-3);
        if (i == 0 && j == 0) x0 = int(x), y0 = int(y);
        EXPECT_EQ(int(x), x0 + i);
        EXPECT_EQ(int(y), y0 + j);
        EXPECT_EQ(pixel(a, int(x), int(y)), expected(test::texel_colour(ids[grid::index(N, i, j)])))
            << "slab " << s << " texel " << i << "," << j;
      }
    // Every pixel of the tile (texels and a one-pixel border) holds the colour of a valid texel at
    // the smallest Euclidean distance (brute force, any of a tie).
    for (int b = -1; b <= N + 1; ++b)
      for (int c = -1; c <= N + 1; ++c) {
        const int x = x0 + c, y = y0 + b;
        ASSERT_TRUE(x >= 0 && y >= 0 && x < a.width && y < a.height);
        EXPECT_EQ(owner[size_t(y) * a.width + x], -1) << "tiles overlap";
        owner[size_t(y) * a.width + x] = s;
        int best = 1 << 30;
        for (int j = 0; j <= N; ++j)
          for (int i = 0; i + j <= N; ++i) best = std::min(best, (i - c) * (i - c) + (j - b) * (j - b));
        bool found = false;
        for (int j = 0; j <= N && !found; ++j)
          for (int i = 0; i + j <= N && !found; ++i)
            found = (i - c) * (i - c) + (j - b) * (j - b) == best &&
                    pixel(a, x, y) == expected(test::texel_colour(ids[grid::index(N, i, j)]));
        EXPECT_TRUE(found) << "slab " << s << " pixel " << c << "," << b;
      }
  }

  // Bilinear footprints of points inside each slab stay in that slab's tile.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u01(0, 1);
  for (int s = 0; s < model.slab_count(); ++s)
    for (int k = 0; k < 200; ++k) {
      double wT = u01(rng), wS = u01(rng);
      if (wT + wS > 1) wT = 1 - wT, wS = 1 - wS;
      const Eigen::Vector2f uv = a.uv(s, wT, wS);
      const int x = int(std::floor(uv.x() * a.width - 0.5)), y = int(std::floor(uv.y() * a.height - 0.5));
      for (int dy : {0, 1})
        for (int dx : {0, 1}) EXPECT_EQ(owner[size_t(y + dy) * a.width + x + dx], s);
    }
}

INSTANTIATE_TEST_SUITE_P(Grids, Atlas,
                         ::testing::Values(std::pair{4, 2}, std::pair{1, 1}, std::pair{3, 1}, std::pair{2, 3}));

TEST(LinearToSrgb, MatchesTheReferenceFormula) {
  for (int k = 0; k <= 1000; ++k) {
    const float c = float(k) / 1000.0f;
    EXPECT_EQ(int(linear_to_srgb8(c)), test::srgb8(c)) << c;
  }
  EXPECT_EQ(linear_to_srgb8(-1.0f), 0);
  EXPECT_EQ(linear_to_srgb8(2.0f), 255);
  EXPECT_EQ(linear_to_srgb8(std::nanf("")), 0);
  EXPECT_EQ(linear_to_srgb8(0.5f), 188);  // published sRGB value of linear 0.5
}

}  // namespace
}  // namespace hdm
