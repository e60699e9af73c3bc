// SPDX-License-Identifier: MIT
// untangle() on crumpled spheres, against the plain sweep it shortens: every star's figure
// searched anew at every test, every trial judged on all the stars around it, no try skipped.
// The kept figures and the early stops must not change a single decision, so the vertices end
// bit for bit where the plain sweep puts them.
#include "../../src/mesh/max_min_direction.h"
#include "../../src/slab/coarse_surface.h"
#include "support/test_models.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace hdm {
namespace {

// The plain sweep: the faces of each star in ascending order (as the bake's vertex -> faces lists).
class PlainUntangle {
 public:
  explicit PlainUntangle(slab::detail::CoarseMesh& c) : c_(c), star_(c.vertices.size()) {
    for (size_t f = 0; f < c.faces.size(); ++f)
      for (int32_t v : c.faces[f]) star_[v].push_back(static_cast<int32_t>(f));
  }

  void run() {
    for (int it = 0; it < 20; ++it) {
      bool moved = false;
      for (int32_t v = 0; v < static_cast<int32_t>(c_.vertices.size()); ++v) moved |= try_vertex(v, it >= 10);
      if (!moved && it >= 10) return;
      if (!moved) it = 9;
    }
  }

 private:
  double figure(int32_t v) const {
    std::vector<Vec3> normals;
    Vec3 mean = Vec3::Zero();
    for (int32_t f : star_[v]) {
      const Tri& t = c_.faces[f];
      const Vec3 n = (c_.vertices[t[1]] - c_.vertices[t[0]]).cross(c_.vertices[t[2]] - c_.vertices[t[0]]);
      if (n.norm() > 0) normals.push_back(n.normalized()), mean += normals.back();
    }
    if (normals.empty()) return 1.0;
    const Vec3 d = mean.norm() > 0 ? Vec3(mean.normalized()) : normals[0];
    double best = 2;
    for (const Vec3& n : normals) best = std::min(best, d.dot(n));
    if (best <= 0.5) mesh::detail::improve_max_min_figure(normals, best);
    return best;
  }
  std::vector<int32_t> ring(int32_t v) const {
    std::vector<int32_t> r;
    for (int32_t f : star_[v])
      for (int32_t u : c_.faces[f])
        if (u != v) r.push_back(u);
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
    return r;
  }
  double worst(const std::vector<int32_t>& vs) const {
    double w = 2;
    for (int32_t u : vs) w = std::min(w, figure(u));
    return w;
  }
  bool try_vertex(int32_t v, bool with_ring) {
    if (figure(v) > 0.02) return false;
    std::vector<int32_t> movers{v}, affected;
    if (with_ring) {
      const std::vector<int32_t> r = ring(v);
      movers.insert(movers.end(), r.begin(), r.end());
    }
    for (int32_t m : movers) {
      const std::vector<int32_t> r = ring(m);
      affected.push_back(m);
      affected.insert(affected.end(), r.begin(), r.end());
    }
    std::sort(affected.begin(), affected.end());
    affected.erase(std::unique(affected.begin(), affected.end()), affected.end());
    const double before = worst(affected);
    std::vector<Vec3> old(movers.size()), target(movers.size());
    for (size_t k = 0; k < movers.size(); ++k) {
      const std::vector<int32_t> r = ring(movers[k]);
      Vec3 m = Vec3::Zero();
      for (int32_t u : r) m += c_.vertices[u];
      old[k] = c_.vertices[movers[k]];
      target[k] = r.empty() ? old[k] : Vec3(m / double(r.size()));
    }
    for (const double step : {0.5, 0.25, 0.1}) {
      for (size_t k = 0; k < movers.size(); ++k) {
        const double s = k ? 0.5 * step : step;
        c_.vertices[movers[k]] = (1 - s) * old[k] + s * target[k];
      }
      if (worst(affected) > before + 1e-6) return true;
      for (size_t k = 0; k < movers.size(); ++k) c_.vertices[movers[k]] = old[k];
    }
    return false;
  }

  slab::detail::CoarseMesh& c_;
  std::vector<std::vector<int32_t>> star_;
};

// An icosphere crumpled at vertex 0 (test_models.h), with @p pushed more vertices each pushed
// along a random direction by up to @p amount of the radius: stars folded over their neighbours.
slab::detail::CoarseMesh tangled_sphere(double size, double twist, int pushed, double amount, unsigned seed) {
  TriangleMesh m = test::crumpled_icosphere(3, size, twist);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<size_t> pick(1, m.vertices.size() - 1);
  std::normal_distribution<double> g(0, 1);
  for (int k = 0; k < pushed; ++k) m.vertices[pick(rng)] += amount * Vec3(g(rng), g(rng), g(rng)).normalized();
  return {m.vertices, m.faces};
}

TEST(Untangle, MovesTheVerticesBitForBitAsThePlainSweepDoes) {
  int moved_cases = 0;
  for (const unsigned seed : {1u, 2u, 3u, 4u, 5u, 6u}) {
    const slab::detail::CoarseMesh in = tangled_sphere(0.1, 150, 12, 0.3, seed);
    ASSERT_GT(test::count_empty_cones(TriangleMesh{in.vertices, in.faces}), 0) << "seed " << seed;
    slab::detail::CoarseMesh kept = in, plain = in;
    slab::detail::untangle(kept);
    PlainUntangle(plain).run();
    ASSERT_EQ(kept.faces, in.faces);
    ASSERT_EQ(kept.vertices.size(), plain.vertices.size());
    for (size_t v = 0; v < kept.vertices.size(); ++v)
      ASSERT_EQ(kept.vertices[v], plain.vertices[v]) << "seed " << seed << ", vertex " << v;
    moved_cases += kept.vertices != in.vertices;
  }
  // The comparison means something only where the sweep moved vertices.
  EXPECT_GE(moved_cases, 4);
}

}  // namespace
}  // namespace hdm
