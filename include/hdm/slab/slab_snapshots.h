// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Consistent views of a slab model for other threads while one thread edits it: copy on write
/// per slab, published in epochs, read without ever blocking the editing thread (docs/editing.md).
///
/// The editing thread (the writer: the servo thread of hdm::SculptSession) owns the live
/// SlabModel. Before it first writes a slab after a publication it asks before_write(), which
/// copies the slab's committed state into a spare version; publish_commit() then makes every
/// write since the last commit visible as one new epoch. A reader (a renderer, a saver) pins the
/// newest epoch (SnapshotReader) and sees every slab as it was at that epoch: a slab no edit has
/// touched since is read from the live model itself (under a per-slab guard the writer checks, so
/// it never writes a slab a reader is copying), an edited one from its preserved version. Unchanged
/// slabs are therefore shared, not copied. Old versions are recycled once no reader's epoch needs
/// them (epoch-based reclamation). The writer never waits: when a reader is copying the slab, or
/// no spare version is free, before_write() says so and the edit resumes on a later tick.

#include <hdm/slab/slab_model.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

namespace hdm {

/// Settings of SlabSnapshots.
struct SnapshotOptions {
  int reader_slots = 8;  ///< readers that may hold a snapshot at once (more wait for a slot)
  /// Spare versions: copies of edited slabs as readers pinned before the edit see them. -1: 5 % of
  /// the slabs, at least 16 and at most #S. Never fewer than one more than the most slabs around a
  /// coarse vertex (a corner sample's write needs them all at once). An edit that would need more
  /// between two publications pauses until the servo publishes and readers move on (SculptSession
  /// does both).
  int spare_versions = -1;
  bool checksums = false;  ///< the writer stores a checksum per version and readers can verify() it (tests)
};

/// One slab as a reader sees it. Arrays in grid::index order of the slab's grid (displacement
/// grid: per_slab points; texel grid: texels_per_slab points), like SlabModel::slab_samples.
/// The pointers stay valid until the reader's next SnapshotReader::slab() call or its end.
struct SlabView {
  uint64_t epoch = 0;                         ///< epoch since which the slab holds this content (0: the model at construction)
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

/// Copy-on-write snapshots of a model, per slab, published in epochs for concurrent readers.
///
/// Memory: the spare versions, about (26·per_slab + 4·texels_per_slab) bytes each, padded to 64
/// bytes and allocated by the constructor, and 20 bytes per slab: 0.39 MiB for the default bunny
/// bake (1,178 slabs, n = 16, m = 2: 59 versions of 6,272 bytes), 3.9 % of the 10.1 MiB the model
/// takes (`hdm bench` prints both). A reader holds one more slab's copy.
/// The model's topology, coarse vertices, grid sizes, source fields and under-layer material
/// must not change while the snapshots exist (edits never change them); readers read those
/// members of the live model directly.
class SlabSnapshots {
 public:
  /// @brief Takes the live @p model as epoch 0 (nothing is copied). Keeps a reference to @p model:
  /// it must outlive this object.
  /// @pre rebuild_derived(model) has run (slab_samples and the layouts are built).
  /// @throws InvalidInput when the model's derived data are missing or the options are out of range.
  explicit SlabSnapshots(const SlabModel& model, const SnapshotOptions& options = {});
  ~SlabSnapshots();
  SlabSnapshots(const SlabSnapshots&) = delete;
  SlabSnapshots& operator=(const SlabSnapshots&) = delete;

  // ---- writer: the one thread that edits the model ----

  /// @brief Asks to write slab @p slab of the live model (any of the data a SlabView shows). The
  /// first call for a slab since the last commit copies its committed state into a spare version,
  /// which readers pinned before the next commit read from then on.
  /// @return true: write the slab freely until the next publish_commit(). false: do not write it
  ///         yet; ask again later. Either no spare version is free (starved(): commit, and readers
  ///         will release the old ones), or a reader is copying the slab from the live model this
  ///         moment (under a microsecond).
  /// @note noexcept, no allocation, no waiting: O(per_slab + texels_per_slab) the first time
  ///       (0.8 µs at n = 16, m = 2 with the commit: `bench_edit` publish/*), O(1) after;
  ///       O(readers + retired versions) when it must recycle versions first.
  bool before_write(int slab) noexcept;
  /// @brief Makes every write since the last commit visible as the next epoch and returns it.
  /// @pre The writer writes no slab it was not granted by before_write() (what a reader sees of a
  ///      slab written without it is undefined).
  /// @note noexcept, no allocation; O(slabs written since the last commit). Does nothing (returns
  ///       epoch()) when nothing was written.
  uint64_t publish_commit() noexcept;
  /// Slabs granted (or being preserved) since the last commit.
  int pending() const noexcept;
  /// @brief Recycles the versions no reader needs any more and tells whether every version an
  /// earlier commit replaced is free again. Committing only then keeps what a reader pinned at an
  /// old epoch holds to one batch, and leaves the rest of the pool to new slabs: a slab written again
  /// before the next commit needs no new version.
  /// @note noexcept, no allocation: O(readers + retired versions).
  bool readers_caught_up() noexcept;
  /// True when the last before_write() refused for want of a spare version (cleared by a commit).
  bool starved() const noexcept { return starved_; }
  /// Spare versions holding an edited slab's older state (pending or retired), writer thread only.
  int versions_in_use() const noexcept { return static_cast<int>(version_total_ - free_.size()); }

  // ---- any thread ----

