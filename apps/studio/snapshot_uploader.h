// SPDX-License-Identifier: MIT
#pragma once
// The render thread's side of the paper's §6 split: each frame pins the newest published epoch
// and re-uploads to the GPU exactly the slabs with a version newer than the one drawn.
#include <hdm/render/slab_renderer.h>
#include <hdm/slab/slab_snapshots.h>

#include <cstdint>
#include <vector>

namespace hdm::studio {

/// What one update() did.
struct UploadFrame {
  uint64_t epoch = 0;  ///< epoch drawn from now on
  int uploaded = 0;    ///< slabs re-uploaded
  int dirty = -1;      ///< with verification: slabs whose data differ from what was drawn (-1: not verified)
  int mismatched = 0;  ///< with verification: slabs uploaded but unchanged, or changed but not uploaded
};

/// Keeps a SlabRenderer in step with SlabSnapshots.
class SnapshotUploader {
 public:
  /// @brief Uploads every slab of epoch `snapshots.epoch()` into @p renderer (upload_all of the
  /// static model, then each slab from the snapshot).
  /// @param verify  also keep a CPU copy of every slab's data (about the snapshots' size) and
  ///                compare it each frame, to count the slabs that really changed (tests).
  /// @note Needs the renderer's GL context current. Allocates.
  SnapshotUploader(const SlabSnapshots& snapshots, SlabRenderer& renderer, bool verify);
  /// @brief Pins the newest epoch and re-uploads the slabs published since the last call.
  /// @note O(#S) to find them plus O(n² + N²) per uploaded slab; no allocation.
  UploadFrame update();
  /// Total slabs uploaded since construction (the initial upload not counted).
  int64_t total_uploaded() const noexcept { return total_; }

 private:
  bool differs(const SlabView& view, int slab) const;
  void remember(const SlabView& view, int slab);

  const SlabSnapshots& snapshots_;
  SlabRenderer& renderer_;
  std::vector<uint64_t> drawn_epoch_;  // per slab: epoch of the version on the GPU
  bool verify_;
  size_t stride_ = 0;
  std::vector<uint8_t> mirror_;  // verify: per slab, the bytes drawn
  int64_t total_ = 0;
};

}  // namespace hdm::studio
