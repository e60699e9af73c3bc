// SPDX-License-Identifier: MIT
#pragma once
// Internal to the mesh code: the one union-find over [0, n) (components of faces through shared
// edges, of vertices through faces, of the corners around a vertex). Path halving: O(α(n))
// amortised per operation (Tarjan & van Leeuwen, "Worst-case analysis of set union algorithms",
// J. ACM 1984).

#include <cstddef>
#include <cstdint>
#include <numeric>
#include <vector>

namespace hdm::mesh::detail {

template <class Index = int32_t>
class DisjointSets {
 public:
  DisjointSets() = default;
  explicit DisjointSets(size_t n) { reset(n); }

  // n singletons, reusing the storage.
  void reset(size_t n) {
    parent_.resize(n);
    std::iota(parent_.begin(), parent_.end(), Index(0));
  }

  // The root of @p x's set.
  Index find(Index x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }

  // Joins the sets of @p a and @p b under the root of @p b's; false when they were one already.
  bool unite(Index a, Index b) {
    a = find(a), b = find(b);
    if (a == b) return false;
    parent_[a] = b;
    return true;
  }

 private:
  std::vector<Index> parent_;
};

}  // namespace hdm::mesh::detail