  /// The newest committed epoch (0 before the first publication).
  uint64_t epoch() const noexcept { return published_.load(std::memory_order_acquire); }
  /// The live model (its static members only may be read from threads other than the writer).
  const SlabModel& model() const noexcept { return model_; }
  /// Reader slots (SnapshotOptions::reader_slots).
  int reader_slots() const noexcept { return static_cast<int>(slot_count_); }
  /// Spare versions allocated.
  int version_count() const noexcept { return static_cast<int>(version_total_); }
  /// Bytes held: the versions and the per-slab state.
  size_t memory_bytes() const noexcept;

 private:
  friend class SnapshotReader;
  static constexpr uint64_t kOpen = UINT64_MAX;  // Version::to while its batch is not committed
  struct Version {
    std::atomic<uint64_t> from{0};     // epoch since which its content was the slab's
    std::atomic<uint64_t> to{kOpen};   // epoch of the commit that replaced it (kOpen: not yet)
    std::atomic<int32_t> prev{-1};     // older version of the same slab (-1: none needed)
    int32_t next = -1;                 // writer only: newer version of the same slab
    int32_t slab = -1;                 // writer only
    bool unlinked = false;             // writer only: retired and no longer any slab's newest
    uint64_t checksum = 0;
  };
  // A version's bytes: storage for its SlabSample, 16-bit fields and texel codes (C++20 implicit
  // object creation in an unsigned char array).
  unsigned char* data(int32_t v) noexcept { return arena_.data() + static_cast<size_t>(v) * stride_; }
  const unsigned char* data(int32_t v) const noexcept { return arena_.data() + static_cast<size_t>(v) * stride_; }
  void fill(unsigned char* d, int slab) const noexcept;
  uint64_t checksum(const unsigned char* d) const noexcept;
  SlabView view(const unsigned char* d, uint64_t epoch) const noexcept;
  void reclaim() noexcept;

  const SlabModel& model_;
  SnapshotOptions options_;
  int per_slab_ = 0, texels_per_slab_ = 0;
  size_t stride_ = 0;  // bytes per version, a multiple of 64
  size_t version_total_ = 0, slot_count_ = 0, slab_total_ = 0;
  std::vector<unsigned char> arena_;
  std::unique_ptr<Version[]> versions_;
  std::unique_ptr<std::atomic<int32_t>[]> head_;         // #S: newest preserved version (-1: none needed)
  std::unique_ptr<std::atomic<int32_t>[]> guard_;        // #S: readers copying the live slab
  std::unique_ptr<std::atomic<uint64_t>[]> live_since_;  // #S: epoch since which the live slab is current
  std::unique_ptr<std::atomic<uint64_t>[]> slots_;       // reader epochs (kFree / kClaiming / epoch)
  std::atomic<uint64_t> published_{0};
  // writer only
  std::vector<uint8_t> state_;  // #S: 0 untouched since the commit, 1 preserved, 2 granted
  std::vector<int32_t> free_, retired_, pending_;
  bool starved_ = false;
};

/// A reader's pinned snapshot: every slab as of one epoch. Hold it briefly (a frame, a save):
/// while it lives, versions replaced after its epoch cannot be recycled, and edits that need a
/// spare version may pause.
///
/// Threading: one object per reading thread; the constructor waits (yielding) while every reader
/// slot is taken, never the writer. Reads are lock-free and see no writes in progress.
class SnapshotReader {
 public:
  /// @brief Pins the newest epoch of @p snapshots.
  /// @note Allocates one slab's copy (SlabSnapshots' version size).
  explicit SnapshotReader(const SlabSnapshots& snapshots);
  ~SnapshotReader();
  SnapshotReader(const SnapshotReader&) = delete;
  SnapshotReader& operator=(const SnapshotReader&) = delete;

  /// The pinned epoch.
  uint64_t epoch() const noexcept { return epoch_; }
  /// @brief Slab @p slab as of epoch(): its preserved version when an edit has written it since,
  /// else a copy of the live slab, made while the writer is held off that slab.
  /// @return a view valid until the next slab() or verify() call of this reader, or its end.
  /// @note noexcept, no allocation; O(per_slab + texels_per_slab) for a live slab's copy (0.8 µs
  ///       at n = 16, m = 2), O(versions of that slab newer than epoch()) otherwise, usually O(1).
  SlabView slab(int slab) const noexcept;
  /// @brief SlabView::epoch of slab(@p slab) without the copy: the epoch since which the slab holds
  /// its content at epoch(). A renderer compares it with the epoch it drew to skip unchanged slabs.
  /// @note noexcept, no allocation; O(1) but for the versions newer than epoch(), as slab().
  uint64_t slab_epoch(int slab) const noexcept;
  /// @brief True when slab @p slab reads back intact: a version's checksum matches its content
  /// (with SnapshotOptions::checksums), and a live slab copied twice under one guard gives the same
  /// bytes. For tests: a version or copy torn by a concurrent write fails it.
  bool verify(int slab) const noexcept;
  /// @brief The stored data of the whole model as of epoch(): a SlabModel with the stored members
  /// filled (derived members empty), ready for save_model() or rebuild_derived().
  /// @note Allocates O(model size); each sample and texel is taken from its home slab.
  SlabModel stored_model() const;

 private:
  // The slab's version at epoch_, or -1 when the live slab is current at it (the guard held).
  int32_t find(int slab) const noexcept;
  const SlabSnapshots& s_;
  size_t slot_ = 0;
  uint64_t epoch_ = 0;
  mutable std::vector<unsigned char> copy_, check_;  // a live slab's copy (and a second, for verify())
};

}  // namespace hdm
