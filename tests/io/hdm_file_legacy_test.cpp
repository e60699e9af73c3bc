// SPDX-License-Identifier: MIT
// .hdm files of format versions 1 and 2 (float colour and roughness) still load: written here
// section by section from the table in hdm_file.h, loaded, and their texels compared with the IEC
// 61966-2-1 and unorm8 encodings of the written floats. Version 3 files (no hardness) load with
// the default hardness; versions 4 and 5 (float per-sample fields, float displacements) load with
// each value rounded once to its code; version 6 (every field code by code) loads its fields of
// one value as one value.
#include "io/io_test_util.h"
#include "support/test_models.h"

#include <hdm/core/error.h>
#include <hdm/io/hdm_file.h>

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

namespace hdm {
namespace {

using test::TempDir;

// A writer of the version 1 and 2 layouts: little-endian values, tagged sections, FNV-1a.
struct LegacyWriter {
  std::vector<uint8_t> b;
  template <class U>
  void bits(U v) {
    for (size_t k = 0; k < sizeof(U); ++k) b.push_back(uint8_t(v >> (8 * k)));
  }
  void f32(float v) { bits(std::bit_cast<uint32_t>(v)); }
  void f64(double v) { bits(std::bit_cast<uint64_t>(v)); }
  void tag(const char* t, uint64_t count) {
    b.insert(b.end(), t, t + 4);
    bits(count);
  }
  template <class Field>
  void floats(const char* t, const Field& v) {
    tag(t, v.size());
    for (const auto x : v) f32(float(x));
  }
  void seal() {
    uint64_t h = 0xcbf29ce484222325ull;
    for (uint8_t c : b) h = (h ^ c) * 0x100000001b3ull;
    bits(h);
  }
};

// The model's stored data as a version 1 or 2 file, with @p colour and @p roughness as the floats
// those versions kept (version 1 stops after SRCD).
std::vector<uint8_t> legacy_file(const SlabModel& m, const std::vector<Vec3f>& colour,
                                 const std::vector<float>& roughness, uint32_t version) {
  LegacyWriter w;
  w.b = {'H', 'D', 'M', 0};
  w.bits(version);
  w.tag("GRID", 2);
  w.bits(uint32_t(m.grid_n));
  w.bits(uint32_t(m.texel_density));
  for (const auto* v : {&m.inner, &m.outer}) {
    w.tag(v == &m.inner ? "INNR" : "OUTR", v->size());
    for (const Vec3& p : *v)
      for (int k = 0; k < 3; ++k) w.f64(p[k]);
  }
  w.tag("SLAB", m.slabs.size());
  for (const Tri& t : m.slabs)
    for (int k = 0; k < 3; ++k) w.bits(uint32_t(t[k]));
  w.floats("DISP", m.displacement);
  w.tag("COLR", colour.size());
  for (const Vec3f& c : colour)
    for (int k = 0; k < 3; ++k) w.f32(c[k]);
  w.floats("FRST", m.friction_static);
  w.floats("FRDY", m.friction_dynamic);
  w.floats("STIF", m.stiffness_scale);
  w.tag("SRCN", m.source.size());
  w.b.insert(w.b.end(), m.source.begin(), m.source.end());
  w.tag("SRCT", 1);
  w.bits(uint64_t(m.source_triangles));
  w.tag("SRCD", 1);
  w.f64(m.source_diagonal);
  if (version >= 2) {
    w.floats("RUFF", roughness);
    w.floats("LAYD", m.layer_displacement);
    w.tag("LAYM", 1);
    const UnderLayer& u = m.under_layer;
    for (float v : {u.colour.x(), u.colour.y(), u.colour.z(), u.stiffness_scale, u.friction_static, u.friction_dynamic,
                    u.roughness})
      w.f32(v);
  }
  w.seal();
  return w.b;
}

// IEC 61966-2-1: the encoded value of a linear channel in [0,1], in [0,1].
double srgb_encoded(double c) { return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055; }

class HdmLegacyFile : public ::testing::Test {
 protected:
  SlabModel model = test::octahedron_model();
  std::vector<Vec3f> colour;
  std::vector<float> roughness;
  TempDir dir;
  std::string path = dir.file("old.hdm");
  void SetUp() override {
    // Floats between the 8-bit codes, so the load must round.
    for (size_t t = 0; t < model.colour.size(); ++t) {
      const float f = float(t) / float(model.colour.size());
      colour.emplace_back(f, 0.37f * f + 0.01f, 1.0f - f);
      roughness.push_back(0.5f * f + 0.013f);
    }
  }
  // The loaded texels are the written floats rounded once: within half a code step of each.
  void expect_quantised(const SlabModel& loaded, bool with_roughness) const {
    ASSERT_EQ(loaded.colour.size(), colour.size());
    for (size_t t = 0; t < colour.size(); ++t) {
      const Srgb8 c = loaded.colour[t];
      const int code[3] = {c.r, c.g, c.b};
      for (int k = 0; k < 3; ++k)
        ASSERT_LE(std::abs(code[k] - 255.0 * srgb_encoded(colour[t][k])), 0.5 + 1e-9) << t << " " << k;
      const double r = with_roughness ? roughness[t] : 1.0;
      ASSERT_LE(std::abs(loaded.roughness[t] - 255.0 * r), 0.5 + 1e-9) << t;
    }
  }
};

TEST_F(HdmLegacyFile, Version2FileLoadsWithColoursRoundedOnce) {
  test::write_bytes(path, legacy_file(model, colour, roughness, 2));
  const SlabModel loaded = load_model(path);
  expect_quantised(loaded, true);
  EXPECT_EQ(test::values(loaded.displacement), test::values(model.displacement));
  EXPECT_EQ(test::values(loaded.layer_displacement), test::values(model.layer_displacement));
  EXPECT_EQ(loaded.under_layer.colour, model.under_layer.colour);
  // Saved again, it is a version 7 file holding the same codes.
  const std::string again = dir.file("again.hdm");
  save_model(loaded, again);
  const std::vector<uint8_t> b = test::read_bytes(again);
  EXPECT_EQ(b[4], 7);
  const SlabModel reloaded = load_model(again);
  EXPECT_EQ(reloaded.colour, loaded.colour);
  EXPECT_EQ(reloaded.roughness, loaded.roughness);
}

// A version-1 file (no roughness, under-layer sections) loads with those fields' defaults.
TEST_F(HdmLegacyFile, Version1FileLoadsWithDefaults) {
  test::write_bytes(path, legacy_file(model, colour, roughness, 1));
  const SlabModel loaded = load_model(path);
  expect_quantised(loaded, false);
  ASSERT_EQ(loaded.layer_displacement.size(), model.layer_displacement.size());
  for (float d : loaded.layer_displacement) ASSERT_EQ(d, 0.0f);
  EXPECT_EQ(loaded.under_layer.colour, UnderLayer{}.colour);
}

// IEEE 754 binary16 bits -> value, from the format's definition (sign, 5-bit exponent, 10-bit
// fraction, subnormals below exponent 1).
double binary16_value(uint16_t h) {
  const int e = (h >> 10) & 31, f = h & 1023;
  const double v = e == 0 ? std::ldexp(double(f), -24) : e == 31 ? INFINITY : std::ldexp(double(1024 + f), e - 25);
  return h >> 15 ? -v : v;
}

// The sections of a version 7 file (the table in hdm_file.h) as an older @p version stores them:
// a per-sample field written as one code (version 7) repeated for every sample, the displacements
// (DISP) as float32 before version 6, and the other five 16-bit field sections too before version
// 5. @p value maps (tag, element index, stored code) to the float.
template <class Value>
std::vector<uint8_t> as_version(const std::vector<uint8_t>& v7, uint8_t version, Value value) {
  const std::vector<std::pair<std::string, size_t>> layout = {
      {"GRID", 4}, {"INNR", 24}, {"OUTR", 24}, {"SLAB", 12}, {"DISP", 2}, {"COLR", 3},
      {"FRST", 2}, {"FRDY", 2},  {"STIF", 2},  {"SRCN", 1},  {"SRCT", 8}, {"SRCD", 8},
      {"RUFF", 1}, {"LAYD", 2},  {"LAYM", 28}, {"HARD", 2},  {"LAYH", 4}};
  const std::vector<uint8_t>& v6 = v7;
  LegacyWriter w;
  w.b.assign(v6.begin(), v6.begin() + 8);
  w.b[4] = version;
  size_t pos = 8;
  uint64_t samples = 0;  // DISP's count
  for (const auto& [tag, bytes] : layout) {
    EXPECT_EQ(std::string(reinterpret_cast<const char*>(&v6[pos]), 4), tag);
    uint64_t count = 0;
    for (int k = 7; k >= 0; --k) count = (count << 8) | v6[pos + 4 + k];
    const size_t body = pos + 12;
    if (tag == "DISP") samples = count;
    auto code = [&](uint64_t k) { return uint16_t(v6[body + 2 * k] | v6[body + 2 * k + 1] << 8); };
    const bool one = bytes == 2 && tag != "DISP" && count == 1 && samples > 1;  // version 7: one code for all
    if (bytes == 2 && (version <= 4 || (version <= 5 && tag == "DISP"))) {
      w.tag(tag.c_str(), one ? samples : count);
      for (uint64_t k = 0; k < (one ? samples : count); ++k) w.f32(value(tag, k, code(one ? 0 : k)));
    } else if (one && version < 7) {
      w.tag(tag.c_str(), samples);
      for (uint64_t k = 0; k < samples; ++k) w.bits(code(0));
    } else {
      w.b.insert(w.b.end(), v6.begin() + pos, v6.begin() + body + count * bytes);
    }
    pos = body + count * bytes;
  }
  EXPECT_EQ(pos + 8, v6.size());
  w.seal();
  return w.b;
}
template <class Value>
std::vector<uint8_t> as_version4(const std::vector<uint8_t>& v6, Value value) {
  return as_version(v6, 4, value);
}

// The float a 16-bit field's code stands for: unorm16 code/65535, binary16 by its definition.
float code_value(const std::string& tag, uint16_t code) {
  return tag == "STIF" || tag == "LAYD" || tag == "DISP" ? float(code / 65535.0) : float(binary16_value(code));
}

// A version 4 file stores the per-sample fields as float32. Written from the model's own codes it
// loads to the same model; written with floats between the codes, each loads rounded once to the
// nearest code (found here by trying every code).
TEST_F(HdmLegacyFile, Version4FileLoadsWithItsFloatFieldsRoundedOnce) {
  for (size_t s = 0; s < model.friction_static.size(); ++s) {  // fields that differ per sample
    model.friction_static.set(s, 0.1f + 0.01f * float(s));
    model.stiffness_scale.set(s, 0.5f + 0.003f * float(s));
    model.hardness.set(s, 250.0f + float(s));
  }
  save_model(model, path);
  const std::vector<uint8_t> v5 = test::read_bytes(path);
  test::write_bytes(path, as_version4(v5, [](const std::string& t, uint64_t, uint16_t c) { return code_value(t, c); }));
  const SlabModel same = load_model(path);
  for (size_t s = 0; s < model.friction_static.size(); ++s) {
    ASSERT_EQ(same.friction_static[s].bits(), model.friction_static[s].bits()) << s;
    ASSERT_EQ(same.stiffness_scale[s].code, model.stiffness_scale[s].code) << s;
    ASSERT_EQ(same.hardness[s].bits(), model.hardness[s].bits()) << s;
    ASSERT_EQ(same.layer_displacement[s].code, model.layer_displacement[s].code) << s;
  }
  // Floats off the codes: each field's value k·0.0123457 + 0.01 (hardness ×1000), rounded on load.
  auto written = [](const std::string& t, uint64_t k) {
    const double x = 0.01 + 0.0123457 * double(k % 80);
    return float(t == "HARD" ? 1000 * x + 1 : x);
  };
  test::write_bytes(path, as_version4(v5, [&](const std::string& t, uint64_t k, uint16_t) { return written(t, k); }));
  const SlabModel loaded = load_model(path);
  auto nearest = [](const std::string& t, float x) {  // the code nearest x, by trying all of them
    float best = NAN;
    for (int c = 0; c < 65536; ++c) {
      const float v = code_value(t, uint16_t(c));
      if (std::isfinite(v) && !(std::abs(v - x) >= std::abs(best - x))) best = v;
    }
    return best;
  };
  for (size_t s = 0; s < loaded.friction_static.size(); s += 7) {
    ASSERT_EQ(float(loaded.friction_static[s]), nearest("FRST", written("FRST", s))) << s;
    ASSERT_EQ(float(loaded.stiffness_scale[s]), nearest("STIF", written("STIF", s))) << s;
    ASSERT_EQ(float(loaded.layer_displacement[s]), nearest("LAYD", written("LAYD", s))) << s;
    ASSERT_EQ(float(loaded.hardness[s]), nearest("HARD", written("HARD", s))) << s;
  }
  // A value the 16-bit field cannot hold is refused by name.
  test::write_bytes(path, as_version4(v5, [&](const std::string& t, uint64_t k, uint16_t c) {
                      return t == "STIF" && k == 3 ? 1.5f : code_value(t, c);
                    }));
  try {
    load_model(path);
    ADD_FAILURE() << "a stiffness scale of 1.5 loaded";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find(path + ": stiffness scale of sample 3 is 1.5"), std::string::npos) << e.what();
  }
}

// A version 5 file stores the displacements as float32 and the other 16-bit fields as codes.
// Written from the model's own codes it loads to the same model; written with floats between the
// codes, each displacement loads as the code nearest it; one outside [0, 1] is refused by name.
TEST_F(HdmLegacyFile, Version5FileLoadsWithItsFloatDisplacementsRoundedOnce) {
  save_model(model, path);
  const std::vector<uint8_t> v6 = test::read_bytes(path);
  test::write_bytes(path,
                    as_version(v6, 5, [](const std::string& t, uint64_t, uint16_t c) { return code_value(t, c); }));
  const SlabModel same = load_model(path);
  for (size_t s = 0; s < model.displacement.size(); ++s)
    ASSERT_EQ(same.displacement[s].code, model.displacement[s].code) << s;
  EXPECT_EQ(test::values(same.friction_static), test::values(model.friction_static));
  auto written = [](uint64_t k) { return float(0.01 + 0.0123457 * double(k % 80)); };
  test::write_bytes(path, as_version(v6, 5, [&](const std::string&, uint64_t k, uint16_t) { return written(k); }));
  const SlabModel loaded = load_model(path);
  for (size_t s = 0; s < loaded.displacement.size(); ++s) {
    const int c = loaded.displacement[s].code;  // no code is nearer the written float
    for (int other : {c - 1, c + 1})
      ASSERT_LE(std::abs(c / 65535.0 - written(s)), std::abs(other / 65535.0 - written(s)) + 1e-9) << s;
  }
  test::write_bytes(path, as_version(v6, 5, [&](const std::string&, uint64_t k, uint16_t c) {
                      return k == 3 ? 1.5f : code_value("DISP", c);
                    }));
  try {
    load_model(path);
    ADD_FAILURE() << "a displacement of 1.5 loaded";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find(path + ": displacement of sample 3 is 1.5"), std::string::npos) << e.what();
  }
}

