// SPDX-License-Identifier: MIT
// SlabSnapshots against the live model it copies: a snapshot holds the model's stored codes (the
// colour's sRGB8, the roughness's unorm8, the float fields) bit for bit, and a reader pinned
// before a publication keeps seeing the slab as it was.
#include "support/test_models.h"

#include <hdm/slab/slab_snapshots.h>

#include <gtest/gtest.h>

#include <memory>
#include <random>

namespace hdm {
namespace {

// The bunny's default bake with every texel's colour and roughness and every sample's friction
// set to random codes, so that a code lost or re-encoded on the way shows.
std::unique_ptr<SlabModel> painted_bunny() {
  auto m = std::make_unique<SlabModel>(test::baked_bunny(0, 16));
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> code(0, 255);
  std::uniform_real_distribution<float> mu(0.0f, 1.0f);
  for (Srgb8& c : m->colour) c = Srgb8{uint8_t(code(rng)), uint8_t(code(rng)), uint8_t(code(rng))};
  for (uint8_t& r : m->roughness) r = uint8_t(code(rng));
  for (Half16& f : m->friction_static) f = mu(rng);
  return m;
}

TEST(SlabSnapshots, HoldTheModelsStoredCodesBitForBit) {
  const auto model = painted_bunny();
  const SlabSnapshots snapshots(*model);
  const SnapshotReader reader(snapshots);
  const SlabModel copy = reader.stored_model();
  EXPECT_TRUE(copy.colour == model->colour);
  EXPECT_TRUE(copy.roughness == model->roughness);
  EXPECT_TRUE(copy.friction_static == model->friction_static);
  EXPECT_TRUE(copy.displacement == model->displacement);
  // Each slot of a slab shows its texel's codes (shared texels included).
  const SampleLayout& T = model->texels;
  for (int s = 0; s < model->slab_count(); s += 97) {
    const SlabView v = reader.slab(s);
    for (int k = 0; k < T.per_slab; ++k) {
      const int32_t id = T.id(s, k);
      const Srgb8 c = model->colour[size_t(id)];
      ASSERT_EQ(v.texels[4 * k], c.r);
      ASSERT_EQ(v.texels[4 * k + 1], c.g);
      ASSERT_EQ(v.texels[4 * k + 2], c.b);
      ASSERT_EQ(v.texels[4 * k + 3], model->roughness[size_t(id)]);
    }
  }
  // Two versions per slab (epoch 0 and a spare), each at most one cache line above its content:
  // 36 bytes per displacement slot and the 4 code bytes per texel slot.
  const size_t S = size_t(model->slab_count()), P = size_t(model->samples.per_slab), Tn = size_t(T.per_slab);
  EXPECT_EQ(snapshots.version_count(), 2 * model->slab_count());
  EXPECT_LE(snapshots.memory_bytes(), 2 * S * (26 * P + 4 * Tn + 64));
}

TEST(SlabSnapshots, APinnedReaderKeepsTheSlabAsItWas) {
  const auto model = painted_bunny();
  SlabSnapshots snapshots(*model);
  const SampleLayout& T = model->texels;
  // A texel interior to slab 0 (one slot only), so publishing slab 0 alone keeps every slab equal.
  int local = -1;
  for (int k = 0; k < T.per_slab && local < 0; ++k)
    if (T.id(0, k) >= T.first_interior) local = k;
  ASSERT_GE(local, 0);
  const int32_t id = T.id(0, local);
  const Srgb8 before = model->colour[size_t(id)], after{uint8_t(before.r ^ 0xff), before.g, uint8_t(before.b ^ 0x0f)};

  const SnapshotReader old(snapshots);
  model->colour[size_t(id)] = after;
  model->roughness[size_t(id)] ^= 0x80;
  ASSERT_TRUE(snapshots.publish_reserve(1));
  snapshots.publish_slab(0);
  EXPECT_EQ(snapshots.publish_commit(), 1u);
  const SnapshotReader now(snapshots);

  const SlabView was = old.slab(0), is = now.slab(0);
  EXPECT_EQ(was.epoch, 0u);
  EXPECT_EQ(is.epoch, 1u);
  EXPECT_EQ(was.texels[4 * local], before.r);
  EXPECT_EQ(was.texels[4 * local + 2], before.b);
  EXPECT_EQ(is.texels[4 * local], after.r);
  EXPECT_EQ(is.texels[4 * local + 2], after.b);
  EXPECT_EQ(is.texels[4 * local + 3], model->roughness[size_t(id)]);
  EXPECT_EQ(old.stored_model().colour[size_t(id)], before);
  EXPECT_EQ(now.stored_model().colour[size_t(id)], after);
}

}  // namespace
}  // namespace hdm
