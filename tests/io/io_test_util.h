// SPDX-License-Identifier: MIT
#pragma once
// Fixtures for the io tests: a hand-built octahedron slab model, temporary directories, file
// bytes, and independent reference formulas (sRGB, FNV-1a).

#include <hdm/slab/slab_model.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <unistd.h>

namespace hdm::test {

/// The six unit vectors ±x, ±y, ±z: the corners of the regular octahedron.
inline std::vector<Vec3> octahedron_vertices() {
  return {Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, 1), Vec3(0, 0, -1)};
}

/// The eight faces of the octahedron, counter-clockwise seen from outside: one per octant, with
/// the corner order flipped where the octant's sign product is negative.
inline std::vector<Tri> octahedron_faces() {
  std::vector<Tri> faces;
  for (int sx : {1, -1})
    for (int sy : {1, -1})
      for (int sz : {1, -1}) {
        const int32_t x = sx > 0 ? 0 : 1, y = sy > 0 ? 2 : 3, z = sz > 0 ? 4 : 5;
        faces.push_back(sx * sy * sz > 0 ? Tri{x, y, z} : Tri{x, z, y});
      }
  return faces;
}

/// Linear colour of texel id @p t: three base-16 digits of t, so every texel below 4096 has its
/// own 8-bit sRGB triple.
inline Vec3f texel_colour(int t) {
  return Vec3f(float(t % 16) / 15.0f, float((t / 16) % 16) / 15.0f, float((t / 256) % 16) / 15.0f);
}

/// Displacement of sample @p s: a pattern in [0.1, 0.9].
inline float sample_displacement(int s) { return 0.1f + 0.2f * float(s % 5); }

/// Octahedron slab model: inner = 0.8·v, outer = 1.2·v, every stored field filled with a known
/// pattern, sizes computed from the layout formulas (#C + (n-1)·#E + (n-1)(n-2)/2·#S), then
/// rebuild_derived().
inline SlabModel octahedron_model(int n = 4, int m = 2) {
  SlabModel model;
  model.grid_n = n;
  model.texel_density = m;
  for (const Vec3& v : octahedron_vertices()) {
    model.inner.push_back(0.8 * v);
    model.outer.push_back(1.2 * v);
  }
  model.slabs = octahedron_faces();
  const int C = 6, E = 12, S = 8, N = n * m;
  const int samples = C + (n - 1) * E + (n - 1) * (n - 2) / 2 * S;
  const int texels = C + (N - 1) * E + (N - 1) * (N - 2) / 2 * S;
  std::vector<Half16> friction_static, friction_dynamic, hardness;
  std::vector<Unorm16> stiffness_scale, layer_displacement;
  for (int s = 0; s < samples; ++s) {
    model.displacement.push_back(sample_displacement(s));
    friction_static.push_back(0.5f + 0.001f * float(s));
    friction_dynamic.push_back(0.3f);  // one value: a uniform field
    stiffness_scale.push_back(s % 2 ? 1.0f : 0.75f);
    layer_displacement.push_back(0.25f * sample_displacement(s));
    hardness.push_back(50.0f + 7.0f * float(s % 40));
  }
  model.friction_static.assign(std::move(friction_static));
  model.friction_dynamic.assign(std::move(friction_dynamic));
  model.stiffness_scale.assign(std::move(stiffness_scale));
  model.layer_displacement.assign(std::move(layer_displacement));
  model.hardness.assign(std::move(hardness));
  std::vector<Srgb8> colour;
  std::vector<uint8_t> roughness;
  for (int t = 0; t < texels; ++t) {
    colour.push_back(encode_srgb8(texel_colour(t)));
    roughness.push_back(unit_to_unorm8(float(t % 5) / 4.0f));
  }
  model.colour.assign(std::move(colour));
  model.roughness.assign(std::move(roughness));
  model.under_layer = UnderLayer{Vec3f(0.9f, 0.7f, 0.2f), 0.4f, 0.6f, 0.45f, 0.3f, 61.5f};
  model.source = "octahedron (hand-built test model)";
  model.source_triangles = 8;
  model.source_diagonal = 2.0 * std::sqrt(3.0);
  rebuild_derived(model);
  return model;
}

/// Reference sRGB encoding (IEC 61966-2-1) of a linear value in [0,1] to 8 bits.
inline int srgb8(float linear) {
  const double c = std::min(1.0, std::max(0.0, double(linear)));
  const double s = c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
  return int(std::floor(s * 255.0 + 0.5));
}

/// A fresh temporary directory, removed when the object goes out of scope.
struct TempDir {
  std::filesystem::path path;
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = info ? std::string(info->test_suite_name()) + "_" + info->name() : std::string("x");
    for (char& c : name)
      if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';  // parameterised names contain '/'
    path = std::filesystem::temp_directory_path() / ("hdm_io_" + std::to_string(::getpid()) + "_" + name);
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  std::string file(const std::string& name) const { return (path / name).string(); }
};

inline std::vector<uint8_t> read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline void write_bytes(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

/// Appends the bytes of @p v to @p s, little-endian (this machine's order) or, with @p big, reversed.
template <class T>
void put(std::string& s, T v, bool big = false) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (big) std::reverse(b, b + sizeof(T));
  s.append(b, sizeof(T));
}

inline void write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

}  // namespace hdm::test