// A version 6 file stores every per-sample field code by code, a field of one value included:
// it loads to the same model, that field uniform (no array), and saved again it is the version 7
// file, one code for that field.
TEST_F(HdmLegacyFile, Version6FileLoadsWithItsUniformFieldsAsOneValue) {
  ASSERT_TRUE(model.friction_dynamic.uniform());  // the octahedron's: 0.3 everywhere
  save_model(model, path);
  const std::vector<uint8_t> v7 = test::read_bytes(path);
  const std::vector<uint8_t> v6 =
      as_version(v7, 6, [](const std::string& t, uint64_t, uint16_t c) { return code_value(t, c); });
  EXPECT_EQ(v6.size(), v7.size() + 2 * (model.displacement.size() - 1));  // FRDY written out
  test::write_bytes(path, v6);
  const SlabModel loaded = load_model(path);
  EXPECT_TRUE(loaded.friction_dynamic.uniform());
  EXPECT_TRUE(loaded.friction_dynamic == model.friction_dynamic);
  EXPECT_TRUE(loaded.friction_static == model.friction_static);
  EXPECT_TRUE(loaded.hardness == model.hardness);
  EXPECT_TRUE(loaded.layer_displacement == model.layer_displacement);
  EXPECT_TRUE(loaded.stiffness_scale == model.stiffness_scale);
  save_model(loaded, path);
  EXPECT_EQ(test::read_bytes(path), v7);
}

