// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Undo / redo per stroke with bounded memory: the old values of the samples and texels a stroke
/// changed, recorded when the stroke first touches them, in a ring of fixed size.

#include <hdm/core/field16.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

namespace hdm {

/// Every stored per-sample value an edit may change (SlabModel's displacement, friction_static,
/// friction_dynamic, stiffness_scale, layer_displacement, hardness), as the model stores them:
/// copied without a conversion, so a restore gives back the same codes.
struct SampleValues {
  float delta;                 ///< SlabModel::displacement
  Half16 friction_static;      ///< SlabModel::friction_static
  Half16 friction_dynamic;     ///< SlabModel::friction_dynamic
  Unorm16 stiffness_scale;     ///< SlabModel::stiffness_scale
  Unorm16 layer_displacement;  ///< SlabModel::layer_displacement
  Half16 hardness;             ///< SlabModel::hardness [HV]
};

/// Every stored per-texel value an edit may change (SlabModel's colour and roughness).
struct TexelValues {
  /// @{ The texel's linear RGB colour and roughness, each in [0,1], decoded from its 8-bit codes.
  float r, g, b, roughness;
  /// @}
};

/// One record: a sample's or a texel's values (before the stroke until it is undone; after the
/// stroke once it is undone, so that redo swaps them back). 20 bytes.
struct UndoRecord {
  int32_t index;  ///< >= 0: sample id; < 0: texel id -(index + 1)
  alignas(4) unsigned char values[16];  ///< SampleValues or TexelValues, bit for bit

  /// A sample's record. @note noexcept, O(1).
  UndoRecord(int32_t sample, const SampleValues& v) noexcept : index(sample) { set(v); }
  /// A texel's record (@p texel is the texel id). @note noexcept, O(1).
  UndoRecord(int32_t texel, const TexelValues& v) noexcept : index(-(texel + 1)) { set(v); }
  UndoRecord() noexcept : index(0), values{} {}
  /// The sample's values (index >= 0). @note noexcept, O(1).
  SampleValues sample() const noexcept { return get<SampleValues>(); }
  /// The texel's values (index < 0). @note noexcept, O(1).
  TexelValues texel() const noexcept { return get<TexelValues>(); }
  /// Stores @p v (SampleValues or TexelValues). @note noexcept, O(1).
  template <class V>
  void set(const V& v) noexcept {
    static_assert(sizeof(V) <= sizeof(values) && std::is_trivially_copyable_v<V>);
    std::memcpy(values, &v, sizeof(V));
  }

 private:
  template <class V>
  V get() const noexcept {
    V v;
    std::memcpy(&v, values, sizeof(V));
    return v;
  }
};

/// The undo history: strokes (button down to button up) as ranges of records in one ring.
///
/// Memory is fixed at construction: @p cap_bytes of records (20 bytes each) and a table of
/// @p max_strokes strokes. When a new record does not fit, the oldest strokes are forgotten; when
/// the stroke being recorded alone exceeds the ring, the whole history is dropped and that stroke
/// cannot be undone (can_undo() is then false until the next stroke). A new stroke discards the
/// strokes that were undone (no redo after new work), as editors do.
/// Kept in memory for the session only: `.hdm` files do not store it.
///
/// Threading: one thread (the one that edits). No allocation after construction.
class UndoHistory {
 public:
  /// @brief Allocates the ring. @param cap_bytes record memory [bytes] (at least one record).
  /// @param max_strokes strokes remembered (at least 1).
  explicit UndoHistory(size_t cap_bytes = size_t(64) << 20, int max_strokes = 4096);

  /// @brief Opens a stroke; discards the redo strokes. Nested calls close the open stroke first.
  void begin_stroke() noexcept;
  /// @brief Appends a record to the open stroke (ignored when no stroke is open or it overflowed).
  void record(const UndoRecord& r) noexcept;
  /// @brief Closes the open stroke; an empty or overflowed stroke is not kept.
  void end_stroke() noexcept;
  /// True while a stroke is open.
  bool recording() const noexcept { return open_; }

  /// Strokes that can be undone.
  int undo_count() const noexcept { return top_ - first_stroke_; }
  /// Strokes that can be redone (undone since the last new stroke).
  int redo_count() const noexcept { return stroke_end_ - top_; }
  /// True when no stroke is open and one can be undone.
  bool can_undo() const noexcept { return !open_ && undo_count() > 0; }
  /// True when no stroke is open and one can be redone.
  bool can_redo() const noexcept { return !open_ && redo_count() > 0; }

  /// @brief Records of the stroke the next undo reverts (the last applied one), as a range of
  /// ring positions [first, last); read them with at(). Precondition: can_undo().
  void undo_range(uint64_t& first, uint64_t& last) const noexcept;
  /// @brief Records of the stroke the next redo re-applies. Precondition: can_redo().
  void redo_range(uint64_t& first, uint64_t& last) const noexcept;
  /// Marks the last applied stroke as undone (after its records were swapped into the model).
  void undone() noexcept { --top_; }
  /// Marks the next undone stroke as redone.
  void redone() noexcept { ++top_; }
  /// The record at ring position @p pos (from undo_range / redo_range). O(1).
  UndoRecord& at(uint64_t pos) noexcept { return records_[pos % records_.size()]; }

  /// Bytes of record memory (the cap).
  size_t capacity_bytes() const noexcept { return records_.size() * sizeof(UndoRecord); }
  /// Records held now (all kept strokes).
  size_t records_held() const noexcept { return static_cast<size_t>(end_ - begin_); }
  /// Strokes dropped so far because the cap was reached (oldest first, or a whole history).
  int64_t strokes_dropped() const noexcept { return dropped_; }

 private:
  struct StrokeRange {
    uint64_t first = 0, last = 0;  // ring positions [first, last)
  };
  StrokeRange& stroke(int k) noexcept { return strokes_[static_cast<size_t>(k) % strokes_.size()]; }
  const StrokeRange& stroke(int k) const noexcept { return strokes_[static_cast<size_t>(k) % strokes_.size()]; }
  void forget_oldest() noexcept;

  std::vector<UndoRecord> records_;
  std::vector<StrokeRange> strokes_;
  uint64_t begin_ = 0, end_ = 0;  // ring positions held [begin_, end_)
  int first_stroke_ = 0;          // oldest stroke kept (index into the stroke table, monotonic)
  int top_ = 0;                   // strokes [first_stroke_, top_) are applied, [top_, stroke_end_) undone
  int stroke_end_ = 0;
  bool open_ = false, overflow_ = false;
  int64_t dropped_ = 0;
};

}  // namespace hdm
