// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Finding the slab that holds a point: previous slab, its neighbours, then a uniform grid over
/// slab boxes (paper §3.1 suggests a hierarchy; a grid with cells of half a slab box needs one
/// lookup and a short contiguous list, where a BVH descent missed the cache at every level at
/// 10^5 slabs; docs/design.md#slab-locator).

#include <hdm/query/alpha_plane.h>

#include <cstdint>
#include <vector>

namespace hdm {

/// Static search structure over the slabs of one model. Slab boxes never change while editing
/// (edits move displacements only), so it is built once.
///
/// Threading: const methods may be called from any number of threads at once.
class SlabLocator {
 public:
  /// @brief Builds the search grid and per-slab neighbourhoods of @p model (its derived data must
  /// be built). Keeps pointers to @p model's slab geometry and inner shell: the model must outlive
  /// the locator and keep those arrays (edits change displacements and fields, never them).
  /// @note O(#S) time (~1 s at 10^5 slabs, mostly the sub-cell occupancy); about 1.5 KB per slab
  ///       (mostly the grid's cell lists and the neighbourhoods' boxes).
  explicit SlabLocator(const SlabModel& model);

  /// @brief Finds a slab that contains @p p.
  /// @param p       point [model units].
  /// @param hint    slab to try first (the previous tick's slab) or -1.
  /// @param solver  alpha-plane root finder.
  /// @param[out] c  coordinates of @p p in the slab found.
  /// @return the slab id, or -1 when no slab holds @p p (outside the shell, or NaN).
  /// @note noexcept, no allocation. Tries the hint, its edge and corner neighbours, then the slabs
  ///       listed in the point's grid cell; a point in a sub-cell that no slab reaches is answered
  ///       -1 after one load.
  int find(const Vec3& p, int hint, AlphaSolver solver, SlabCoordinates& c) const noexcept {
    return find(p, hint, solver, -1.0, c);
  }

  /// @brief find() with a starting guess for α (the previous tick's α; -1 for none).
  /// @note Same result as find() up to rounding of α. When the hint fails, the edge neighbour
  ///       beyond the edge the point crossed is tried first, then the sub-cell occupancy, the rest
  ///       of the neighbourhood (each behind a float box test), then the grid cell.
  int find(const Vec3& p, int hint, AlphaSolver solver, double alpha_guess, SlabCoordinates& c) const noexcept;

  /// @brief Slabs sharing an edge or a corner with @p slab (edge neighbours first).
  /// @param slab        slab id in [0, #S).
  /// @param[out] count  number of entries.
  const int32_t* neighbourhood(int slab, int& count) const noexcept {
    count = ring_offsets_[slab + 1] - ring_offsets_[slab];
    return ring_.data() + ring_offsets_[slab];
  }

  /// @brief Whether @p p, a point in no slab, is enclosed by the inner shell (the inner faces of
  /// all slabs): the winding number of the inner shell around @p p is not zero, as
  /// ExactMeshQuery::inside() answers on the inner shell (ray parity for a shell that does not
  /// cross itself). With find(), this classifies every point of space as hdm check does: in a slab,
  /// inside the inner shell (under the surface) or outside the outer one.
  /// @param p  point [model units], model frame; a point that some slab holds gets the answer for
  ///           the inner shell alone (meaningless for the haptic query).
  /// @return false for a non-finite point or one outside the grid's box.
  /// @note noexcept, no allocation. A point in a grid cell that no slab box overlaps is answered by
  ///       the cell's winding number, classified once at construction (O(1)); a point in a cell
  ///       that lists slabs counts the signed crossings of the inner faces listed in the cells along
  ///       the ray +x until a classified cell or the grid's end (a few cells, ~15 triangles each).
  ///       Crossings use a 2D edge test with a symbolic perturbation for ties, so a ray through a
  ///       shared edge or vertex of a closed shell counts once (watertight). Cost: one lookup for
  ///       most points far from the shell, about 0.3-1 µs near it.
  bool inside_inner_shell(const Vec3& p) const noexcept;

  /// Heap bytes held by this locator (grid, neighbourhoods, per-slab filters).
  size_t memory_bytes() const noexcept;

