// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Global sample ids for a triangular grid laid over every slab, with the samples on slab edges
/// and corners stored once (docs/design.md#sample-layout-and-seams). The same layout is used
/// for displacement samples (grid n) and colour texels (grid n·m).

#include <hdm/core/types.h>
#include <hdm/slab/triangle_grid.h>

#include <cstdint>
#include <vector>

namespace hdm {

/// A grid point of a layout: slab and packed grid index (grid::index) within it.
struct GridSlot {
  int32_t slab = -1;  ///< slab id in [0, #S)
  int32_t index = 0;  ///< packed grid index in [0, SampleLayout::per_slab)
};

/// A grid triangle's place in its slab (SampleLayout::grid_cell()).
struct GridCellRef {
  int32_t slab = 0;   ///< slab id in [0, #S)
  int i = 0;          ///< i of the cell's lowest grid point (i, j), i + j < n
  int j = 0;          ///< j of the cell's lowest grid point
  bool down = false;  ///< the cell's "down" triangle (i+1,j) (i,j+1) (i+1,j+1), else its "up" one
};

/// The global sample ids of one slab's grid points, read through operator[] as if they were an
/// array indexed by packed grid index (SampleLayout::slab_ids()): an interior point's id is
/// computed, a corner or edge point's is read from the slab's stored boundary ids.
struct SlabIds {
  const int32_t* rank = nullptr;      ///< SampleLayout::local_rank
  const int32_t* boundary = nullptr;  ///< this slab's 3n boundary ids (SampleLayout::boundary_ids)
  int32_t interior_base = 0;          ///< id of this slab's first interior sample
  /// @brief Id of the sample at packed grid index @p index (0 <= index < per_slab).
  /// @note O(1): two loads (a per_slab table, the slab's boundary ids) and a select; noexcept.
  int32_t operator[](int32_t index) const noexcept {
    // Without a branch (interior and boundary points alternate in a row's triangles): the
    // boundary load always reads a valid entry (entry 0 for an interior point), then a select.
    const int32_t r = rank[index];
    const int32_t stored = boundary[r < 0 ? ~r : 0];
    return r >= 0 ? interior_base + r : stored;
  }
};

/// Global sample ids and their adjacency for a grid of `n` intervals per slab edge.
///
/// Sample ids: the first #coarse-vertices ids are the slab corners (id = coarse vertex id); then
/// n-1 ids per undirected coarse edge, ordered from the smaller to the larger vertex id; then
/// (n-1)(n-2)/2 interior ids per slab, slab by slab, in grid::index order within a slab.
/// Interior samples (82 % at n = 16, 91 % at n = 32) are therefore computed, not stored: only
/// each slab's 3n boundary ids, the shared samples' homes, each coarse edge's second slab side and
/// each corner's slots are. Slots and neighbours of every sample are computed from these.
struct SampleLayout {
  int n = 0;                  ///< intervals per slab edge
  int per_slab = 0;           ///< grid points per slab: (n+1)(n+2)/2
  int count = 0;              ///< number of distinct samples
  int32_t slab_count = 0;     ///< number of slabs #S
  int interior_per_slab = 0;  ///< interior grid points per slab: (n-1)(n-2)/2
  /// floor((2^64 - 1) / interior_per_slab) (0 without interior points): home() divides r by
  /// interior_per_slab as the high word of this × (r + 1), one multiply instead of a division,
  /// exact for every r < 2^32 - 1 and every divisor (the product is below (r + 1) / d by less
  /// than 2^-31: it floors to r / d whether or not d divides r + 1).
  uint64_t interior_divisor_magic = 0;
  /// UINT64_MAX / per_slab: a slot's slab by a multiplication, as for `interior_divisor_magic`.
  uint64_t slot_divisor_magic = 0;
  /// per_slab entries: for each packed grid index, its rank among the slab's interior points in
  /// grid::index order (>= 0), or ~(its rank among the slab's boundary points) (< 0).
  std::vector<int32_t> local_rank;
  /// interior_per_slab entries: the packed grid index of each interior rank (inverse of local_rank).
  std::vector<int32_t> interior_index;
  /// #S·3n ids of each slab's boundary (corner and edge) grid points, slab-major, in grid::index
  /// order within a slab. Read through slab_ids() or id().
  std::vector<int32_t> boundary_ids;
  /// For each shared sample (id < first_interior), its home (the first slot in slab order that
  /// holds it; home()), packed in one word, slab << home_bits | grid index. Stored, not computed
  /// from the edge's sides: home() runs for every sample an edit visits and for each of its
  /// neighbours, and a computed one (a multiplication and two dependent loads) made the warm
  /// strokes 1.04-1.08 times slower.
  std::vector<uint32_t> homes;
  /// Bits of the grid index in `homes`: the least b with per_slab <= 2^b. Then 2^b < 2·per_slab, so
  /// slab·2^b < #S·2·per_slab <= 2^32 while the slots (#S·per_slab) fit an int32, as
  /// build_sample_layout() requires.
  int home_bits = 0;
  /// per_slab entries: grid coordinates (i, j) of each packed index (inverse of grid::index).
  /// @{
  std::vector<int16_t> point_i, point_j;
  /// @}
  /// Samples with id >= first_interior are interior to their home slab: their only grid point is
  /// home(). Corner and edge samples (ids below it) may be held by several slabs.
  int32_t first_interior = 0;
  /// Id of the first edge sample: the corners are ids [0, first_edge), one per coarse vertex, and
  /// coarse edge e owns ids first_edge + e·(n-1) + [0, n-1), from its smaller vertex id to its larger.
  int32_t first_edge = 0;
  /// floor((2^64 - 1) / (n - 1)) (0 for n = 1): an edge sample's edge, as `interior_divisor_magic`.
  uint64_t edge_divisor_magic = 0;
  /// One entry per coarse edge: the side of the higher-numbered of the two slabs that hold its
  /// samples, packed as slab << 3 | side << 1 | reversed, or `kNoSide` on an open boundary (the
  /// lower-numbered slab's side holds the samples' homes). Side 0 runs over grid points (k, 0) from
  /// corner R to T, side 1 over (0, k) from R to S, side 2 over (k, n-k) from S to T; `reversed`
  /// when that corner order runs from the larger vertex id to the smaller. An edge sample's second
  /// slot is computed from it and `side_points`: 4 B per coarse edge, where a list of the slots
  /// took an offset per edge sample and 4 B per slot. Empty for n = 1 (no edge samples). slab < 2^29:
  /// #S·per_slab fits an int32 and per_slab >= 6 for n >= 2.
  std::vector<uint32_t> edge_other_side;
  /// An `edge_other_side` entry of an edge that one slab holds.
  static constexpr uint32_t kNoSide = UINT32_MAX;
  /// 3·(n+1) entries: the packed grid index of point k (0 <= k <= n) of side s (as in
  /// `edge_other_side`) at s·(n+1) + k.
  std::vector<int32_t> side_points;
  /// CSR over the corner samples (ids < first_edge): every grid point that holds corner c is
  /// corner_slots[corner_slot_offsets[c] .. corner_slot_offsets[c+1]), sorted, a slot being
  /// slab·per_slab + grid index; the first is the corner's home. With `edge_other_side`, lets edits
  /// update slab-major copies of a sample's data (SlabModel::slab_samples) without a search.
  /// @{
  std::vector<int32_t> corner_slot_offsets, corner_slots;
  /// @}
  /// Number of slots (grid points of every slab): #S·per_slab.
  size_t slot_count() const noexcept { return static_cast<size_t>(slab_count) * per_slab; }

