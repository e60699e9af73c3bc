// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Consistent copies of a slab model for other threads while one thread edits it: per-slab
/// versions published in epochs, read without ever blocking the editing thread (docs/editing.md).
///
/// The editing thread (the writer: the servo thread of hdm::SculptSession) owns the live
/// SlabModel. When it holds no half edit it copies the slabs an edit changed into spare versions
/// (publish_slab) and makes them visible together as one new epoch (publish_commit). A reader (a
/// renderer, a saver) pins the newest epoch (SnapshotReader) and sees every slab as it was at
/// that epoch: a state the live model had, never part of an edit, with shared edge and corner
/// samples equal in every slab. Old versions are recycled once no reader's epoch needs them
/// (epoch-based reclamation); while a slow reader pins an old epoch the writer may run out of
/// spare versions, and then publishes later (publish_reserve() returns false): it never waits.

#include <hdm/slab/slab_model.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

namespace hdm {

/// Settings of SlabSnapshots.
struct SnapshotOptions {
  int reader_slots = 8;  ///< readers that may hold a snapshot at once (more wait for a slot)
  /// Versions beyond one per slab, for publishing while readers hold older ones; -1: one per slab
  /// (enough to publish any edit while no reader holds an old epoch).
  int spare_versions = -1;
  bool checksums = false;  ///< the writer stores a checksum per version and readers can verify() it (tests)
};

/// One slab as a reader sees it. Arrays in grid::index order of the slab's grid (displacement
/// grid: per_slab points; texel grid: texels_per_slab points), like SlabModel::slab_samples.
struct SlabView {
  uint64_t epoch = 0;                         ///< epoch that published this version (0: the model at construction)
  int per_slab = 0;                           ///< displacement grid points of a slab
  int texels_per_slab = 0;                    ///< texel grid points of a slab
  const SlabSample* points = nullptr;         ///< per_slab displacement δ, unit and force-shading normals
  const Half16* friction_static = nullptr;      ///< per_slab μs (SlabModel::friction_static)
  const Half16* friction_dynamic = nullptr;     ///< per_slab μd
  const Unorm16* stiffness_scale = nullptr;     ///< per_slab stiffness scale
  const Unorm16* layer_displacement = nullptr;  ///< per_slab under-layer top δ
  const Half16* hardness = nullptr;             ///< per_slab hardness [HV] (SlabModel::hardness)
  /// texels_per_slab × 4 bytes: the colour's 8-bit sRGB codes (r, g, b; SlabModel::colour) and the
  /// roughness as unorm8 (SlabModel::roughness), the codes the model stores
  const uint8_t* texels = nullptr;
};

class SnapshotReader;

/// Per-slab versions of a model published in epochs for concurrent readers.
///
/// Memory: (#S + spare) versions of about (26·per_slab + 4·texels_per_slab) bytes, allocated by
/// the constructor, each padded to 64 bytes: 14.1 MiB for the default bunny bake (1,178 slabs,
/// n = 16, m = 2: 2,356 versions of 6,272 bytes), beside the 11.8 MiB the model takes.
/// The model's topology, coarse vertices, grid sizes, source fields and under-layer material
/// must not change while the snapshots exist (edits never change them); readers read those
/// members of the live model directly.
class SlabSnapshots {
 public:
  /// @brief Copies every slab of @p model as epoch 0. Keeps a reference to @p model: it must
  /// outlive this object.
  /// @pre rebuild_derived(model) has run (slab_samples and the layouts are built).
  /// @throws InvalidInput when the model's derived data are missing or the options are out of range.
  explicit SlabSnapshots(const SlabModel& model, const SnapshotOptions& options = {});
  ~SlabSnapshots();
  SlabSnapshots(const SlabSnapshots&) = delete;
  SlabSnapshots& operator=(const SlabSnapshots&) = delete;

  // ---- writer: the one thread that edits the model ----

  /// @brief Recycles the versions no reader needs any more, then tells whether @p slabs more
  /// slabs can be copied in this batch (that many spare versions are free).
  /// @note noexcept, no allocation, no waiting: O(readers + retired versions).
  bool publish_reserve(int slabs) noexcept;
  /// @brief Copies slab @p slab of the model into a spare version (not yet visible).
  /// @pre publish_reserve() returned true for at least as many slabs as this batch publishes,
  ///      and the model holds no half edit from the batch's first copy to its commit.
  /// @note noexcept, no allocation; O(per_slab + texels_per_slab) (about 2 µs at n = 16, m = 2).
  void publish_slab(int slab) noexcept;
  /// @brief Makes the copied slabs visible together as the next epoch and returns it.
  /// @note noexcept, no allocation; O(slabs in the batch). Does nothing (returns epoch()) for an
  ///       empty batch.
  uint64_t publish_commit() noexcept;
  /// Slabs copied for the batch not yet committed.
  int pending() const noexcept;

