// SPDX-License-Identifier: MIT
// The snorm16 normals of SlabSample against the definition (code = round(32767·x)) and against the
// float directions they stand for.
#include <hdm/slab/slab_model.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace hdm {
namespace {

TEST(Snorm16, EveryCodeDecodesAndEncodesToItself) {
  for (int code = -32767; code <= 32767; ++code) {
    const float x = decode_snorm16(int16_t(code));
    ASSERT_NEAR(x, code / 32767.0, 1e-7) << code;
    ASSERT_EQ(int(encode_snorm16(x)), code);
  }
}

TEST(Snorm16, OutOfRangeClampsAndNaNGivesZero) {
  EXPECT_EQ(int(encode_snorm16(2.0f)), 32767);
  EXPECT_EQ(int(encode_snorm16(-7.0f)), -32767);  // never -32768, which has no value of its own
  EXPECT_EQ(int(encode_snorm16(std::numeric_limits<float>::infinity())), 32767);
  EXPECT_EQ(int(encode_snorm16(std::numeric_limits<float>::quiet_NaN())), 0);
}

TEST(Snorm16, UnitNormalsComeBackWithinTheStatedAngle) {
  // 200,000 directions uniform on the sphere, plus the axes and diagonals (the largest rounding
  // in all three coordinates at once).
  std::mt19937 rng(7);
  std::normal_distribution<double> g;
  double worst_angle = 0, worst_length = 0;
  auto check = [&](const Vec3& d) {
    const Vec3f n = d.normalized().cast<float>();
    SlabSample s{{encode_snorm16(n[0]), encode_snorm16(n[1]), encode_snorm16(n[2])}, 0.5f, {}};
    const Vec3 back = s.normal().cast<double>();
    const double angle = std::atan2(back.cross(d.normalized()).norm(), back.dot(d.normalized()));
    worst_angle = std::max(worst_angle, angle);
    worst_length = std::max(worst_length, std::abs(back.norm() - 1));
  };
  for (int k = 0; k < 200000; ++k) check(Vec3(g(rng), g(rng), g(rng)));
  for (int a = 0; a < 27; ++a)
    if (a != 13) check(Vec3(a % 3 - 1, (a / 3) % 3 - 1, a / 9 - 1));
  // Each coordinate is within half a step (1/65534): the vector within √3 of that.
  EXPECT_LE(worst_angle, 2.7e-5);
  EXPECT_LE(worst_length, 2.7e-5);
  EXPECT_GT(worst_angle, 1e-6);  // the codes do round: a float copy would pass with 0
}

}  // namespace
}  // namespace hdm