  /// @brief The ids of slab @p slab's grid points, indexed by packed grid index.
  /// Precondition: 0 <= slab < slab_count. @note O(1), noexcept; valid while the layout lives.
  SlabIds slab_ids(int32_t slab) const noexcept {
    return {local_rank.data(), boundary_ids.data() + static_cast<size_t>(slab) * 3 * n,
            first_interior + slab * interior_per_slab};
  }

  /// @brief Id of the sample at packed grid index @p index of slab @p slab.
  /// Preconditions: 0 <= slab < slab_count, 0 <= index < per_slab. @note O(1), noexcept.
  int32_t id(int32_t slab, int32_t index) const noexcept { return slab_ids(slab)[index]; }

  /// @brief Home of sample @p s: the first grid point, in slab-major order, that holds it. Shared
  /// samples' projection lines are evaluated there, with one fixed formula, so that the slabs
  /// holding a sample agree bit for bit. Precondition: 0 <= s < count. @note O(1), noexcept.
  GridSlot home(int32_t s) const noexcept {
    if (s >= first_interior) {
      const auto r = static_cast<uint32_t>(s - first_interior);
      const auto slab = static_cast<int32_t>((static_cast<unsigned __int128>(interior_divisor_magic) * (r + 1)) >> 64);
      return {slab, interior_index[static_cast<int32_t>(r) - slab * interior_per_slab]};
    }
    const uint32_t h = homes[s];
    return {static_cast<int32_t>(h >> home_bits), static_cast<int32_t>(h & ((uint32_t{1} << home_bits) - 1))};
  }

