// SPDX-License-Identifier: MIT
// The slab locator against a brute-force scan of every slab: the same answer for points in the
// shell (a slab that holds the point) and outside it (none), with and without a hint.
#include "support/test_models.h"

#include <hdm/query/slab_locator.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

using namespace hdm;

namespace {

void check_against_brute_force(const SlabModel& m, int points) {
  const SlabLocator loc(m);
  std::mt19937 rng(11);
  std::uniform_int_distribution<int32_t> pick(0, m.samples.count - 1);
  // Offsets along the normal up to 3 % of the diagonal: in the shell, above it and below it.
  std::uniform_real_distribution<double> off(-0.03, 0.03);
  int inside = 0, outside = 0;
  for (int k = 0; k < points; ++k) {
    const int32_t s = pick(rng);
    const Vec3 p = m.positions[s].cast<double>() + off(rng) * m.source_diagonal * m.normals[s].cast<double>();
    std::vector<int> holders;
    SlabCoordinates c;
    for (int t = 0; t < m.slab_count(); ++t)
      if (locate_in_slab(m.geometry[t], p, AlphaSolver::Newton, c)) holders.push_back(t);
    const int hint = k % 2 ? -1 : int(rng() % m.slab_count());
    const int found = loc.find(p, hint, AlphaSolver::Newton, c);
    if (holders.empty()) {
      ASSERT_EQ(found, -1) << "point " << k;
      ++outside;
    } else {
      ASSERT_NE(std::find(holders.begin(), holders.end(), found), holders.end()) << "point " << k;
      ++inside;
    }
  }
  EXPECT_GT(inside, points / 10);
  EXPECT_GT(outside, points / 10);
}

}  // namespace

TEST(LocatorTest, agrees_with_a_scan_of_every_slab) { check_against_brute_force(test::baked_bunny(0, 16), 3000); }

TEST(LocatorTest, agrees_with_a_scan_of_every_slab_at_3000_slabs) {
  check_against_brute_force(test::baked_bunny(3000, 4), 1500);
}
