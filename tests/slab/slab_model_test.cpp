// SPDX-License-Identifier: MIT
// The model's surface points are evaluated, not cached: its box, and the normals an update derives
// after displacements change, against the analytic surface and against a full rebuild.
#include "support/flat_sheet.h"

#include <hdm/slab/slab_model.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

namespace hdm {
namespace {

// The sheet's surface lies at z = 2δ - 1 (inner face z = -1, outer z = +1).
float delta_at_height(double z) { return static_cast<float>((z + 1) / 2); }

TEST(SlabModel, SurfaceBoxIsTheBoxOfTheDisplacedSheet) {
  SlabModel m = test::flat_sheet();
  const Aabb flat = surface_box(m);
  EXPECT_EQ(flat.min, Vec3(-test::kSheetHalf, -test::kSheetHalf, test::sheet_surface_z()));
  EXPECT_EQ(flat.max, Vec3(test::kSheetHalf, test::kSheetHalf, test::sheet_surface_z()));
  // One sample raised to z = 0.75 and one lowered to z = -0.5: the box follows them.
  m.displacement[m.samples.id(3, 40)] = delta_at_height(0.75);
  m.displacement[m.samples.id(20, 70)] = delta_at_height(-0.5);
  const Aabb moved = surface_box(m);
  const double half_step = 1.0 / 65535;  // half a unorm16 step of δ over the 2 mm shell
  EXPECT_NEAR(moved.max.z(), 0.75, half_step);
  EXPECT_NEAR(moved.min.z(), -0.5, half_step);
  EXPECT_EQ(moved.min.head<2>(), flat.min.head<2>());
  EXPECT_EQ(moved.max.head<2>(), flat.max.head<2>());
}

TEST(SlabModel, NormalsAfterADisplacementChangeMatchTheSurfaceAndAFullRebuild) {
  SlabModel m = test::flat_sheet();
  // A paraboloid bump z = h·(1 - r²/R²) inside r < R, across several slabs and their seams.
  const double R = 5, h = 1;
  std::vector<int32_t> changed;
  for (int32_t s = 0; s < m.samples.count; ++s) {
    const Vec3 p = sample_position(m, s);
    const double r2 = p.head<2>().squaredNorm();
    if (r2 < R * R) m.displacement[s] = delta_at_height(h * (1 - r2 / (R * R))), changed.push_back(s);
  }
  ASSERT_GT(changed.size(), 500u);
  // The changed samples and their one-ring: every sample whose normal reads a changed point.
  std::vector<char> in_ring(size_t(m.samples.count), 0);
  std::vector<int32_t> ring;
  for (int32_t s : changed) {
    auto add = [&](int32_t t) {
      if (!in_ring[size_t(t)]) in_ring[size_t(t)] = 1, ring.push_back(t);
    };
    add(s);
    m.samples.for_each_neighbour(s, add);
  }
  update_displacements(m, changed.data(), changed.size());
  update_normals(m, ring.data(), ring.size());

  // The same values, bit for bit, as rebuilding every derived array from the stored ones.
  SlabModel fresh = m;
  rebuild_derived(fresh);
  ASSERT_EQ(fresh.slab_samples.size(), m.slab_samples.size());
  for (size_t slot = 0; slot < m.slab_samples.size(); ++slot)
    ASSERT_EQ(std::memcmp(&fresh.slab_samples[slot], &m.slab_samples[slot], sizeof(SlabSample)), 0) << "slot " << slot;

  // Inside the bump (away from its crease at r = R) the normal is the paraboloid's,
  // (2h·x/R², 2h·y/R², 1) normalised, to within the grid's resolution (spacing 0.3125 mm; 0.33° at most).
  double worst = 0;
  for (int32_t s : changed) {
    const Vec3 p = sample_position(m, s);
    if (p.head<2>().norm() > 0.7 * R) continue;
    const Vec3 exact = Vec3(2 * h * p.x() / (R * R), 2 * h * p.y() / (R * R), 1).normalized();
    worst = std::max(worst, std::acos(std::clamp(exact.dot(sample_normal(m, s).cast<double>()), -1.0, 1.0)));
  }
  EXPECT_LT(worst * 180 / M_PI, 0.5) << "largest angle to the paraboloid's normal";
}

}  // namespace
}  // namespace hdm
