// SPDX-License-Identifier: MIT
// SlabSnapshots against the live model it shares: a snapshot holds the model's stored codes (the
// colour's sRGB8, the roughness's unorm8, the float fields) bit for bit, unchanged slabs take no
// copy, a reader pinned before a publication keeps seeing the slab as it was, and a writer out of
// spare versions is refused until readers move on.
#include "support/test_models.h"

#include <hdm/core/error.h>
#include <hdm/slab/model_memory.h>
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
  for (size_t t = 0; t < m->colour.size(); ++t)
    m->colour.set(t, Srgb8{uint8_t(code(rng)), uint8_t(code(rng)), uint8_t(code(rng))});
  for (size_t t = 0; t < m->roughness.size(); ++t) m->roughness.set(t, uint8_t(code(rng)));
  for (size_t s = 0; s < m->friction_static.size(); ++s) m->friction_static.set(s, mu(rng));
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
}

TEST(SlabSnapshots, ShareUnchangedSlabsWithTheLiveModel) {
  const auto model = painted_bunny();
  SlabSnapshots snapshots(*model);
  // Nothing is copied up front: the spare versions (5 % of the slabs) are all the memory, within
  // a tenth of the model's own bytes.
  const int S = model->slab_count();
  EXPECT_EQ(snapshots.version_count(), (S + 19) / 20);
  EXPECT_EQ(snapshots.versions_in_use(), 0);
  EXPECT_LE(double(snapshots.memory_bytes()), 0.1 * double(model_memory(*model).total()));
  // Three slabs edited (their interior texels, which no other slab holds) and published hold three
  // versions (their state before the edit); the other slabs stay shared.
  const SnapshotReader old(snapshots);
  std::vector<uint8_t> hit(model->colour.size(), 0);
  int expected = 0;
  for (int s : {3, 50, 700}) {
    ASSERT_TRUE(snapshots.before_write(s));
    for (int k = 0; k < model->texels.per_slab; ++k) {
      const size_t id = size_t(model->texels.id(s, k));
      if (hit[id] || int32_t(id) < model->texels.first_interior) continue;
      hit[id] = 1;
      Srgb8 c = model->colour[id];
      c.r ^= 0x55;
      model->colour.set(id, c);
      ++expected;
    }
  }
  EXPECT_EQ(snapshots.publish_commit(), 1u);
  EXPECT_EQ(snapshots.versions_in_use(), 3);
  const SnapshotReader now(snapshots);
  const SlabModel before = old.stored_model(), after = now.stored_model();
  int changed = 0;
  for (size_t id = 0; id < model->colour.size(); ++id) changed += !(before.colour[id] == after.colour[id]);
  EXPECT_EQ(changed, expected);
  EXPECT_TRUE(after.colour == model->colour);
}

TEST(SlabSnapshots, APinnedReaderKeepsTheSlabAsItWas) {
  const auto model = painted_bunny();
  SlabSnapshots snapshots(*model);
  const SampleLayout& T = model->texels;
  // A texel interior to slab 0 (one slot only), so writing slab 0 alone keeps every slab equal.
  int local = -1;
  for (int k = 0; k < T.per_slab && local < 0; ++k)
    if (T.id(0, k) >= T.first_interior) local = k;
  ASSERT_GE(local, 0);
  const int32_t id = T.id(0, local);
  const Srgb8 before = model->colour[size_t(id)], after{uint8_t(before.r ^ 0xff), before.g, uint8_t(before.b ^ 0x0f)};

  const SnapshotReader old(snapshots);
  ASSERT_TRUE(snapshots.before_write(0));
  model->colour.set(size_t(id), after);
  model->roughness.set(size_t(id), uint8_t(model->roughness[size_t(id)] ^ 0x80));
  EXPECT_EQ(old.slab(0).texels[4 * local], before.r) << "an uncommitted write is not seen";
  EXPECT_EQ(snapshots.publish_commit(), 1u);
  const SnapshotReader now(snapshots);

  const SlabView was = old.slab(0);
  EXPECT_EQ(was.epoch, 0u);
  EXPECT_EQ(was.texels[4 * local], before.r);
  EXPECT_EQ(was.texels[4 * local + 2], before.b);
  const SlabView is = now.slab(0);
  EXPECT_EQ(is.epoch, 1u);
  EXPECT_EQ(is.texels[4 * local], after.r);
  EXPECT_EQ(is.texels[4 * local + 2], after.b);
  EXPECT_EQ(is.texels[4 * local + 3], model->roughness[size_t(id)]);
  EXPECT_EQ(old.stored_model().colour[size_t(id)], before);
  EXPECT_EQ(now.stored_model().colour[size_t(id)], after);
  EXPECT_EQ(now.slab(1).epoch, 0u) << "an unwritten slab keeps its epoch";
}

TEST(SlabSnapshots, AWriterOutOfVersionsIsRefusedUntilReadersMoveOn) {
  const auto model = painted_bunny();
  SnapshotOptions o;
  o.spare_versions = 2;  // raised to one more than the most slabs around a coarse vertex
  SlabSnapshots snapshots(*model, o);
  std::vector<int> around(size_t(model->coarse_vertex_count()), 0);
  int most = 0;
  for (const Tri& t : model->slabs)
    for (int32_t v : t) most = std::max(most, ++around[size_t(v)]);
  const int V = snapshots.version_count();
  EXPECT_EQ(V, most + 1);
  auto reader = std::make_unique<SnapshotReader>(snapshots);
  for (int s = 0; s < V; ++s) EXPECT_TRUE(snapshots.before_write(s));
  EXPECT_TRUE(snapshots.before_write(1)) << "granted until the commit";
  EXPECT_FALSE(snapshots.before_write(V));
  EXPECT_TRUE(snapshots.starved());
  snapshots.publish_commit();
  EXPECT_FALSE(snapshots.starved());
  // The reader pinned at epoch 0 still needs the written slabs as they were.
  EXPECT_FALSE(snapshots.readers_caught_up());
  EXPECT_FALSE(snapshots.before_write(V));
  reader.reset();
  EXPECT_TRUE(snapshots.readers_caught_up());
  EXPECT_TRUE(snapshots.before_write(V));
  EXPECT_EQ(snapshots.versions_in_use(), 1);
  const SnapshotReader now(snapshots);
  EXPECT_EQ(now.slab(0).epoch, 1u);
  EXPECT_TRUE(now.verify(0));
  EXPECT_THROW(SlabSnapshots(*model, SnapshotOptions{8, 0, false}), InvalidInput);
}

}  // namespace
}  // namespace hdm
