// SPDX-License-Identifier: MIT
// The octahedral force-shading normals of SlabSample (encode_oct8(), decode_oct8()) against the
// float directions they stand for, and the proxy's three-corner interpolation of them against the
// corners decoded one by one.
#include <hdm/query/detail/surface_eval.h>
#include <hdm/slab/slab_model.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>

namespace hdm {
namespace {

double angle_deg(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180 / std::numbers::pi;
}

TEST(Oct8, UnitVectorsComeBackWithinTheStatedAngle) {
  // Two million directions uniform on the sphere, plus the axes and diagonals (the octahedron's
  // corners and the lower half's fold).
  std::mt19937 rng(11);
  std::normal_distribution<double> g;
  double worst = 0;
  bool reserved = false;
  auto check = [&](const Vec3& d) {
    const auto c = encode_oct8(d.normalized().cast<float>());
    reserved |= c[0] == -128 && c[1] == -128;
    SlabSample s{};
    s.h[0] = c[0], s.h[1] = c[1];
    worst = std::max(worst, angle_deg(s.shading().cast<double>(), d.normalized()));
  };
  for (int k = 0; k < 2000000; ++k) check(Vec3(g(rng), g(rng), g(rng)));
  for (int a = 0; a < 27; ++a)
    if (a != 13) check(Vec3(a % 3 - 1, (a / 3) % 3 - 1, a / 9 - 1));
  std::printf("largest angle %.3f deg\n", worst);
  EXPECT_FALSE(reserved) << "a direction got the code that stands for no normal";
  EXPECT_LE(worst, 0.65);
  EXPECT_GT(worst, 0.3);  // the codes do round: a float copy would pass with 0
}

TEST(Oct8, NoDirectionGivesTheZeroVector) {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  const Vec3f cases[] = {Vec3f::Zero(), Vec3f(nan, 0, 1), Vec3f(inf, 0, 0), Vec3f(0, -inf, 1)};
  for (const Vec3f& v : cases) {
    const auto c = encode_oct8(v);
    EXPECT_EQ(int(c[0]), -128);
    EXPECT_EQ(int(c[1]), -128);
    EXPECT_EQ(decode_oct8(c.data()), Vec3f::Zero());
  }
}

// interpolated_shading() decodes the three corners of a cell at once (SSE2 where built with it):
// it must equal the weighted sum of the corners' shading(), decoded one at a time, including a
// corner without a normal, which adds nothing.
TEST(Oct8, ThreeCornerInterpolationEqualsTheCornersOneByOne) {
  std::mt19937 rng(5);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> u(0, 1);
  SlabModel m;
  m.samples.per_slab = 3;
  m.slab_samples.resize(3);
  double worst = 0;
  for (int k = 0; k < 100000; ++k) {
    for (int i = 0; i < 3; ++i) {
      const bool none = k % 7 == 0 && i == k % 3;
      const auto c = encode_oct8(none ? Vec3f::Zero() : Vec3f(Vec3(g(rng), g(rng), g(rng)).normalized().cast<float>()));
      m.slab_samples[i].h[0] = c[0], m.slab_samples[i].h[1] = c[1];
    }
    const double a = u(rng), b = u(rng) * (1 - a);
    const slab_query::detail::LocalCell cell{0, 1, 2, a, b, 1 - a - b};
    const Vec3f got = slab_query::detail::interpolated_shading(m, 0, cell);
    const Vec3f want = float(cell.wa) * m.slab_samples[0].shading() + float(cell.wb) * m.slab_samples[1].shading() +
                       float(cell.wd) * m.slab_samples[2].shading();
    worst = std::max(worst, double((got - want).norm()));
  }
  EXPECT_LE(worst, 1e-6);
}

}  // namespace
}  // namespace hdm
