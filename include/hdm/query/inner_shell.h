// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// The region enclosed by the inner shell: material deeper than any slab reaches.

#include <hdm/slab/slab_model.h>

#include <vector>

namespace hdm {

/// The inner triangles of all slabs, (inner[R], inner[S], inner[T]) per slab, as one surface with a
/// BVH for ray-parity tests.
///
/// A point in no slab is either outside the outer shell or enclosed by the inner shell; in the
/// second case it is inside the material, deeper than the displacement map can say. The haptic
/// query leaves this case to the proxy (which keeps its contact), but a memoryless inside/outside
/// test (contact accuracy, a penalty renderer that wants to know) needs it.
///
/// Threading: const methods may be called from any number of threads at once.
class InnerShell {
 public:
  /// @brief Copies the inner triangles of @p model and builds their BVH.
  /// @note O(#S log #S) time, about 100 bytes per slab. The inner shell never changes while
  ///       editing (edits move displacements only), so it is built once.
  explicit InnerShell(const SlabModel& model);

  /// True when every slab edge is shared by two slabs, so the inner shell encloses a volume.
  /// An open model's inner shell still answers encloses() by parity, like the open input.
  bool closed() const noexcept { return closed_; }

  /// @brief Whether @p p is enclosed by the inner shell.
  /// @param p  point [model units, model frame].
  /// @return false for NaN points and points outside the inner shell's box; otherwise the majority
  ///         of three ray-parity tests along fixed skew directions (one ray grazing an edge cannot
  ///         flip the answer). For an open model (closed() false) the inner shell is open like its
  ///         input, and the answer is the same majority-of-three parity that
  ///         ExactMeshQuery::inside gives on an open input: well defined near the surface, away
  ///         from the boundary; near the boundary, as for the input, it depends on the rays.
  /// @note noexcept, no allocation. Cost: three ray traversals of a BVH over #S triangles,
  ///       O(log #S + crossings) each.
  /// @pre the slabs are valid and disjoint (`hdm check`: no invalid slabs, no overlapping pairs);
  ///      otherwise the inner shell may cross itself and the answer is the parity of crossings.
  bool encloses(const Vec3& p) const noexcept;

  /// Heap bytes held.
  size_t memory_bytes() const noexcept;

 private:
  struct Node {
    float lo[3], hi[3];
    int32_t first;  // leaf: first triangle; inner: right child (left child is this + 1)
    int32_t count;  // leaf: number of triangles; inner: 0
  };
  int build(int32_t begin, int32_t end, std::vector<Vec3>& centres);
  int crossings(const Vec3& p, const Vec3& d) const noexcept;

  bool closed_ = false;
  std::vector<std::array<Vec3, 3>> tris_;  // in BVH order
  std::vector<Node> nodes_;
};

}  // namespace hdm
