// SPDX-License-Identifier: MIT
// The unorm16 displacements against the definition (code = round(65535·x), value = code/65535):
// writes within half a step, stochastic rounding unbiased and within a step, and the model's
// stored surface points within displacement_quantisation() of the points written, computed here
// in double from the projection lines.
#include <hdm/slab/slab_model.h>

#include "../support/flat_sheet.h"
#include "../support/test_models.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace hdm {
namespace {

TEST(Unorm16, EveryCodeReadsBackAsItselfAndWritesLandWithinHalfAStep) {
  for (int code = 0; code <= 65535; ++code) {
    Unorm16 q;
    q.code = uint16_t(code);
    ASSERT_NEAR(float(q), code / 65535.0, 1e-7) << code;
    ASSERT_EQ(Unorm16(float(q)).code, code);
  }
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int k = 0; k < 100000; ++k) {
    const float x = u(rng);
    ASSERT_LE(std::abs(Unorm16(x).code - 65535.0 * x), 0.5 + 1e-3) << x;
  }
  EXPECT_EQ(Unorm16(-0.25f).code, 0);
  EXPECT_EQ(Unorm16(7.0f).code, 65535);
  EXPECT_EQ(Unorm16(std::numeric_limits<float>::quiet_NaN()).code, 0);
}

TEST(Unorm16, DitheredRoundingKeepsTheMeanAndStaysWithinAStep) {
  // Over draws u evenly spread in [0, 1), the mean code is 65535·x to within 1/draws: increments far
  // below a step add up instead of vanishing.
  const int draws = 4096;
  for (float x : {0.0f, 1e-7f, 0.25f, 0.5f, 0.3000001f, 0.99999f, 1.0f}) {
    double sum = 0;
    for (int k = 0; k < draws; ++k) {
      const Unorm16 q = Unorm16::dithered(x, (float(k) + 0.5f) / float(draws));
      ASSERT_LT(std::abs(q.code - 65535.0 * x), 1.0) << x;
      sum += q.code;
    }
    EXPECT_NEAR(sum / draws, 65535.0 * double(x), 1.0 / draws + 1e-3) << x;
  }
  EXPECT_EQ(Unorm16::dithered(-1.0f, 0.99f).code, 0);
  EXPECT_EQ(Unorm16::dithered(2.0f, 0.99f).code, 65535);
  EXPECT_EQ(Unorm16::dithered(std::numeric_limits<float>::quiet_NaN(), 0.5f).code, 0);
}

TEST(Unorm16, StoredSurfacePointsLieWithinTheReportedBound) {
  SlabModel m = test::flat_sheet();
  // Stretch the shell unevenly so the lines differ in length: corner v's outer end at z = 1 + v/10.
  for (size_t v = 0; v < m.outer.size(); ++v) m.outer[v].z() = 1.0 + 0.1 * double(v % 7);
  rebuild_derived(m);
  double longest = 0;
  for (size_t v = 0; v < m.outer.size(); ++v) longest = std::max(longest, (m.outer[v] - m.inner[v]).norm());
  const double bound = displacement_quantisation(m);
  EXPECT_DOUBLE_EQ(bound, 0.5 / 65535 * longest);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> written(m.displacement.size());
  for (size_t s = 0; s < written.size(); ++s) m.displacement[s] = float(written[s] = double(float(u(rng))));
  double worst = 0;
  for (int s = 0; s < m.samples.count; ++s) {
    const GridSlot h = m.samples.home(s);
    Vec3 p0, p1;
    projection_line(m, h.slab, h.index, p0, p1);
    worst = std::max(worst, (sample_position(m, s) - (p0 + written[size_t(s)] * (p1 - p0))).norm());
  }
  EXPECT_LE(worst, bound + 1.2e-7 * longest);  // and the float the code reads back as, to an ulp
  EXPECT_GT(worst, 0.5 * bound) << "the bound is not loose by more than the lines' spread";
}

}  // namespace
}  // namespace hdm