  /// @brief Calls @p f(slot) for every grid point (slab·per_slab + grid index) that holds sample
  /// @p s, in increasing slot order (the first is home()).
  /// @note O(number of slabs holding s): 1 for interior samples, 1 or 2 for edge samples;
  ///       noexcept if @p f is.
  template <class F>
  void for_each_slot(int32_t s, F&& f) const {
    if (s >= first_interior) {
      const GridSlot h = home(s);
      f(h.slab * per_slab + h.index);
      return;
    }
    int32_t pair[2];
    const SlotRange r = shared_slots(s, pair);
    for (const int32_t* x = r.first; x != r.last; ++x) f(*x);
  }

  /// @brief Number of slabs around coarse vertex @p v: the slots of its corner sample (corner
  /// ids are coarse vertex ids). Precondition: 0 <= v < first_edge. @note O(1), noexcept.
  int32_t vertex_slab_count(int32_t v) const noexcept { return corner_slot_offsets[v + 1] - corner_slot_offsets[v]; }

  /// @brief Calls @p f(slab) for each slab around coarse vertex @p v, in increasing order: the
  /// slabs of its corner sample's slots (`corner_slots`; a slab holds each of its corners once).
  /// Precondition: 0 <= v < first_edge.
  /// @note O(slabs around v), a multiplication each; noexcept if @p f is.
  template <class F>
  void for_each_vertex_slab(int32_t v, F&& f) const {
    for (int32_t k = corner_slot_offsets[v]; k < corner_slot_offsets[v + 1]; ++k) f(slab_of_slot(corner_slots[k]));
  }

  /// @brief Calls @p f(t) once for every sample t that shares a grid edge with sample @p s. An
  /// interior sample: its six grid neighbours (i±1, j), (i, j±1), (i+1, j-1), (i-1, j+1) in its
  /// home slab, in that order. A shared sample: the grid neighbours of each grid point holding it,
  /// slot by slot (for_each_slot()); a grid edge along a slab's side, which the slab across that
  /// side holds too, is listed from the lower-numbered of the two. Nothing is stored for it.
  /// @tparam each_once  false: a neighbour along a slab's side may come twice, once from each slab
  ///                    (for a flood, whose marks drop repeats, without the test that skips them).
  /// @note O(neighbours), no allocation: 6 for an interior sample, about 4 per slab holding a
  ///       shared one (n = 1: O(slabs²) at a coarse vertex); noexcept if @p f is.
  template <bool each_once = true, class F>
  void for_each_neighbour(int32_t s, F&& f) const {
    if (s >= first_interior) {  // all six grid neighbours in the home slab, rows of n+1-j points
      const GridSlot h = home(s);
      const int32_t p = h.index, i = point_i[p], j = point_j[p];
      if (i >= 2 && j >= 2 && i + j <= n - 2) {  // all six interior too: ids s + rank offsets
        // Interior row j holds n-1-j points: (i, j±1) is n-1-j ahead or n-j behind in rank.
        const int32_t up = n - 1 - j, down = n - j;
        f(s + 1), f(s - 1), f(s + up), f(s + up - 1), f(s - down + 1), f(s - down);
        return;
      }
      const SlabIds g = slab_ids(h.slab);
      const int32_t row = n + 1 - j;
      f(g[p + 1]), f(g[p - 1]), f(g[p + row]), f(g[p + row - 1]), f(g[p - row]), f(g[p - row - 1]);
      return;
    }
    int32_t pair[2];
    const SlotRange r = shared_slots(s, pair);
    for (const int32_t* x = r.first; x != r.last; ++x) {  // a loop, not a callback: the body stays inline
      const GridPoint gp = grid_point(*x);                // named members: a lambda below captures the slab
      const int32_t slab = gp.slab, i = gp.i, j = gp.j, p = *x - slab * per_slab, row = n + 1 - j;
      const SlabIds& g = gp.ids;
      const bool corner = (i == 0 || i == n) && (j == 0 || j == n);
      // A grid edge along a side of this slab is held by the slab across that side too: it is
      // listed from the lower-numbered one, for an edge sample its first slot (slots are sorted).
      auto visit = [&](int32_t t, bool along_side) {
        if (!each_once || !along_side || (corner ? !held_below(s, t, slab) : x == r.first)) f(t);
      };
      if (i + j < n) visit(g[p + 1], j == 0), visit(g[p + row], i == 0);        // (i+1, j), (i, j+1)
      if (i > 0) visit(g[p - 1], j == 0), visit(g[p + row - 1], i + j == n);    // (i-1, j), (i-1, j+1)
      if (j > 0) visit(g[p - row - 1], i == 0), visit(g[p - row], i + j == n);  // (i, j-1), (i+1, j-1)
    }
  }

