// SPDX-License-Identifier: MIT
// SampleField against a plain array of codes kept beside it: every read, after any sequence of
// writes, equals the array's code; the field holds an array exactly when its codes differ (or
// materialise() ran), and never frees one that materialise() gave it.
#include <hdm/core/field16.h>
#include <hdm/core/sample_field.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

namespace hdm {
namespace {

bool same_codes(const SampleField<Half16>& f, const std::vector<Half16>& ref) {
  if (f.size() != ref.size()) return false;
  for (size_t k = 0; k < ref.size(); ++k)
    if (!SampleField<Half16>::same(f[k], ref[k])) return false;
  return true;
}

TEST(SampleField, UniformUntilAWriteDiffers) {
  SampleField<Half16> f(1000, 0.3f);
  EXPECT_TRUE(f.uniform());
  EXPECT_EQ(f.heap_bytes(), 0u);
  EXPECT_EQ(float(f[999]), float(Half16(0.3f)));
  f.set(17, 0.3f);  // the value it holds: nothing stored
  EXPECT_TRUE(f.uniform());
  EXPECT_EQ(f.heap_bytes(), 0u);
  f.set(17, 0.5f);
  EXPECT_FALSE(f.uniform());
  EXPECT_GE(f.heap_bytes(), 1000 * sizeof(Half16));
  EXPECT_EQ(float(f[17]), 0.5f);
  EXPECT_EQ(float(f[16]), float(Half16(0.3f)));
  f.set(17, 0.3f);  // painted back: the array stays until compact()
  EXPECT_FALSE(f.uniform());
  f.compact();
  EXPECT_TRUE(f.uniform());
  EXPECT_EQ(f.heap_bytes(), 0u);
  EXPECT_EQ(float(f.uniform_value()), float(Half16(0.3f)));
}

TEST(SampleField, RandomWritesReadBackAsAPlainArray) {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> at(0, 499), pick(0, 3);
  const float values[4] = {0.2f, 0.2f, 0.7f, 3.0f};  // the uniform value twice as often
  SampleField<Half16> f(500, 0.2f);
  std::vector<Half16> ref(500, 0.2f);
  for (int step = 0; step < 5000; ++step) {
    const int i = at(rng);
    const float v = values[pick(rng)];
    f.set(size_t(i), v);
    ref[size_t(i)] = v;
    if (step % 97 == 0) f.compact();
    ASSERT_TRUE(same_codes(f, ref)) << "step " << step;
  }
  const bool all_first = std::all_of(ref.begin(), ref.end(), [](Half16 h) { return h.bits() == Half16(0.2f).bits(); });
  EXPECT_EQ(f == SampleField<Half16>(500, 0.2f), all_first);
  const std::vector<Half16> codes = f.codes();
  ASSERT_EQ(codes.size(), ref.size());
  std::vector<float> iterated(f.begin(), f.end());
  for (size_t k = 0; k < ref.size(); ++k) {
    EXPECT_EQ(codes[k].bits(), ref[k].bits());
    EXPECT_EQ(iterated[k], float(ref[k]));
  }
}

TEST(SampleField, AnArrayOfOneValueIsKeptAsThatValue) {
  SampleField<Unorm16> f;
  f.assign(std::vector<Unorm16>(300, Unorm16(0.25f)));
  EXPECT_TRUE(f.uniform());
  EXPECT_EQ(f.size(), 300u);
  EXPECT_EQ(f.heap_bytes(), 0u);
  std::vector<Unorm16> mixed(300, Unorm16(0.25f));
  mixed[299] = 0.5f;
  f.assign(std::move(mixed));
  EXPECT_FALSE(f.uniform());
  EXPECT_EQ(float(f[299]), float(Unorm16(0.5f)));
  // Equality compares codes, not how they are stored.
  SampleField<Unorm16> g(300, 0.25f);
  EXPECT_FALSE(f == g);
  g.set(299, 0.5f);
  EXPECT_TRUE(f == g);
  EXPECT_FALSE(f == SampleField<Unorm16>(299, 0.25f));
}

// What the edits rely on: once materialised, no write, assign or compact allocates or frees.
TEST(SampleField, AMaterialisedFieldKeepsItsArray) {
  SampleField<Half16> f(256, 300.0f);
  f.materialise();
  EXPECT_TRUE(f.materialised());
  EXPECT_FALSE(f.uniform());
  const size_t bytes = f.heap_bytes();
  EXPECT_GE(bytes, 256 * sizeof(Half16));
  f.compact();
  EXPECT_EQ(f.heap_bytes(), bytes);
  f.assign(256, 55.0f);  // the same size: filled in place
  EXPECT_EQ(f.heap_bytes(), bytes);
  EXPECT_FALSE(f.uniform());
  EXPECT_EQ(float(f[100]), 55.0f);
  f.set(100, 60.0f);
  EXPECT_EQ(float(f[100]), 60.0f);
  EXPECT_EQ(f.heap_bytes(), bytes);
  SampleField<Half16> empty;
  empty.materialise();
  EXPECT_FALSE(empty.materialised());
  EXPECT_EQ(empty.heap_bytes(), 0u);
}

}  // namespace
}  // namespace hdm
