// SPDX-License-Identifier: MIT
// .hdm files: bit-exact round trip, layout checked against the format spec with the test's own
// decoder and FNV-1a, and every documented failure (corruption, truncation, version, huge counts,
// failed saves).
#include "io/io_test_util.h"

#include <hdm/core/error.h>
#include <hdm/io/hdm_file.h>

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <map>
#include <new>
#include <string>
#include <vector>

// ---- allocation probe: the largest single allocation made while `g_track` is set ----
// (GCC flags free() in a replaced operator delete as mismatched once it inlines both; it is not.)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
namespace {
std::atomic<bool> g_track{false};
std::atomic<size_t> g_largest{0};
}  // namespace

void* operator new(size_t size) {
  if (g_track.load(std::memory_order_relaxed)) {
    size_t seen = g_largest.load();
    while (size > seen && !g_largest.compare_exchange_weak(seen, size)) {}
  }
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, size_t) noexcept { std::free(p); }

namespace hdm {
namespace {

using test::TempDir;

uint64_t reference_fnv1a(const uint8_t* p, size_t n) {
  uint64_t h = 0xcbf29ce484222325ull;
  for (size_t k = 0; k < n; ++k) {
    h ^= p[k];
    h *= 0x100000001b3ull;
  }
  return h;
}

uint64_t get_u64(const std::vector<uint8_t>& b, size_t at) {
  uint64_t v = 0;
  for (int k = 7; k >= 0; --k) v = (v << 8) | b[at + k];
  return v;
}
void set_u64(std::vector<uint8_t>& b, size_t at, uint64_t v) {
  for (int k = 0; k < 8; ++k) b[at + k] = uint8_t(v >> (8 * k));
}
void reseal(std::vector<uint8_t>& b) { set_u64(b, b.size() - 8, reference_fnv1a(b.data(), b.size() - 8)); }

// Section tag -> offset of its count field, walking the layout the format spec in hdm_file.h gives.
std::map<std::string, size_t> section_offsets(const std::vector<uint8_t>& b) {
  const std::map<std::string, size_t> element_bytes = {
      {"GRID", 4}, {"INNR", 24}, {"OUTR", 24}, {"SLAB", 12}, {"DISP", 2}, {"COLR", 3},
      {"FRST", 2}, {"FRDY", 2},  {"STIF", 2},  {"SRCN", 1},  {"SRCT", 8}, {"SRCD", 8},
      {"RUFF", 1}, {"LAYD", 2},  {"LAYM", 28}, {"HARD", 2},  {"LAYH", 4}};
  std::map<std::string, size_t> at;
  size_t pos = 8;
  for (const char* tag : {"GRID", "INNR", "OUTR", "SLAB", "DISP", "COLR", "FRST", "FRDY", "STIF", "SRCN", "SRCT",
                          "SRCD", "RUFF", "LAYD", "LAYM", "HARD", "LAYH"}) {
    EXPECT_EQ(std::string(reinterpret_cast<const char*>(&b[pos]), 4), tag);
    at[tag] = pos + 4;
    pos += 12 + get_u64(b, pos + 4) * element_bytes.at(tag);
  }
  EXPECT_EQ(pos + 8, b.size()) << "sections must be followed by exactly the 8-byte checksum";
  return at;
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}
template <class T>
bool same_bits(const SampleField<T>& a, const SampleField<T>& b) {
  return same_bits(a.codes(), b.codes());
}

template <class E>
std::string expect_load_error(const std::string& path) {
  try {
    load_model(path);
    ADD_FAILURE() << "no exception for " << path;
  } catch (const E& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "wrong exception type: " << e.what();
  }
  return {};
}

class HdmFile : public ::testing::Test {
 protected:
  SlabModel model = test::octahedron_model();
  TempDir dir;
  std::string path = dir.file("model.hdm");
  void SetUp() override { save_model(model, path); }
};

TEST_F(HdmFile, RoundTripIsBitForBit) {
  const SlabModel loaded = load_model(path);
  EXPECT_EQ(loaded.grid_n, model.grid_n);
  EXPECT_EQ(loaded.texel_density, model.texel_density);
  EXPECT_TRUE(same_bits(loaded.inner, model.inner));
  EXPECT_TRUE(same_bits(loaded.outer, model.outer));
  EXPECT_TRUE(same_bits(loaded.slabs, model.slabs));
  EXPECT_TRUE(same_bits(loaded.displacement, model.displacement));
  EXPECT_TRUE(same_bits(loaded.colour, model.colour));
  EXPECT_TRUE(same_bits(loaded.friction_static, model.friction_static));
  EXPECT_TRUE(same_bits(loaded.friction_dynamic, model.friction_dynamic));
  EXPECT_TRUE(same_bits(loaded.stiffness_scale, model.stiffness_scale));
  EXPECT_TRUE(same_bits(loaded.roughness, model.roughness));
  EXPECT_TRUE(same_bits(loaded.layer_displacement, model.layer_displacement));
  EXPECT_TRUE(same_bits(loaded.hardness, model.hardness));
  // A field of one value (the octahedron's dynamic friction) loads as that value, with no array;
  // the others keep theirs.
  EXPECT_TRUE(loaded.friction_dynamic.uniform());
  EXPECT_EQ(loaded.friction_dynamic.heap_bytes(), 0u);
  EXPECT_FALSE(loaded.friction_static.uniform());
  EXPECT_FALSE(loaded.hardness.uniform());
  EXPECT_EQ(loaded.under_layer.hardness_hv, 61.5f);
  EXPECT_EQ(loaded.under_layer.colour, model.under_layer.colour);
  EXPECT_EQ(loaded.under_layer.stiffness_scale, model.under_layer.stiffness_scale);
  EXPECT_EQ(loaded.under_layer.friction_static, model.under_layer.friction_static);
  EXPECT_EQ(loaded.under_layer.friction_dynamic, model.under_layer.friction_dynamic);
  EXPECT_EQ(loaded.under_layer.roughness, model.under_layer.roughness);
  EXPECT_EQ(loaded.source, model.source);
  EXPECT_EQ(loaded.source_triangles, model.source_triangles);
  EXPECT_EQ(std::memcmp(&loaded.source_diagonal, &model.source_diagonal, sizeof(double)), 0);
  // Derived data rebuilt: the same slab-major samples (displacement and normal) in every slot.
  ASSERT_EQ(loaded.slab_samples.size(), model.slab_samples.size());
  for (size_t slot = 0; slot < model.slab_samples.size(); ++slot)
    ASSERT_EQ(std::memcmp(&loaded.slab_samples[slot], &model.slab_samples[slot], sizeof(SlabSample)), 0) << slot;

  const std::string again = dir.file("again.hdm");
  save_model(loaded, again);
  EXPECT_EQ(test::read_bytes(again), test::read_bytes(path));
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
}

// Whether the model holds a field of one value as that value or as an array (as the edits
// materialise it) does not change the file: the same codes give the same bytes.
TEST_F(HdmFile, AMaterialisedFieldOfOneValueWritesTheSameBytes) {
  SlabModel edited = model;
  materialise_fields(edited);
  ASSERT_FALSE(edited.friction_dynamic.uniform());
  const std::string other = dir.file("materialised.hdm");
  save_model(edited, other);
  EXPECT_EQ(test::read_bytes(other), test::read_bytes(path));
}

// Texels of one colour and one roughness, as a bake leaves them: each section one element, loaded
// back as one value for every texel.
TEST_F(HdmFile, TexelFieldsOfOneValueAreOneElement) {
  SlabModel one = model;
  one.colour.assign(one.colour.size(), Srgb8{200, 100, 50});
  one.roughness.assign(one.roughness.size(), uint8_t{17});
  save_model(one, path);
  const std::vector<uint8_t> b = test::read_bytes(path);
  const auto at = section_offsets(b);
  ASSERT_EQ(get_u64(b, at.at("COLR")), 1u);
  EXPECT_EQ(b[at.at("COLR") + 8], 200);
  EXPECT_EQ(b[at.at("COLR") + 10], 50);
  ASSERT_EQ(get_u64(b, at.at("RUFF")), 1u);
  EXPECT_EQ(b[at.at("RUFF") + 8], 17);
  const SlabModel loaded = load_model(path);
  EXPECT_TRUE(loaded.colour.uniform());
  EXPECT_TRUE(loaded.roughness.uniform());
  EXPECT_TRUE(loaded.colour == one.colour);
  EXPECT_TRUE(loaded.roughness == one.roughness);
  EXPECT_EQ(loaded.colour.size(), model.colour.size());
}

TEST_F(HdmFile, LayoutFollowsTheSpec) {
  const std::vector<uint8_t> b = test::read_bytes(path);
  ASSERT_GT(b.size(), 16u);
  EXPECT_EQ(std::memcmp(b.data(), "HDM\0", 4), 0);
  EXPECT_EQ(b[4] | b[5] << 8 | b[6] << 16 | b[7] << 24, 7);
  EXPECT_EQ(get_u64(b, b.size() - 8), reference_fnv1a(b.data(), b.size() - 8));
  const auto at = section_offsets(b);
  EXPECT_EQ(get_u64(b, at.at("DISP")), model.displacement.size());
  EXPECT_EQ(get_u64(b, at.at("COLR")), model.colour.size());
  EXPECT_EQ(get_u64(b, at.at("SLAB")), 8u);
  EXPECT_EQ(get_u64(b, at.at("INNR")), 6u);
  EXPECT_EQ(get_u64(b, at.at("RUFF")), model.roughness.size());
  EXPECT_EQ(get_u64(b, at.at("LAYD")), model.layer_displacement.size());
  EXPECT_EQ(get_u64(b, at.at("LAYM")), 1u);
  EXPECT_EQ(get_u64(b, at.at("HARD")), model.hardness.size());
  EXPECT_EQ(get_u64(b, at.at("LAYH")), 1u);
  // The octahedron's dynamic friction is one value: one binary16 code for every sample.
  EXPECT_EQ(get_u64(b, at.at("FRST")), model.friction_static.size());
  ASSERT_EQ(get_u64(b, at.at("FRDY")), 1u);
  EXPECT_EQ(b[at.at("FRDY") + 8] | b[at.at("FRDY") + 9] << 8, Half16(0.3f).bits());
  // Displacements as little-endian unorm16 codes, each within half a step of the pattern's value.
  for (size_t s = 0; s < model.displacement.size(); ++s) {
    const int code = b[at.at("DISP") + 8 + 2 * s] | b[at.at("DISP") + 9 + 2 * s] << 8;
    ASSERT_LE(std::abs(code - 65535.0 * test::sample_displacement(int(s))), 0.5 + 1e-3) << s;  // half a step
  }
  // Stiffness scale and under-layer top as little-endian unorm16 codes, code/65535.
  for (size_t s = 0; s < model.stiffness_scale.size(); ++s)
    for (const auto& [tag, field] : {std::pair{"STIF", &model.stiffness_scale}, {"LAYD", &model.layer_displacement}}) {
      const int code = b[at.at(tag) + 8 + 2 * s] | b[at.at(tag) + 9 + 2 * s] << 8;
      ASSERT_EQ(float(code / 65535.0), float((*field)[s])) << tag << " " << s;
    }
  // Colour as 3 bytes R, G, B per texel, roughness as 1 byte: the texel pattern's sRGB codes.
  for (size_t t = 0; t < model.colour.size(); ++t) {
    const Vec3f c = test::texel_colour(int(t));
    for (int k = 0; k < 3; ++k) ASSERT_EQ(b[at.at("COLR") + 8 + 3 * t + size_t(k)], test::srgb8(c[k])) << t;
    ASSERT_EQ(b[at.at("RUFF") + 8 + t], std::lround(255.0 * double(t % 5) / 4.0)) << t;
  }
  const uint64_t x0 = get_u64(b, at.at("INNR") + 8);
  double x;
  std::memcpy(&x, &x0, 8);
  EXPECT_EQ(x, 0.8);
}

TEST_F(HdmFile, CorruptByteFailsTheChecksum) {
  std::vector<uint8_t> b = test::read_bytes(path);
  const auto at = section_offsets(b);
  b[at.at("DISP") + 8 + 5] ^= 0x10;  // inside the displacement payload
  test::write_bytes(path, b);
  const std::string msg = expect_load_error<IoError>(path);
  EXPECT_NE(msg.find("checksum mismatch (file corrupt)"), std::string::npos) << msg;
}

TEST_F(HdmFile, TruncatedFileFails) {
  const std::vector<uint8_t> b = test::read_bytes(path);
  for (size_t keep : {size_t(0), size_t(3), size_t(6), size_t(30), b.size() / 2, b.size() - 8, b.size() - 1}) {
    test::write_bytes(path, std::vector<uint8_t>(b.begin(), b.begin() + keep));
    const std::string msg = expect_load_error<IoError>(path);
    EXPECT_NE(msg.find("truncated"), std::string::npos) << "kept " << keep << " bytes: " << msg;
  }
}

TEST_F(HdmFile, WrongVersionFails) {
  std::vector<uint8_t> b = test::read_bytes(path);
  b[4] = 8;
  reseal(b);
  test::write_bytes(path, b);
  const std::string msg = expect_load_error<IoError>(path);
  EXPECT_NE(msg.find(path + ": format version 8, this hdm reads versions 1 to 7"), std::string::npos) << msg;
}

TEST_F(HdmFile, BadMagicFails) {
  std::vector<uint8_t> b = test::read_bytes(path);
  b[0] = 'X';
  test::write_bytes(path, b);
  expect_load_error<IoError>(path);
}

TEST_F(HdmFile, HugeCountFailsWithoutAllocating) {
  const std::vector<uint8_t> good = test::read_bytes(path);
  const auto at = section_offsets(good);
  for (const char* tag : {"INNR", "SLAB", "DISP", "COLR", "SRCN"})
    for (uint64_t count : {uint64_t(1) << 62, uint64_t(1) << 32, uint64_t(good.size())}) {
      std::vector<uint8_t> b = good;
      set_u64(b, at.at(tag), count);
      reseal(b);  // a valid checksum, so only the count check can stop it
      test::write_bytes(path, b);
      g_largest = 0;
      g_track = true;
      const std::string msg = expect_load_error<IoError>(path);
      g_track = false;
      EXPECT_LE(g_largest.load(), 4 * good.size()) << tag << " count " << count << ": " << msg;
    }
}

// grid_n and texel_density alone size the sample and texel layouts: a file whose grids do not
// match its DISP and COLR counts is refused before any layout is built. The expected counts come
// from the layout formula in hdm_file.h with the octahedron's 6 corners, 12 edges and 8 slabs.
TEST_F(HdmFile, GridsThatDoNotMatchTheStoredSamplesFailWithoutAllocating) {
  const std::vector<uint8_t> good = test::read_bytes(path);
  const size_t grid = section_offsets(good).at("GRID") + 8;  // grid_n, then texel_density
  auto samples = [](int64_t k) { return 6 + 12 * (k - 1) + 8 * ((k - 1) * (k - 2) / 2); };
  struct Case {
    int32_t n, m;
    const char* message;
  };
  for (const Case& c : {Case{1024, 1, "DISP holds"}, Case{4, 1024, "COLR holds"}, Case{1, 4096, "DISP holds"},
                        Case{4, 3, "COLR holds"}}) {
    std::vector<uint8_t> b = good;
    for (int k = 0; k < 4; ++k) b[grid + k] = uint8_t(uint32_t(c.n) >> (8 * k));
    for (int k = 0; k < 4; ++k) b[grid + 4 + k] = uint8_t(uint32_t(c.m) >> (8 * k));
    reseal(b);
    test::write_bytes(path, b);
    g_largest = 0;
    g_track = true;
    const std::string msg = expect_load_error<InvalidInput>(path);
    g_track = false;
    EXPECT_NE(msg.find(c.message), std::string::npos) << msg;
    const bool disp = std::string(c.message) == "DISP holds";
    EXPECT_NE(msg.find(std::to_string(disp ? samples(c.n) : samples(int64_t(c.n) * c.m))), std::string::npos) << msg;
    EXPECT_LE(g_largest.load(), 4 * good.size()) << c.n << " x " << c.m << ": " << msg;
  }
}

TEST_F(HdmFile, SizeLimitIsCheckedBeforeReading) {
  ModelLoadOptions small;
  small.max_file_bytes = 100;
  EXPECT_THROW(load_model(path, small), IoError);
  const std::vector<uint8_t> bytes = test::read_bytes(path);
  EXPECT_TRUE(same_bits(load_model_from_memory(bytes, "memory.hdm").displacement, model.displacement));
}

TEST_F(HdmFile, InconsistentContentThrowsInvalidInput) {
  std::vector<uint8_t> b = test::read_bytes(path);
  const auto at = section_offsets(b);
  b[at.at("SLAB") + 8] = 99;  // slab 0's R corner -> coarse vertex 99 of 6
  reseal(b);
  test::write_bytes(path, b);
  expect_load_error<InvalidInput>(path);
}

TEST_F(HdmFile, MissingFileThrowsIoError) { expect_load_error<IoError>(dir.file("nothing.hdm")); }

TEST_F(HdmFile, FailedSaveKeepsThePreviousFileAndNamesThePath) {
  const std::vector<uint8_t> before = test::read_bytes(path);
  // The destination is a non-empty directory: the final rename must fail.
  const std::string blocked = dir.file("blocked.hdm");
  std::filesystem::create_directories(blocked + "/keep");
  try {
    save_model(model, blocked);
    ADD_FAILURE() << "no exception";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(blocked), std::string::npos) << e.what();
  }
  EXPECT_TRUE(std::filesystem::is_directory(blocked + "/keep"));
  EXPECT_FALSE(std::filesystem::exists(blocked + ".tmp"));
  // No directory at all: the temporary file cannot be created.
  EXPECT_THROW(save_model(model, dir.file("no/such/dir/m.hdm")), IoError);
  // Overwriting an existing model replaces it completely.
  SlabModel other = model;
  other.displacement[0] = 1.0f;
  rebuild_derived(other);
  save_model(other, path);
  EXPECT_NE(test::read_bytes(path), before);
  EXPECT_EQ(load_model(path).displacement[0], 1.0f);
}

}  // namespace
}  // namespace hdm
