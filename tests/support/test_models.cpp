// SPDX-License-Identifier: MIT
#include "support/test_models.h"

#include <hdm/io/read_mesh.h>
#include <hdm/slab/bake.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <cmath>
#include <map>
#include <memory>
#include <numbers>
#include <random>
#include <set>

namespace hdm::test {

std::string data_path(const std::string& name) {
  const std::string p = (std::filesystem::path(HDM_DATA_DIR) / name).string();
  if (!std::filesystem::exists(p)) ADD_FAILURE() << p << " missing: run scripts/setup.sh";
  return p;
}

const TriangleMesh& bunny() {
  static const TriangleMesh mesh = read_mesh(data_path("bunny00.off"));
  return mesh;
}

const SlabModel& baked_bunny(int slabs, int grid) {
  static std::map<std::pair<int, int>, std::unique_ptr<SlabModel>> cache;
  auto& slot = cache[{slabs, grid}];
  if (!slot) {
    BakeOptions o;
    o.slabs = slabs;
    o.grid_n = grid;
    slot = std::make_unique<SlabModel>(bake_slabs(bunny(), "bunny00.off", o));
  }
  return *slot;
}

TriangleMesh crumpled_icosphere(int subdivisions, double size, double twist_deg) {
  TriangleMesh m = icosphere(subdivisions, 1.0);
  const Vec3 c = m.vertices[0], n = c.normalized();
  std::set<int32_t> ring;
  for (const Tri& t : m.faces)
    if (t[0] == 0 || t[1] == 0 || t[2] == 0)
      for (int32_t v : t)
        if (v != 0) ring.insert(v);
  const double a = twist_deg * std::numbers::pi / 180;
  for (int32_t r : ring) {
    Vec3 d = m.vertices[r] - c;
    d -= d.dot(n) * n;  // in the tangent plane, then turned about n (Rodrigues) and shrunk
    const Vec3 turned = d * std::cos(a) + n.cross(d) * std::sin(a);
    m.vertices[r] = c + size * turned;
  }
  return m;
}

int count_empty_cones(const TriangleMesh& mesh, double margin) {
  constexpr int kDirections = 40000;
  std::vector<Vec3> dirs(kDirections);
  const double golden = std::numbers::pi * (3 - std::sqrt(5.0));
  for (int i = 0; i < kDirections; ++i) {
    const double z = 1 - 2 * (i + 0.5) / kDirections, r = std::sqrt(1 - z * z);
    dirs[i] = Vec3(r * std::cos(golden * i), r * std::sin(golden * i), z);
  }
  std::vector<std::vector<Vec3>> star(mesh.vertices.size());
  for (const Tri& t : mesh.faces) {
    const Vec3 nrm = (mesh.vertices[t[1]] - mesh.vertices[t[0]]).cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]);
    if (nrm.norm() > 0)
      for (int32_t v : t) star[v].push_back(nrm.normalized());
  }
  auto worst = [](const std::vector<Vec3>& normals, const Vec3& d) {
    double w = 2;
    for (const Vec3& x : normals) w = std::min(w, d.dot(x));
    return w;
  };
  int empty = 0;
  for (const std::vector<Vec3>& normals : star) {
    if (normals.empty()) continue;
    double best = -2;
    Vec3 best_d = dirs[0];
    for (const Vec3& d : dirs)
      if (const double w = worst(normals, d); w > best) best = w, best_d = d;
    // Refine around the best sample: random steps of shrinking size, kept when better.
    std::mt19937 rng(1);
    std::normal_distribution<double> g(0, 1);
    for (double step = 0.02; step > 1e-5; step *= 0.7)
      for (int k = 0; k < 20; ++k) {
        const Vec3 d = (best_d + step * Vec3(g(rng), g(rng), g(rng))).normalized();
        if (const double w = worst(normals, d); w > best) best = w, best_d = d;
      }
    empty += !(best > margin);
  }
  return empty;
}

TriangleMesh icosphere(int subdivisions, double radius, const Vec3& centre) {
  const double t = (1 + std::sqrt(5.0)) / 2;
  TriangleMesh m;
  m.vertices = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  m.faces = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
             {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
             {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (Vec3& v : m.vertices) v.normalize();
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      m.vertices.push_back((m.vertices[a] + m.vertices[b]).normalized());
      return mid[key] = static_cast<int>(m.vertices.size()) - 1;
    };
    std::vector<Tri> faces;
    for (const Tri& f : m.faces) {
      const int a = midpoint(f[0], f[1]), b = midpoint(f[1], f[2]), c = midpoint(f[2], f[0]);
      faces.push_back({f[0], a, c});
      faces.push_back({f[1], b, a});
      faces.push_back({f[2], c, b});
      faces.push_back({a, b, c});
    }
    m.faces = std::move(faces);
  }
  for (Vec3& v : m.vertices) v = centre + radius * v;
  return m;
}

Vec3 point_from_corners(const SlabModel& m, int slab, const Vec3& w, double alpha) {
  Vec3 p = Vec3::Zero();
  for (int k = 0; k < 3; ++k) {
    const int v = m.slabs[slab][k];
    p += w[k] * (m.inner[v] + alpha * (m.outer[v] - m.inner[v]));
  }
  return p;
}

TriangleMesh fan_capped_disk(int n) {
  TriangleMesh m;
  for (double z : {0.0, 0.1})
    for (int k = 0; k < n; ++k) m.vertices.emplace_back(std::cos(2 * M_PI * k / n), std::sin(2 * M_PI * k / n), z);
  for (int k = 0; k < n; ++k) {
    const int a = k, b = (k + 1) % n;
    m.faces.push_back({a, b, n + b});
    m.faces.push_back({a, n + b, n + a});
  }
  for (int k = 1; k < n - 1; ++k) {
    m.faces.push_back({0, k + 1, k});
    m.faces.push_back({n, n + k, n + k + 1});
  }
  return m;
}

std::pair<size_t, size_t> append(TriangleMesh& to, const TriangleMesh& part) {
  const auto base = static_cast<int32_t>(to.vertices.size());
  const size_t first = to.faces.size();
  to.vertices.insert(to.vertices.end(), part.vertices.begin(), part.vertices.end());
  for (const Tri& t : part.faces) to.faces.push_back({t[0] + base, t[1] + base, t[2] + base});
  return {first, to.faces.size()};
}

double signed_volume(const TriangleMesh& m) {
  double v = 0;
  for (const Tri& t : m.faces) v += m.vertices[t[0]].dot(m.vertices[t[1]].cross(m.vertices[t[2]])) / 6;
  return v;
}

}  // namespace hdm::test
