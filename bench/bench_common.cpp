// SPDX-License-Identifier: MIT
#include "bench_common.h"

#include <hdm/io/hdm_file.h>
#include <hdm/io/read_mesh.h>
#include <hdm/slab/bake.h>

#include <cstdlib>
#include <filesystem>
#include <random>

namespace hdm::bench {
namespace {

int env_int(const char* name, int fallback) {
  const char* v = std::getenv(name);
  return v && *v ? std::atoi(v) : fallback;
}

// Walk over the sample graph to random targets, one point every `step` of arc length, offset along
// the normal by a slow sine of amplitude `depth` (a simplified version of hdm bench's path).
std::vector<Vec3> walk(const SlabModel& m, int count, double step, double depth, std::mt19937_64& rng) {
  const SampleLayout& L = m.samples;
  std::uniform_int_distribution<int32_t> pick(0, L.count - 1);
  std::vector<Vec3> out;
  int32_t at = pick(rng), target = pick(rng);
  while (static_cast<int>(out.size()) < count) {
    int32_t next = -1;
    float best = (m.positions[at] - m.positions[target]).squaredNorm();
    for (int32_t e = L.neighbour_offsets[at]; e < L.neighbour_offsets[at + 1]; ++e) {
      const float d = (m.positions[L.neighbours[e]] - m.positions[target]).squaredNorm();
      if (d < best) best = d, next = L.neighbours[e];
    }
    if (next < 0) {
      target = pick(rng);
      continue;
    }
    const Vec3 a = m.positions[at].cast<double>(), b = m.positions[next].cast<double>();
    const Vec3 n = m.normals[at].cast<double>();
    const int k = std::max(1, static_cast<int>((b - a).norm() / step));
    for (int i = 0; i < k; ++i)
      out.push_back(a + (b - a) * (double(i) / k) + depth * std::sin(out.size() * 6.283185307 / 1000) * n);
    at = next;
  }
  out.resize(count);
  return out;
}

}  // namespace

std::string model_path() {
  const char* v = std::getenv("HDM_BENCH_MODEL");
  return v && *v ? v : HDM_BENCH_DEFAULT_MODEL;
}

const Fixture& fixture() {
  static const std::unique_ptr<Fixture> f = [] {
    auto x = std::make_unique<Fixture>();
    x->path = model_path();
    x->mesh = read_mesh(x->path);
    x->diagonal = bounds(x->mesh).diagonal();
    BakeOptions o;
    o.slabs = env_int("HDM_BENCH_SLABS", 0);
    o.grid_n = env_int("HDM_BENCH_GRID", 16);
    o.texel_density = env_int("HDM_BENCH_TEXELS", 2);
    o.separate_slabs = env_int("HDM_BENCH_SEPARATE", 1) != 0;
    // $HDM_BENCH_HDM: a baked model reused across runs (loaded if it exists, else baked and saved),
    // so large models (10^5 slabs: minutes to bake) are baked once for many benchmark runs.
    const char* cached = std::getenv("HDM_BENCH_HDM");
    if (cached && *cached && std::filesystem::exists(cached)) {
      x->model = load_model(cached);
    } else {
      x->model = bake_slabs(x->mesh, x->path, o);
      if (cached && *cached) save_model(x->model, cached);
    }
    x->locator = std::make_unique<SlabLocator>(x->model);
    std::mt19937_64 rng(1);
    x->path_points = walk(x->model, 20000, x->diagonal / 1600, 0.005 * x->diagonal, rng);
    std::uniform_int_distribution<int32_t> pick(0, x->model.samples.count - 1);
    std::uniform_real_distribution<double> off(-0.01, 0.01);
    for (int k = 0; k < 20000; ++k) {
      const int32_t s = pick(rng);
      x->global_points.push_back(x->model.positions[s].cast<double>() +
                                 off(rng) * x->diagonal * x->model.normals[s].cast<double>());
    }
    return x;
  }();
  return *f;
}

}  // namespace hdm::bench