 private:
  // Slab box (slab_bounds()) rounded outward to float: a 24-byte test that rejects most
  // candidates without touching the 216-byte SlabGeometry (it contains the double box).
  struct Box {
    float lo[3], hi[3];
    bool contains(float x, float y, float z) const noexcept {
      return x >= lo[0] && x <= hi[0] && y >= lo[1] && y <= hi[1] && z >= lo[2] && z <= hi[2];
    }
  };
  // Three side planes n·x <= d of the slab: a slab point is a convex combination of its six corners,
  // so a plane with every corner behind it bounds the slab; d carries a margin far above float
  // rounding and the inside test's tolerance. Rejects the neighbours whose boxes overlap (slabs are
  // thick and narrow at 10^4+ slabs) before the cubic is solved.
  struct Sides {
    float n[3][3], d[3];
    bool may_contain(float x, float y, float z) const noexcept {
      return n[0][0] * x + n[0][1] * y + n[0][2] * z <= d[0] && n[1][0] * x + n[1][1] * y + n[1][2] * z <= d[1] &&
             n[2][0] * x + n[2][1] * y + n[2][2] * z <= d[2];
    }
  };
  // Box and side planes of one slab side by side (72 bytes, two cache lines at most): one miss per
  // candidate instead of one per array.
  struct Filter {
    Box box;
    Sides sides;
    bool may_contain(float x, float y, float z) const noexcept {
      return box.contains(x, y, z) && sides.may_contain(x, y, z);
    }
  };
  bool candidate(int32_t slab, float x, float y, float z) const noexcept { return filters_[slab].may_contain(x, y, z); }
  int find_grid(const Vec3& p, AlphaSolver solver, double alpha_guess, SlabCoordinates& c) const noexcept;
  void build_grid();
  void classify_cells();
  // Winding number of the inner shell around p: signed crossings of the ray p + t·x̂ (t > 0) with
  // the inner faces listed in the cells of p's row, from p's cell up to the first classified cell
  // (whose winding is added) or the grid's end; stop_at_classified = false walks to the end.
  int winding_along_x(const Vec3& p, bool stop_at_classified) const noexcept;
  // Cell coordinate of v along axis a: monotonic in v, so a box [lo, hi] holding v is listed in
  // v's cell when it is listed in every cell from cell(lo) to cell(hi).
  int cell_coord(float v, int a) const noexcept {
    const float t = (v - grid_lo_[a]) * grid_inv_[a];
    return t <= 0 ? 0 : t >= float(grid_dim_[a] - 1) ? grid_dim_[a] - 1 : static_cast<int>(t);
  }

  const std::vector<SlabGeometry>* geometry_;
  std::vector<Filter> filters_;               // #S, by slab id
  std::vector<std::array<int32_t, 3>> edge_;  // #S: slab across edge RS, ST, TR or -1
  std::vector<int32_t> ring_offsets_, ring_;
  // Four slab boxes side by side, one array per coordinate (112 bytes, two cache lines): the four
  // containment tests are one branch-free mask, where a run of per-box tests mispredicted on about
  // every box (a point sits in 0-2 of a cell's ~14 boxes at 10^5 slabs). Unused lanes hold an
  // empty box (lo = +inf, hi = -inf) and slab -1, so they never pass.
  struct alignas(16) BoxBlock {
    float lo[3][4], hi[3][4];
    int32_t slab[4];
    // Bit i set iff lane i's box contains (x, y, z) (false for NaN).
    unsigned contains(float x, float y, float z) const noexcept {
      unsigned m = 0;
      for (int i = 0; i < 4; ++i)
        m |= unsigned((x >= lo[0][i]) & (x <= hi[0][i]) & (y >= lo[1][i]) & (y <= hi[1][i]) & (z >= lo[2][i]) &
                      (z <= hi[2][i]))
             << i;
      return m;
    }
  };
  // Lists of slab boxes packed four to a block: list k is blocks[offsets[k] .. offsets[k+1]), in
  // the order given (lane order within a block), so a scan visits the slabs in that order.
  struct BoxLists {
    std::vector<int32_t> offsets;
    std::vector<BoxBlock> blocks;
    size_t memory_bytes() const noexcept {
      return offsets.capacity() * sizeof(int32_t) + blocks.capacity() * sizeof(BoxBlock);
    }
  };
  // Packs lists[k] (slab ids) with their boxes from filters_.
  BoxLists pack_lists(const std::vector<int32_t>& offsets, const std::vector<int32_t>& slabs) const;
  // First slab of list blocks [b, e) that holds p, in list order, skipping `skip`; -1 if none.
  int scan(const BoxBlock* b, const BoxBlock* e, const Vec3& p, float x, float y, float z, int32_t skip,
           AlphaSolver solver, double guess, SlabCoordinates& c) const noexcept;

