// SPDX-License-Identifier: MIT
#include <hdm/core/error.h>
#include <hdm/slab/sample_layout.h>
#include <hdm/slab/triangle_grid.h>

#include "../core/parallel_for.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>

namespace hdm {
namespace {

uint64_t edge_key(int32_t a, int32_t b) {
  const auto [lo, hi] = std::minmax(a, b);
  return (static_cast<uint64_t>(static_cast<uint32_t>(lo)) << 32) | static_cast<uint32_t>(hi);
}

// CSR from (key, value) pairs with keys in [0, count), listed by `each(emit)` calling emit(key,
// value) for every pair (twice: counting, then filling, so the pairs are never stored): counting
// sort, then each (short) row sorted and deduplicated in place, rows in parallel; linear in the
// number of pairs, unlike one global sort.
template <class Each>
void build_csr(Each each, int count, std::vector<int32_t>& offsets, std::vector<int32_t>& values) {
  std::vector<int32_t> start(count + 1, 0);
  each([&](int32_t key, int32_t) { ++start[key + 1]; });
  for (int s = 0; s < count; ++s) start[s + 1] += start[s];
  std::vector<int32_t> raw(start[count]), fill(start.begin(), start.end() - 1);
  each([&](int32_t key, int32_t value) { raw[fill[key]++] = value; });
  std::vector<int32_t>().swap(fill);
  std::vector<int32_t> kept(count);
  core::detail::parallel_blocks(size_t(count), 4096, [&](size_t b, size_t e, size_t) {
    for (size_t s = b; s < e; ++s) {
      auto first = raw.begin() + start[s], last = raw.begin() + start[s + 1];
      std::sort(first, last);
      kept[s] = static_cast<int32_t>(std::unique(first, last) - first);
    }
  });
  offsets.assign(count + 1, 0);
  for (int s = 0; s < count; ++s) offsets[s + 1] = offsets[s] + kept[s];
  values.assign(offsets[count], 0);
  core::detail::parallel_blocks(size_t(count), 4096, [&](size_t b, size_t e, size_t) {
    for (size_t s = b; s < e; ++s)
      std::copy(raw.begin() + start[s], raw.begin() + start[s] + kept[s], values.begin() + offsets[s]);
  });
}

// The undirected coarse edges, numbered in order of first use; each owns n-1 edge samples.
struct EdgeSamples {
  std::unordered_map<uint64_t, std::pair<int32_t, int32_t>> edges;  // key -> (index, uses)
  int32_t base = 0;                                                 // id of the first edge sample
  int n = 1;

  // Index of the undirected coarse edge (a, b).
  int32_t index(int32_t a, int32_t b) const { return edges.at(edge_key(a, b)).first; }

