// SPDX-License-Identifier: MIT
// analyze_topology() against a brute-force count: every edge's uses and directions tallied in an
// ordered map, components by a breadth-first search over the edges, on random soups full of the
// defects it counts (non-manifold edges, faces traversing an edge the same way, repeated vertex
// ids, zero-area faces) and on a closed sphere.
#include <hdm/mesh/triangle_mesh.h>

#include "support/test_models.h"

#include <gtest/gtest.h>

#include <map>
#include <random>
#include <utility>
#include <vector>

namespace hdm {
namespace {

MeshTopology brute_force(const TriangleMesh& m) {
  MeshTopology t;
  std::map<std::pair<int32_t, int32_t>, std::pair<int, int>> edges;  // (lo, hi) -> (uses, lo→hi uses)
  std::vector<std::vector<int32_t>> next(m.vertices.size());
  for (const Tri& f : m.faces) {
    // A face that repeats a vertex id is degenerate and joins nothing: it has no proper edge.
    if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) {
      ++t.degenerate_faces;
      continue;
    }
    // Integer coordinates: a zero cross product is exact.
    if ((m.vertices[f[1]] - m.vertices[f[0]]).cross(m.vertices[f[2]] - m.vertices[f[0]]).squaredNorm() == 0)
      ++t.degenerate_faces;
    for (int k = 0; k < 3; ++k) {
      const int32_t a = f[k], b = f[(k + 1) % 3];
      auto& e = edges[{std::min(a, b), std::max(a, b)}];
      ++e.first, e.second += a < b;
      next[a].push_back(b), next[b].push_back(a);
    }
  }
  for (const auto& [key, e] : edges) {
    if (e.first == 1) ++t.boundary_edges;
    if (e.first > 2) ++t.non_manifold_edges;
    if (e.first == 2 && e.second != 1) ++t.inconsistent_edges;
  }
  std::vector<uint8_t> seen(m.vertices.size(), 0);
  for (size_t v = 0; v < m.vertices.size(); ++v) {
    if (seen[v]) continue;
    ++t.components;
    std::vector<int32_t> stack{int32_t(v)};
    seen[v] = 1;
    while (!stack.empty()) {
      const int32_t u = stack.back();
      stack.pop_back();
      for (int32_t w : next[u])
        if (!seen[w]) seen[w] = 1, stack.push_back(w);
    }
  }
  return t;
}

void expect_same(const MeshTopology& got, const MeshTopology& want, const std::string& what) {
  EXPECT_EQ(got.boundary_edges, want.boundary_edges) << what;
  EXPECT_EQ(got.non_manifold_edges, want.non_manifold_edges) << what;
  EXPECT_EQ(got.inconsistent_edges, want.inconsistent_edges) << what;
  EXPECT_EQ(got.degenerate_faces, want.degenerate_faces) << what;
  EXPECT_EQ(got.components, want.components) << what;
}

TEST(AnalyzeTopologyTest, RandomSoupsCountAsABruteForceTallyDoes) {
  std::mt19937 rng(20261126);
  int64_t defects = 0;
  for (int trial = 0; trial < 200; ++trial) {
    TriangleMesh m;
    const int nv = 3 + int(rng() % 40), nf = 1 + int(rng() % 150);
    std::uniform_int_distribution<int> coord(0, 3), id(0, nv - 1);
    for (int v = 0; v < nv; ++v) m.vertices.emplace_back(coord(rng), coord(rng), coord(rng));
    for (int f = 0; f < nf; ++f) m.faces.push_back({id(rng), id(rng), id(rng)});
    const MeshTopology want = brute_force(m);
    defects += want.non_manifold_edges + want.inconsistent_edges + want.degenerate_faces;
    expect_same(analyze_topology(m), want, "trial " + std::to_string(trial));
  }
  EXPECT_GT(defects, 1000);  // the soups do hold what is counted
}

TEST(AnalyzeTopologyTest, ASphereAndTwoSpheresWithAFlippedFace) {
  TriangleMesh s = test::icosphere(4, 1.0);
  for (Vec3& v : s.vertices) v = (v * 1024).array().round();  // integer coordinates, as brute_force() wants
  const MeshTopology one = analyze_topology(s);
  expect_same(one, brute_force(s), "sphere");
  EXPECT_EQ(one.boundary_edges + one.non_manifold_edges + one.inconsistent_edges, 0);
  EXPECT_EQ(one.components, 1);
  TriangleMesh two = s;
  const auto nv = int32_t(s.vertices.size());
  for (const Vec3& v : s.vertices) two.vertices.push_back(v + Vec3(4096, 0, 0));
  for (Tri t : s.faces) two.faces.push_back({t[0] + nv, t[1] + nv, t[2] + nv});
  std::swap(two.faces.back()[1], two.faces.back()[2]);
  const MeshTopology t = analyze_topology(two);
  expect_same(t, brute_force(two), "two spheres");
  EXPECT_EQ(t.inconsistent_edges, 3);
  EXPECT_EQ(t.components, 2);
}

}  // namespace
}  // namespace hdm