  // Uniform grid over the slab boxes, cells half a slab box wide: cell k lists, inline, the
  // boxes of every slab whose box overlaps it (grid_.blocks[grid_.offsets[k] .. [k+1])). A
  // global query reads one offset and one contiguous run instead of descending a BVH, and a
  // point in no slab is rejected as cheaply.
  float grid_lo_[3] = {0, 0, 0}, grid_hi_[3] = {0, 0, 0}, grid_inv_[3] = {0, 0, 0};
  int grid_dim_[3] = {1, 1, 1};
  BoxLists grid_;
  // Per grid cell, 4x4x4 sub-cells: bit (sz·4 + sy)·4 + sx is set when some slab may reach into
  // that sub-cell (its box and seven bounding planes, with margins, meet the sub-cell). The shell
  // is thin next to a slab box, so a point in no slab (45 % of a coherent path and 70 % of the
  // global points at 10^5 slabs) often lands in a clear sub-cell and is answered after one load,
  // before the neighbourhood and the cell's boxes. 8 bytes per cell.
  std::vector<uint64_t> occupied_;
  void build_occupancy(const SlabModel& model);
  // Cell index of (x, y, z) and its sub-cell's bit in occupied_; false outside the grid (or NaN).
  bool cell_of(float x, float y, float z, size_t& cell, uint64_t& bit) const noexcept {
    if (!(x >= grid_lo_[0] && x <= grid_hi_[0] && y >= grid_lo_[1] && y <= grid_hi_[1] && z >= grid_lo_[2] &&
          z <= grid_hi_[2]))
      return false;
    const float v[3] = {x, y, z};
    int ci[3], sub[3];
    for (int a = 0; a < 3; ++a) {  // the cell as cell_coord() gives it, then the quarter within it
      const float t = (v[a] - grid_lo_[a]) * grid_inv_[a];
      ci[a] = t <= 0 ? 0 : t >= float(grid_dim_[a] - 1) ? grid_dim_[a] - 1 : static_cast<int>(t);
      const float f = (t - static_cast<float>(ci[a])) * 4.0f;
      sub[a] = f <= 0 ? 0 : f >= 3 ? 3 : static_cast<int>(f);
    }
    cell = (static_cast<size_t>(ci[2]) * grid_dim_[1] + ci[1]) * grid_dim_[0] + ci[0];
    bit = uint64_t{1} << ((sub[2] * 4 + sub[1]) * 4 + sub[0]);
    return true;
  }
  // scan() over grid cell `cell`'s list.
  int scan_cell(size_t cell, const Vec3& p, float x, float y, float z, AlphaSolver solver, double guess,
                SlabCoordinates& c) const noexcept {
    const BoxBlock* b = grid_.blocks.data();
    return scan(b + grid_.offsets[cell], b + grid_.offsets[cell + 1], p, x, y, z, -1, solver, guess, c);
  }
  // The neighbourhood of every slab with its boxes inline (ring_blocks_ list s is ring_ of s): the
  // ring scan after a failed hint reads 3-4 contiguous blocks instead of ~12 scattered filters.
  BoxLists ring_blocks_;
  // Per grid cell: the inner shell's winding number around every point of a cell that no slab
  // box overlaps (the shell does not pass through it), or kMixed for a cell that lists slabs.
  static constexpr int8_t kMixed = INT8_MIN;
  std::vector<int8_t> cell_winding_;
  const std::vector<Vec3>* inner_;       // the model's inner shell vertices (SlabModel::inner) and
  const std::vector<Tri>* inner_faces_;  // faces (SlabModel::slabs), read like geometry_
};

}  // namespace hdm
