// SPDX-License-Identifier: MIT
#pragma once
// Internal to the bake: the shell's offsets, grown while every slab stays valid and thinned where
// slabs of different parts overlap (docs/design.md#growing-the-shell).

#include <hdm/slab/slab_model.h>

#include "ray_frames.h"
#include "shell_targets.h"

#include <cstdint>
#include <utility>
#include <vector>

namespace hdm::slab::detail {

// The inner and outer shell of a model under construction: per coarse vertex an offset each side
// along its ray, written to SlabModel::inner and outer as they change. Holds references to the
// model, the coarse mesh, the frames and the targets, which must outlive it.
class Shell {
 public:
  // Places the thinnest shell (ShellTargets::min_off each side) and notes the slabs that are
  // invalid even there ("hopeless": left out of the growth test, reported by the bake).
  // Resizes model.inner and outer to the coarse vertex count.
  Shell(SlabModel& model, const CoarseMesh& coarse, const VertexFrame& fr, ShellTargets& targets);

  // Back to the thinnest shell with the targets as given at construction (a new pass).
  void restart();

  // Raises each offset towards its target, keeping the largest value (bisection) for which every
  // slab around the vertex keeps its required Jacobian; Gauss-Seidel sweeps, at most 32.
  void grow();

  // Thins the shell where slabs overlap (an exact boundary intersection test), then re-thins any
  // slab the uneven shrinking made invalid; targets follow, so growth stops there. At most 12 rounds;
  // no pair found around the slabs that moved is confirmed over every slab before stopping.
  void separate();

  // The overlapping slab pairs, recomputed only around slabs whose corners moved since the last call.
  const std::vector<std::pair<int32_t, int32_t>>& current_pairs();

  // Raises the targets of the flagged vertices by half, within their caps: inward for @p grow_in,
  // outward for @p grow_out (one flag per coarse vertex). Returns whether any target rose.
  bool widen(const std::vector<uint8_t>& grow_in, const std::vector<uint8_t>& grow_out);

 private:
  void place(size_t v);
  double jacobian(int32_t f) const;
  bool slab_ok(int32_t f) const { return jacobian(f) > required_[f]; }
  bool ring_ok(size_t v) const;
  void shrink(size_t v, double f);

  SlabModel& model_;
  const CoarseMesh& coarse_;
  const VertexFrame& fr_;
  ShellTargets& t_;
  const std::vector<double> tgt_in0_, tgt_out0_;  // the targets as given
  std::vector<double> off_in_, off_out_;          // current offsets [model units]
  std::vector<double> required_;                  // per slab: the Jacobian it must keep
  std::vector<uint8_t> hopeless_;                 // per slab: invalid in the thinnest shell
  std::vector<std::pair<int32_t, int32_t>> known_pairs_;
  std::vector<Vec3> checked_inner_, checked_outer_;  // corners at the last overlap check
  std::vector<uint8_t> moved_;
};

}  // namespace hdm::slab::detail
