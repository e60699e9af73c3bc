// SPDX-License-Identifier: MIT
// The 8-bit texel encodings of SlabModel against the IEC 61966-2-1 transfer functions written here.
#include <hdm/core/srgb.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cmath>
#include <limits>

namespace hdm {
namespace {

// IEC 61966-2-1, both directions, values in [0,1].
double encoded(double c) { return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055; }
double decoded(double s) { return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4); }

TEST(Srgb8, EveryCodeDecodesAndEncodesToItself) {
  for (int code = 0; code < 256; ++code) {
    const float linear = srgb8_to_linear(uint8_t(code));
    EXPECT_NEAR(linear, decoded(code / 255.0), 1e-7) << code;
    EXPECT_EQ(int(linear_to_srgb8(linear)), code);
    EXPECT_EQ(int(unit_to_unorm8(unorm8_to_unit(uint8_t(code)))), code);
  }
}

TEST(Srgb8, LinearToCodeAndBackIsWithinHalfACodeStep) {
  // A dense sweep plus the floats either side of every code boundary (where rounding flips).
  auto check = [](float c) {
    const int code = linear_to_srgb8(c);
    const double exact = 255.0 * encoded(std::clamp(double(c), 0.0, 1.0));
    ASSERT_LE(std::abs(code - exact), 0.5 + 1e-9) << c;
    // The decoded value is a float: its rounding (relative 6e-8) moves it by up to ~1e-5 codes.
    ASSERT_LE(std::abs(255.0 * encoded(srgb8_to_linear(uint8_t(code))) - exact), 0.5 + 1e-5) << c;
  };
  for (int k = 0; k <= 200000; ++k) check(float(k) / 200000.0f);
  for (int k = 0; k < 255; ++k) {
    const float edge = float(decoded((k + 0.5) / 255.0));
    for (float c : {std::nextafter(edge, 0.0f), edge, std::nextafter(edge, 2.0f)}) check(c);
  }
  EXPECT_EQ(linear_to_srgb8(-1.0f), 0);
  EXPECT_EQ(linear_to_srgb8(2.0f), 255);
  EXPECT_EQ(linear_to_srgb8(std::numeric_limits<float>::infinity()), 255);
  EXPECT_EQ(linear_to_srgb8(std::nanf("")), 0);
  EXPECT_EQ(linear_to_srgb8(0.5f), 188);  // published sRGB value of linear 0.5
}

// The code of linear @p c by the formula, rounded once in double: the reference for exact rounding.
int reference_code(float c) { return int(std::lround(255.0 * encoded(double(c)))); }

TEST(Srgb8, EveryFloatInTheUnitIntervalEncodesAsTheFormulaRounds) {
  // All 1,065,353,217 floats in [0,1] in increasing order (their bit patterns are). The encoder
  // must never decrease and must step by exactly one code; where it steps, the formula must give
  // the same code on both sides. The formula is non-decreasing too, so between two steps (where
  // the encoder is constant) it is pinned to the same code: the two agree at every float.
  const uint32_t one = std::bit_cast<uint32_t>(1.0f);
  int prev = linear_to_srgb8(0.0f), steps = 0;
  ASSERT_EQ(prev, reference_code(0.0f));
  for (uint32_t bits = 1; bits <= one; ++bits) {
    const float c = std::bit_cast<float>(bits);
    const int code = linear_to_srgb8(c);
    if (code == prev) continue;
    ASSERT_EQ(code, prev + 1) << c;
    const float before = std::bit_cast<float>(bits - 1);
    ASSERT_EQ(prev, reference_code(before)) << before;
    ASSERT_EQ(code, reference_code(c)) << c;
    prev = code, ++steps;
  }
  EXPECT_EQ(prev, 255);
  EXPECT_EQ(steps, 255);
}

TEST(Srgb8, UnitValuesRoundToTheNearestCodeHalvesUp) {
  // The nearest code: |255·v − code| ≤ 1/2, a half going up (255·v is exact in double), over a
  // dense sweep and the floats either side of every half-code.
  auto check = [](float v) {
    const double x = 255.0 * double(v);
    const int code = unit_to_unorm8(v);
    ASSERT_TRUE(x - code < 0.5 && code - x <= 0.5) << v;
  };
  for (int k = 0; k <= 1000000; ++k) check(float(k) / 1000000.0f);
  for (int k = 0; k < 255; ++k) {
    const float half = float((k + 0.5) / 255.0);
    for (float v : {std::nextafter(half, 0.0f), half, std::nextafter(half, 2.0f)}) check(v);
  }
  EXPECT_EQ(unit_to_unorm8(1.0f), 255);
  EXPECT_EQ(unit_to_unorm8(2.0f), 255);
  EXPECT_EQ(unit_to_unorm8(std::numeric_limits<float>::infinity()), 255);
  EXPECT_EQ(unit_to_unorm8(-std::numeric_limits<float>::infinity()), 0);
}

TEST(Srgb8, ColoursEncodeChannelByChannel) {
  const Srgb8 c = encode_srgb8(Vec3f(0.0f, 0.5f, 1.0f));
  EXPECT_EQ(c, (Srgb8{0, 188, 255}));
  const Vec3f back = decode_srgb8(c);
  EXPECT_NEAR(back.y(), decoded(188 / 255.0), 1e-7);
  EXPECT_EQ(unit_to_unorm8(0.5f), 128);
  EXPECT_EQ(unit_to_unorm8(-0.1f), 0);
  EXPECT_EQ(unit_to_unorm8(std::nanf("")), 0);
}

}  // namespace
}  // namespace hdm