  // ---- any thread ----

  /// The newest committed epoch (0 before the first publication).
  uint64_t epoch() const noexcept { return published_.load(std::memory_order_acquire); }
  /// The live model (its static members only may be read from threads other than the writer).
  const SlabModel& model() const noexcept { return model_; }
  /// Reader slots (SnapshotOptions::reader_slots).
  int reader_slots() const noexcept { return static_cast<int>(slot_count_); }
  /// Versions allocated (#S + spare).
  int version_count() const noexcept { return static_cast<int>(version_total_); }
  /// Bytes held by the versions.
  size_t memory_bytes() const noexcept { return arena_.size(); }

 private:
  friend class SnapshotReader;
  struct Version {
    uint64_t epoch = 0;                // written only while no reader can reach the version
    uint64_t superseded = UINT64_MAX;  // writer only: epoch of the next version of its slab
    std::atomic<int32_t> prev{-1};     // older version of the same slab (-1: none needed)
    int32_t next = -1;                 // writer only: newer version of the same slab
    int32_t slab = -1;
    uint64_t checksum = 0;
  };
  // A version's bytes: storage for its SlabSample, 16-bit fields and texel codes (C++20 implicit
  // object creation in an unsigned char array).
  unsigned char* data(int32_t v) noexcept { return arena_.data() + static_cast<size_t>(v) * stride_; }
  const unsigned char* data(int32_t v) const noexcept { return arena_.data() + static_cast<size_t>(v) * stride_; }
  void fill(int32_t version, int slab) noexcept;
  uint64_t checksum(int32_t version) const noexcept;
  SlabView view(int32_t version) const noexcept;
  int32_t version_at(int slab, uint64_t epoch) const noexcept;

  const SlabModel& model_;
  SnapshotOptions options_;
  int per_slab_ = 0, texels_per_slab_ = 0;
  size_t stride_ = 0;  // bytes per version, a multiple of 64
  size_t version_total_ = 0, slot_count_ = 0;
  std::vector<unsigned char> arena_;
  std::unique_ptr<Version[]> versions_;
  std::unique_ptr<std::atomic<int32_t>[]> current_;  // #S: newest committed version of each slab
  std::unique_ptr<std::atomic<uint64_t>[]> slots_;   // reader epochs (kFree / kClaiming / epoch)
  std::atomic<uint64_t> published_{0};
  // writer only
  std::vector<int32_t> free_, retired_, pending_;
};

/// A reader's pinned snapshot: every slab as of one epoch. Hold it briefly (a frame, a save):
/// while it lives, versions superseded after its epoch cannot be recycled.
///
/// Threading: one object per reading thread; the constructor waits (yielding) while every reader
/// slot is taken, never the writer. Reads are lock-free and see no writes in progress.
class SnapshotReader {
 public:
  /// @brief Pins the newest epoch of @p snapshots.
  explicit SnapshotReader(const SlabSnapshots& snapshots);
  ~SnapshotReader();
  SnapshotReader(const SnapshotReader&) = delete;
  SnapshotReader& operator=(const SnapshotReader&) = delete;

  /// The pinned epoch.
  uint64_t epoch() const noexcept { return epoch_; }
  /// @brief Slab @p slab as of epoch() (the newest version published at or before it).
  /// @note noexcept, O(versions newer than epoch() of that slab), usually O(1).
  SlabView slab(int slab) const noexcept;
  /// @brief True when the version's checksum matches its content (always true without
  /// SnapshotOptions::checksums). For tests: a torn copy fails it.
  bool verify(int slab) const noexcept;
  /// @brief The stored data of the whole model as of epoch(): a SlabModel with the stored members
  /// filled (derived members empty), ready for save_model() or rebuild_derived().
  /// @note Allocates O(model size); each sample and texel is taken from its home slab.
  SlabModel stored_model() const;

 private:
  const SlabSnapshots& s_;
  size_t slot_ = 0;
  uint64_t epoch_ = 0;
};

}  // namespace hdm