  /// Number of grid triangles: #slabs·n². The grid triangles (the surface drawn, felt and
  /// exported) are not stored: grid_triangle(), for_each_triangle() and
  /// for_each_incident_triangle() derive them from the ids (slab_ids()).
  int32_t triangle_count() const noexcept { return slab_count * n * n; }

  /// @brief Calls @p f(corners) for every grid triangle, slab by slab, in triangle index order
  /// (triangle t of slab k has index k·n² + t; within a slab, row by row, each cell's "up"
  /// triangle then its "down" one, hdm/slab/triangle_grid.h), corners counter-clockwise from outside.
  /// @note O(#slabs·n²), no allocation.
  template <class F>
  void for_each_triangle(F&& f) const {
    for (int32_t k = 0; k < slab_count; ++k) for_each_slab_triangle(k, f);
  }

  /// @brief Calls @p f(corners) for the n² grid triangles of slab @p slab, in triangle index order
  /// (for_each_triangle()), corners counter-clockwise from outside.
  /// Precondition: 0 <= slab < slab_count. @note O(n²), no allocation.
  template <class F>
  void for_each_slab_triangle(int32_t slab, F&& f) const {
    const SlabIds g = slab_ids(slab);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i + j < n; ++i) {
        f(up_triangle(g, i, j));
        if (i + j <= n - 2) f(down_triangle(g, i, j));
      }
  }

  /// @brief Corners of grid triangle @p t (see for_each_triangle()), counter-clockwise from outside.
  /// Precondition: 0 <= t < triangle_count(). @note O(1) (a square root), noexcept.
  Tri grid_triangle(int32_t t) const noexcept;

  /// @brief Where grid triangle @p t lies: its slab, its cell (i, j) and whether it is the cell's
  /// "down" triangle (GridCellRef). Its corners, counter-clockwise from outside, are the grid
  /// points (i, j), (i, j+1), (i+1, j) for an "up" triangle and (i+1, j), (i, j+1), (i+1, j+1)
  /// for a "down" one: grid_triangle() gives their sample ids.
  /// Precondition: 0 <= t < triangle_count(). @note O(1) (a square root), noexcept.
  GridCellRef grid_cell(int32_t t) const noexcept;

  /// @brief Calls @p f(t, corners) for every grid triangle t with sample @p s as a corner, in
  /// increasing t (the order of a sorted incidence list: sums over them are the same bit for bit
  /// as with a stored one), with its corners counter-clockwise from outside.
  /// @note O(6 × the slabs holding s), no allocation; noexcept if @p f is.
  template <class F>
  void for_each_incident_triangle(int32_t s, F&& f) const {
    for_each_slot(s, [&](int32_t slot) {
      const auto [k, g, i, j] = grid_point(slot);
      const int32_t here = k * n * n + row_start(j), below = here - row_start(j) + row_start(j - 1);
      // Row j-1 then row j, each in increasing index: down(i-1, j-1), up(i, j-1), down(i, j-1),
      // up(i-1, j), down(i-1, j), up(i, j); a cell outside the grid is skipped.
      if (j >= 1) {
        if (i >= 1) f(below + 2 * i - 1, down_triangle(g, i - 1, j - 1));
        f(below + 2 * i, up_triangle(g, i, j - 1));
        if (i + j <= n - 1) f(below + 2 * i + 1, down_triangle(g, i, j - 1));
      }
      if (i >= 1) {
        f(here + 2 * i - 2, up_triangle(g, i - 1, j));
        if (i + j <= n - 1) f(here + 2 * i - 1, down_triangle(g, i - 1, j));
      }
      if (i + j <= n - 1) f(here + 2 * i, up_triangle(g, i, j));
    });
  }