  // Sample id of the k-th point (0 < k < n) on the way from coarse vertex a to b.
  int32_t sample(int32_t a, int32_t b, int k) const {
    const int32_t e = index(a, b);
    const int t = a < b ? k : n - k;
    return base + e * (n - 1) + t - 1;
  }
};

// Numbers the slabs' coarse edges, rejecting invalid vertex ids and non-manifold edges.
EdgeSamples number_edges(const std::vector<Tri>& slabs, int coarse_vertex_count, int n) {
  EdgeSamples E;
  E.base = coarse_vertex_count;
  E.n = n;
  E.edges.reserve(slabs.size() * 2);
  const auto S = static_cast<int32_t>(slabs.size());
  for (int32_t s = 0; s < S; ++s)
    for (int k = 0; k < 3; ++k) {
      const int32_t a = slabs[s][k], b = slabs[s][(k + 1) % 3];
      if (a < 0 || a >= coarse_vertex_count || b < 0 || b >= coarse_vertex_count || a == b)
        throw InvalidInput("slab " + std::to_string(s) + ": invalid coarse vertex ids");
      auto [it, fresh] = E.edges.try_emplace(edge_key(a, b), static_cast<int32_t>(E.edges.size()), 0);
      if (++it->second.second > 2)
        throw InvalidInput("slab " + std::to_string(s) + ": coarse edge (" + std::to_string(a) + ", " +
                           std::to_string(b) + ") is shared by more than two slabs (non-manifold)");
    }
  return E;
}

// The per_slab tables: grid coordinates, interior or boundary rank of each packed index, and the
// packed index of each interior rank.
void fill_local_tables(SampleLayout& L) {
  const int n = L.n;
  L.point_i.resize(L.per_slab);
  L.point_j.resize(L.per_slab);
  L.local_rank.resize(L.per_slab);
  L.interior_index.clear();
  L.side_points.resize(3 * (n + 1));
  for (int k = 0; k <= n; ++k) {  // sides R→T (k, 0), R→S (0, k), S→T (k, n-k)
    L.side_points[k] = grid::index(n, k, 0);
    L.side_points[(n + 1) + k] = grid::index(n, 0, k);
    L.side_points[2 * (n + 1) + k] = grid::index(n, k, n - k);
  }
  int32_t boundary = 0;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i + j <= n; ++i) {
      const int p = grid::index(n, i, j);
      L.point_i[p] = static_cast<int16_t>(i);
      L.point_j[p] = static_cast<int16_t>(j);
      const bool interior = i > 0 && j > 0 && i + j < n;
      L.local_rank[p] = interior ? static_cast<int32_t>(L.interior_index.size()) : ~boundary++;
      if (interior) L.interior_index.push_back(p);
    }
}

// Sample id of every boundary slot (corners and shared edge samples), stored per slab, and each
// shared sample's home slot (its first); interior ids are computed (SlabIds).
void assign_sample_ids(SampleLayout& L, const std::vector<Tri>& slabs, const EdgeSamples& E) {
  const int n = L.n;
  const auto S = static_cast<int32_t>(slabs.size());
  L.boundary_ids.resize(static_cast<size_t>(S) * 3 * n);
  constexpr uint32_t kNone = UINT32_MAX;  // no home yet: above every packed home (slab < #S)
  L.homes.assign(L.first_interior, kNone);
  for (int32_t s = 0; s < S; ++s) {
    const int32_t R = slabs[s][0], Sv = slabs[s][1], T = slabs[s][2];
    int32_t* out = &L.boundary_ids[static_cast<size_t>(s) * 3 * n];
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i + j <= n; ++i) {
        const int local = grid::index(n, i, j);
        if (L.local_rank[local] >= 0) continue;  // interior
        int32_t id;
        if (i == 0 && j == 0)
          id = R;
        else if (i == n)
          id = T;
        else if (j == n)
          id = Sv;
        else if (j == 0)
          id = E.sample(R, T, i);
        else if (i == 0)
          id = E.sample(R, Sv, j);
        else
          id = E.sample(Sv, T, i);
        out[~L.local_rank[local]] = id;
        if (L.homes[id] == kNone) L.homes[id] = static_cast<uint32_t>(s) << L.home_bits | static_cast<uint32_t>(local);
      }
  }
}

// Each coarse edge's side in its higher-numbered slab (SampleLayout::edge_other_side): slabs are
// visited in increasing order, and the first to reach an edge holds its samples' homes.
void assign_other_sides(SampleLayout& L, const std::vector<Tri>& slabs, const EdgeSamples& E) {
  if (L.n < 2) return;  // no edge samples
  L.edge_other_side.assign(E.edges.size(), SampleLayout::kNoSide);
  std::vector<bool> reached(E.edges.size(), false);
  for (size_t s = 0; s < slabs.size(); ++s) {
    const Tri& t = slabs[s];
    const int32_t from[3] = {t[0], t[0], t[1]}, to[3] = {t[2], t[1], t[2]};  // R→T, R→S, S→T
    for (uint32_t side = 0; side < 3; ++side) {
      const int32_t e = E.index(from[side], to[side]);
      if (!reached[e]) {
        reached[e] = true;
        continue;
      }
      L.edge_other_side[e] = static_cast<uint32_t>(s) << 3 | side << 1 | uint32_t(from[side] > to[side]);
    }
  }
}