// A version-3 file is a version-4 file without its last two sections (HARD, LAYH): it loads with
// the default hardness, everything else as stored.
TEST_F(HdmLegacyFile, Version3FileLoadsWithTheDefaultHardness) {
  save_model(model, path);
  std::vector<uint8_t> b =
      as_version4(test::read_bytes(path), [](const std::string& t, uint64_t, uint16_t c) { return code_value(t, c); });
  const size_t hard = b.size() - 8 - (12 + 4 * model.hardness.size()) - (12 + 4);  // HARD as float32
  ASSERT_EQ(std::string(reinterpret_cast<const char*>(&b[hard]), 4), "HARD");
  b.resize(hard);
  b[4] = 3;
  LegacyWriter w;
  w.b = b;
  w.seal();
  test::write_bytes(path, w.b);
  const SlabModel loaded = load_model(path);
  ASSERT_EQ(loaded.hardness.size(), model.displacement.size());
  for (float h : loaded.hardness) ASSERT_EQ(h, default_hardness_hv);
  EXPECT_EQ(loaded.under_layer.hardness_hv, UnderLayer{}.hardness_hv);
  EXPECT_EQ(test::values(loaded.displacement), test::values(model.displacement));
  EXPECT_EQ(loaded.colour, model.colour);
  EXPECT_EQ(test::values(loaded.layer_displacement), test::values(model.layer_displacement));
  EXPECT_EQ(loaded.under_layer.roughness, model.under_layer.roughness);
}

TEST_F(HdmLegacyFile, NonFiniteColourOrRoughnessOutsideTheUnitIntervalIsRefused) {
  colour[5].y() = std::nanf("");
  test::write_bytes(path, legacy_file(model, colour, roughness, 2));
  try {
    load_model(path);
    ADD_FAILURE() << "a NaN colour loaded";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find(path + ": colour of texel 5 is not finite"), std::string::npos) << e.what();
  }
  colour[5].y() = 0.5f;
  roughness[7] = 1.5f;
  test::write_bytes(path, legacy_file(model, colour, roughness, 2));
  try {
    load_model(path);
    ADD_FAILURE() << "a roughness of 1.5 loaded";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("roughness of texel 7 is outside [0, 1]"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hdm
