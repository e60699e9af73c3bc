// SPDX-License-Identifier: MIT
// model_memory() against the allocator: copying a model allocates exactly its arrays, so the heap
// the copy takes (glibc's mallinfo2) is what model_memory() must count, give or take the
// allocator's per-block overhead. An array the accounting forgot shows as a larger heap.
#include "support/test_models.h"

#include <hdm/slab/model_memory.h>

#include <gtest/gtest.h>
#include <malloc.h>

namespace hdm {
namespace {

// g++ defines __SANITIZE_*__, clang 14 answers __has_feature().
#if defined(__has_feature)
#define HDM_SANITIZED_ALLOCATOR (__has_feature(address_sanitizer) || __has_feature(thread_sanitizer))
#else
#define HDM_SANITIZED_ALLOCATOR 0
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__) || HDM_SANITIZED_ALLOCATOR
constexpr bool kOwnAllocator = false;  // the sanitizers' allocators leave mallinfo2 empty
#else
constexpr bool kOwnAllocator = true;
#endif

int64_t heap_in_use() {
  const struct mallinfo2 m = mallinfo2();
  return static_cast<int64_t>(m.uordblks + m.hblkhd);  // small blocks + mmapped large ones
}

TEST(ModelMemory, CountsEveryArrayTheModelAllocates) {
  if (!kOwnAllocator) GTEST_SKIP() << "needs glibc's allocator";
  const SlabModel& bunny = test::baked_bunny(0, 16);  // the default bake: ~150k samples
  const int64_t before = heap_in_use();
  const auto copy = std::make_unique<SlabModel>(bunny);
  const int64_t taken = heap_in_use() - before;
  const ModelMemory m = model_memory(*copy);
  ASSERT_GT(taken, 0);
  // Per block: up to 16 bytes of header and alignment, or a page for an mmapped one; 36 arrays
  // and the source string, so 48 pages bound the overhead. A per-sample float array the
  // accounting forgot is 4 bytes × ~150k samples, above that bound.
  // mallinfo2 counts the blocks glibc's per-thread cache (tcache) holds as in use: a small array
  // of the copy may reuse one that was already counted before the copy, so the copy can appear a
  // few hundred bytes smaller than its arrays (260 B with the hardness array; none with
  // GLIBC_TUNABLES=glibc.malloc.tcache_count=0). A page of slack covers that.
  EXPECT_LE(m.total(), taken + 4096);
  EXPECT_GE(m.total(), taken - 48 * 4096) << "the copy holds " << taken - m.total() << " bytes the accounting misses";
}

TEST(ModelMemory, SplitsSamplesFromTexels) {
  const SlabModel& bunny = test::baked_bunny(0, 16);
  const ModelMemory m = model_memory(bunny);
  EXPECT_EQ(m.samples, bunny.samples.count);
  EXPECT_EQ(m.texels, bunny.texels.count);
  // The stored displacement alone is a unorm16 per sample; colour and roughness, once an editor
  // gives them their arrays, are 3 + 1 bytes per texel.
  EXPECT_GE(m.sample_fields, int64_t(sizeof(Unorm16)) * m.samples);
  SlabModel edited = bunny;
  materialise_fields(edited);
  const ModelMemory e = model_memory(edited);
  EXPECT_GE(e.texel_fields, 4 * e.texels);
  EXPECT_LE(e.texel_fields, 8 * e.texels);
  EXPECT_NEAR(m.per_sample() * double(m.samples) + m.per_texel() * double(m.texels), double(m.total()), 1.0);
  EXPECT_EQ(model_memory(SlabModel{}).total(), 0);
  EXPECT_EQ(model_memory(SlabModel{}).per_sample(), 0);
}

// A baked model's friction, stiffness scale, layer top and hardness, and its texels' colour and
// roughness, are one value each (no brush has painted them): they take no array until the edits
// materialise them, 2 bytes per sample and 3 + 1 per texel.
TEST(ModelMemory, UniformFieldsTakeNoArrayUntilMaterialised) {
  const SlabModel& bunny = test::baked_bunny(0, 16);
  for (bool u : {bunny.friction_static.uniform(), bunny.friction_dynamic.uniform(), bunny.stiffness_scale.uniform(),
                 bunny.layer_displacement.uniform(), bunny.hardness.uniform(), bunny.colour.uniform(),
                 bunny.roughness.uniform()})
    EXPECT_TRUE(u);
  SlabModel edited = bunny;
  const ModelMemory before = model_memory(edited);
  EXPECT_EQ(before.sample_fields, int64_t(edited.displacement.capacity() * sizeof(Unorm16)));
  EXPECT_EQ(before.texel_fields, 0);
  materialise_fields(edited);
  const ModelMemory after = model_memory(edited);
  EXPECT_EQ(after.sample_fields - before.sample_fields, 5 * int64_t(sizeof(Unorm16)) * after.samples);
  EXPECT_EQ(after.texel_fields, int64_t(sizeof(Srgb8) + sizeof(uint8_t)) * after.texels);
  EXPECT_EQ(after.total() - before.total(),
            after.sample_fields - before.sample_fields + after.texel_fields - before.texel_fields);
  EXPECT_EQ(after.total() - before.total(), before.uniform_fields);  // what `hdm info` announces
  EXPECT_EQ(after.uniform_fields, 0);
  // The values are the same, sample for sample and texel for texel.
  EXPECT_TRUE(edited.hardness == bunny.hardness);
  EXPECT_TRUE(edited.friction_static == bunny.friction_static);
  EXPECT_TRUE(edited.colour == bunny.colour);
  EXPECT_TRUE(edited.roughness == bunny.roughness);
  if (!kOwnAllocator) return;
  // The allocator agrees: copying the materialised model takes its five arrays more.
  const int64_t heap0 = heap_in_use();
  const auto copy = std::make_unique<SlabModel>(edited);
  const int64_t taken = heap_in_use() - heap0;
  EXPECT_LE(model_memory(*copy).total(), taken + 4096);
  EXPECT_GE(model_memory(*copy).total(), taken - 48 * 4096);
}

}  // namespace
}  // namespace hdm