// The slots of the corner samples, sorted; every corner must have one. Edge samples' slots are
// computed from their edge's sides, interior samples' from their id (SampleLayout::for_each_slot()).
void build_corner_slots(SampleLayout& L) {
  build_csr(
      [&](auto emit) {
        for (int32_t k = 0; k < L.slab_count; ++k) {
          const int32_t* g = &L.boundary_ids[static_cast<size_t>(k) * 3 * L.n];
          for (int32_t p = 0; p < L.per_slab; ++p)
            if (L.local_rank[p] < 0 && g[~L.local_rank[p]] < L.first_edge)
              emit(g[~L.local_rank[p]], k * L.per_slab + p);
        }
      },
      L.first_edge, L.corner_slot_offsets, L.corner_slots);
  for (int32_t id = 0; id < L.first_edge; ++id)
    if (L.corner_slot_offsets[id] == L.corner_slot_offsets[id + 1])
      throw InvalidInput("coarse vertex " + std::to_string(id) + " is used by no slab");
}

}  // namespace

SampleLayout build_sample_layout(const std::vector<Tri>& slabs, int coarse_vertex_count, int n) {
  if (n < 1) throw InvalidInput("grid n = " + std::to_string(n) + ": must be at least 1");
  SampleLayout L;
  L.n = n;
  L.per_slab = grid::point_count(n);
  if (static_cast<int64_t>(slabs.size()) * L.per_slab > INT32_MAX)
    throw InvalidInput(std::to_string(slabs.size()) + " slabs at grid n = " + std::to_string(n) +
                       ": more grid points than an int32 counts");
  const auto S = static_cast<int32_t>(slabs.size());

  // Number the undirected coarse edges; each owns n-1 edge samples.
  const EdgeSamples edges = number_edges(slabs, coarse_vertex_count, n);
  const int32_t interior_base = edges.base + static_cast<int32_t>(edges.edges.size()) * (n - 1);
  const int32_t interior_per_slab = (n - 1) * (n - 2) / 2;
  L.count = interior_base + S * interior_per_slab;
  L.slab_count = S;
  while ((int64_t{1} << L.home_bits) < L.per_slab) ++L.home_bits;
  L.interior_per_slab = interior_per_slab;
  L.interior_divisor_magic = interior_per_slab > 0 ? UINT64_MAX / static_cast<uint64_t>(interior_per_slab) : 0;
  L.slot_divisor_magic = UINT64_MAX / static_cast<uint64_t>(L.per_slab);
  L.first_interior = interior_base;
  L.first_edge = coarse_vertex_count;
  L.edge_divisor_magic = n > 1 ? UINT64_MAX / static_cast<uint64_t>(n - 1) : 0;

  fill_local_tables(L);
  assign_sample_ids(L, slabs, edges);
  assign_other_sides(L, slabs, edges);
  build_corner_slots(L);
  return L;
}

GridCellRef SampleLayout::grid_cell(int32_t t) const noexcept {
  const int32_t k = t / (n * n), local = t - k * n * n;
  // Row j is the largest with row_start(j) = n² - (n - j)² <= local.
  int j = static_cast<int>(n - std::sqrt(static_cast<double>(n) * n - local));
  while (j > 0 && row_start(j) > local) --j;
  while (j + 1 < n && row_start(j + 1) <= local) ++j;
  const int32_t r = local - row_start(j);
  return {k, r / 2, j, r % 2 != 0};
}

Tri SampleLayout::grid_triangle(int32_t t) const noexcept {
  const GridCellRef c = grid_cell(t);
  const SlabIds g = slab_ids(c.slab);
  return c.down ? down_triangle(g, c.i, c.j) : up_triangle(g, c.i, c.j);
}

}  // namespace hdm