 private:
  // The slab of a slot, by a multiplication (slot_divisor_magic).
  int32_t slab_of_slot(int32_t slot) const noexcept {
    return static_cast<int32_t>((static_cast<unsigned __int128>(slot_divisor_magic) * uint32_t(slot + 1)) >> 64);
  }
  // The coarse edge of edge sample s (first_edge <= s < first_interior).
  int32_t edge_of(int32_t s) const noexcept {
    return static_cast<int32_t>((static_cast<unsigned __int128>(edge_divisor_magic) * uint32_t(s - first_edge + 1)) >>
                                64);
  }
  // The slots holding a shared sample (id < first_interior), sorted: [first, last).
  struct SlotRange {
    const int32_t *first, *last;
  };
  // A corner's are its stored slots; an edge sample's are its home and, where a second slab holds
  // its edge, the slot computed from that slab's side (`edge_other_side`, `side_points`), in @p pair.
  SlotRange shared_slots(int32_t s, int32_t (&pair)[2]) const noexcept {
    if (s < first_edge)
      return {corner_slots.data() + corner_slot_offsets[s], corner_slots.data() + corner_slot_offsets[s + 1]};
    const GridSlot h = home(s);  // the first side's slot, stored
    pair[0] = h.slab * per_slab + h.index;
    const int32_t e = edge_of(s);
    const uint32_t side = edge_other_side[e];
    if (side == kNoSide) return {pair, pair + 1};
    const int32_t pos = s - first_edge - e * (n - 1) + 1,
                  k = side & 1 ? n - pos : pos;  // pos: 1 .. n-1 from the smaller id
    pair[1] =
        static_cast<int32_t>(side >> 3) * per_slab + side_points[static_cast<int32_t>(side >> 1 & 3) * (n + 1) + k];
    return {pair, pair + 2};
  }
  // A slot's slab, that slab's ids and the slot's grid coordinates (i, j).
  struct GridPoint {
    int32_t slab;
    SlabIds ids;
    int i, j;
  };
  GridPoint grid_point(int32_t slot) const noexcept {
    const int32_t slab = slab_of_slot(slot);
    const int32_t p = slot - slab * per_slab;
    return {slab, slab_ids(slab), point_i[p], point_j[p]};
  }
  // Whether a slab numbered below @p slab holds the grid edge from corner sample s of @p slab to
  // t, along a side of @p slab. For n > 1, t is an edge sample, held by the slabs of that side
  // alone, its slots sorted: its first tells. At n = 1 both are corners: the slabs holding s are
  // searched for t.
  bool held_below(int32_t s, int32_t t, int32_t slab) const noexcept {
    const int32_t below = slab * per_slab;  // the first slot of @p slab
    if (n > 1) return home(t).slab < slab;
    for (int32_t x = corner_slot_offsets[s]; x < corner_slot_offsets[s + 1] && corner_slots[x] < below; ++x) {
      const int32_t lo = corner_slots[x] / per_slab * per_slab;
      for (int32_t y = corner_slot_offsets[t]; y < corner_slot_offsets[t + 1]; ++y)
        if (corner_slots[y] >= lo && corner_slots[y] < lo + per_slab) return true;
    }
    return false;
  }
  // Index within its slab of the first triangle of row j: rows j' < j hold 2(n - j') - 1 each.
  int32_t row_start(int j) const noexcept { return j * (2 * n - j); }
  // The "up" triangle of cell (i, j), (i,j) (i,j+1) (i+1,j), and its "down" triangle,
  // (i+1,j) (i,j+1) (i+1,j+1), from a slab's ids @p g.
  Tri up_triangle(const SlabIds& g, int i, int j) const noexcept {
    return {g[grid::index(n, i, j)], g[grid::index(n, i, j + 1)], g[grid::index(n, i + 1, j)]};
  }
  Tri down_triangle(const SlabIds& g, int i, int j) const noexcept {
    return {g[grid::index(n, i + 1, j)], g[grid::index(n, i, j + 1)], g[grid::index(n, i + 1, j + 1)]};
  }
};

/// @brief Builds the global sample layout of a slab mesh.
/// @param slabs                #S slabs as coarse-vertex triples (R, S, T).
/// @param coarse_vertex_count  number of coarse vertices; every id in @p slabs is below it.
/// @param n                    intervals per slab edge, n >= 1.
/// No layout stores its grid triangles (for_each_triangle()) or adjacency (for_each_neighbour()).
/// @return the layout; edge samples are shared by the two slabs of an edge, corner samples by
///         the whole one-ring (boundary edges belong to one slab).
/// @throws InvalidInput if n < 1, an id is out of range, an edge is used by more than two slabs, or
///         the grid points (#S·(n+1)(n+2)/2) do not fit an int32.
/// @note O(#S·n²) time and memory; the CSR rows of the shared samples' slots are sorted in
///       parallel (std::thread).
SampleLayout build_sample_layout(const std::vector<Tri>& slabs, int coarse_vertex_count, int n);

}  // namespace hdm
