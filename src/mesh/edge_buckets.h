// SPDX-License-Identifier: MIT
#pragma once
// Internal to the mesh code: the half-edges of a triangle mesh grouped by undirected edge, the one
// edge grouping analyze_topology() and orient_outward() share. A counting sort by the edge's lower
// vertex, then a sort of each vertex's few entries: O(#F + #V), where one comparison sort of the
// 3 #F edge keys took 3.4 s at 12.6 M faces (this: 1.0 s for analyze_topology() as a whole).

#include <hdm/mesh/triangle_mesh.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

namespace hdm::mesh::detail {

// Half-edge 3f + k (face f's vertex k to vertex k + 1) of an edge (lo, hi), lo <= hi, is the entry
// `(hi << 1 | (lo is its first vertex and lo != hi)) << 32 | (3f + k)` of bucket lo, the entries
// [start[lo], start[lo + 1]) of `uses`. Within a bucket, after sort(lo), the entries run by hi,
// then direction, then half-edge. Preconditions: vertex ids in [0, #V), 3 #F < 2³².
struct EdgeBuckets {
  std::vector<uint64_t> start;  // #V + 1
  std::vector<uint64_t> uses;

  // @p with_repeats: the edges of faces that repeat a vertex id too (an (a→a) edge is its own
  // reverse); without, such faces add none.
  EdgeBuckets(const TriangleMesh& mesh, bool with_repeats) : start(mesh.vertices.size() + 1, 0) {
    const auto each = [&](auto&& visit) {
      for (size_t f = 0; f < mesh.faces.size(); ++f) {
        const Tri& t = mesh.faces[f];
        if (!with_repeats && (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])) continue;
        for (int k = 0; k < 3; ++k) visit(t[k], t[(k + 1) % 3], uint32_t(3 * f + k));
      }
    };
    each([&](int32_t a, int32_t b, uint32_t) { ++start[std::min(a, b) + 1]; });
    std::partial_sum(start.begin(), start.end(), start.begin());
    uses.resize(start.back());
    std::vector<uint64_t> next(start.begin(), start.end() - 1);
    each([&](int32_t a, int32_t b, uint32_t half) {
      const auto [lo, hi] = std::minmax(a, b);
      uses[next[lo]++] = (uint64_t((uint32_t(hi) << 1) | uint32_t(a < b)) << 32) | half;
    });
  }

  // Sorts bucket @p lo (buckets are independent: any threads may sort different ones at once).
  void sort(size_t lo) { std::sort(uses.begin() + int64_t(start[lo]), uses.begin() + int64_t(start[lo + 1])); }

  static int32_t hi(uint64_t use) { return int32_t(use >> 33); }
  static int forward(uint64_t use) { return int((use >> 32) & 1); }
  static uint32_t half(uint64_t use) { return uint32_t(use); }
};

}  // namespace hdm::mesh::detail
