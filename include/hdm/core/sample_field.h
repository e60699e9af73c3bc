// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// A per-sample field that holds one value for every sample until a write makes two differ: a
/// baked or loaded model's friction, stiffness scale, under-layer top and hardness, and its
/// texels' colour and roughness, are the same everywhere until a brush paints them, and then take
/// no array at all (2 bytes per sample, 4 per texel otherwise). The same idea as OpenVDB's tile
/// values: a constant region stores its value once.

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

namespace hdm {

/// #samples codes of a field (Unorm16, Half16 per displacement sample; Srgb8, uint8_t per texel),
/// stored as one *uniform* value until a write differs from it, then as an array of one code per
/// sample.
///
/// Reads cost one predictable branch. Writes go through set(): a write that equals the uniform
/// value stores nothing; the first one that differs allocates the array (#samples codes). Code that
/// must not allocate while it writes (the edits: StrokeEditor and EditScratch call it when they are
/// made) calls materialise() first: from then on the field keeps its array, and neither set() nor
/// compact() allocates or frees it. Codes compare by their bytes.
/// @tparam Code  a trivially copyable code type without padding (Unorm16, Half16, Srgb8, uint8_t).
template <class Code>
class SampleField {
  static_assert(std::is_trivially_copyable_v<Code> && std::has_unique_object_representations_v<Code>,
                "codes compare by their bytes");

 public:
  SampleField() = default;
  /// @brief @p count samples, each @p value (uniform: no array). @note O(1), no allocation.
  SampleField(size_t count, Code value) noexcept : count_(count), value_(value) {}

  /// Number of samples.
  size_t size() const noexcept { return count_; }
  /// True for a field of no samples.
  bool empty() const noexcept { return count_ == 0; }
  /// True while every sample holds uniform_value() and no array is allocated.
  bool uniform() const noexcept { return values_.empty(); }
  /// The value every sample holds while uniform() (meaningless otherwise).
  Code uniform_value() const noexcept { return value_; }
  /// @brief The code of sample @p i. @pre i < size(). @note noexcept, O(1), no allocation.
  /// Returned const, so that `field[i] = v` does not compile: writes go through set().
  const Code operator[](size_t i) const noexcept { return values_.empty() ? value_ : values_[i]; }

  /// Reads the codes in sample order (a range-for over the field); each is a copy.
  class const_iterator {
   public:
    using value_type = Code;                 ///< a code, by value
    using difference_type = std::ptrdiff_t;  ///< distance between sample indices
    const_iterator() = default;
    /// At sample @p i of @p f.
    const_iterator(const SampleField* f, size_t i) noexcept : f_(f), i_(i) {}
    /// The code of the current sample.
    const Code operator*() const noexcept { return (*f_)[i_]; }
    /// Moves to the next sample.
    const_iterator& operator++() noexcept { return ++i_, *this; }
    /// Moves to the next sample, returning the current position.
    const_iterator operator++(int) noexcept {
      const_iterator t = *this;
      ++i_;
      return t;
    }
    /// Same sample index (of the same field).
    bool operator==(const const_iterator& o) const noexcept { return i_ == o.i_; }

   private:
    const SampleField* f_ = nullptr;
    size_t i_ = 0;
  };
  /// First code, in sample order.
  const_iterator begin() const noexcept { return {this, 0}; }
  /// Past the last code.
  const_iterator end() const noexcept { return {this, count_}; }

  /// @brief Sample @p i takes @p v. On a uniform field a write of the uniform value stores nothing;
  /// another value materialises the field first (allocates size() codes, unless materialise() ran).
  /// @pre i < size(). @throws std::bad_alloc when materialising fails.
  void set(size_t i, Code v) {
    if (values_.empty()) {
      if (same(v, value_)) return;
      values_.assign(count_, value_);  // not kept: compact() may free it again
    }
    values_[i] = v;
  }
  /// @brief Allocates the per-sample array now, each code the uniform value, and keeps it from
  /// then on (materialised()). No effect on an empty field. @throws std::bad_alloc. @note O(size()).
  void materialise() {
    if (values_.empty() && count_ > 0) values_.assign(count_, value_);
    kept_ = count_ > 0;
  }
  /// True once materialise() ran: the array stays, and writes never allocate.
  bool materialised() const noexcept { return kept_; }
  /// @brief @p count samples, each @p value: uniform, with no array (a materialised field of the
  /// same size fills its array instead). @throws std::bad_alloc only when a materialised field
  /// changes size. @note O(1), or O(size()) when materialised.
  void assign(size_t count, Code value) {
    if (kept_) {
      values_.assign(count, value);
    } else {
      std::vector<Code>().swap(values_);
    }
    count_ = count, value_ = value;
    kept_ = kept_ && count > 0;
  }
  /// @brief Takes @p values as the field's codes (one per sample); uniform again, with no array,
  /// when they are all equal and the field is not materialised. @note O(#values), no allocation.
  void assign(std::vector<Code>&& values) noexcept {
    count_ = values.size();
    values_ = std::move(values);
    if (values_.empty()) kept_ = false;
    compact();
  }
  /// @brief Whether every sample holds the same code (true while uniform(), and for a field of at
  /// most one sample). @note O(size()) when materialised, O(1) otherwise; no allocation.
  bool all_equal() const noexcept {
    for (const Code& c : values_)
      if (!same(c, values_[0])) return false;
    return true;
  }
  /// @brief Frees the array when every code equals the first (a painted field painted back, a
  /// loaded field never painted), unless the field is materialised. @note O(size()), no allocation.
  void compact() noexcept {
    if (values_.empty() || kept_ || !all_equal()) return;
    value_ = values_[0];
    std::vector<Code>().swap(values_);
  }
  /// The array of codes, one per sample; null while uniform().
  const Code* data() const noexcept { return values_.empty() ? nullptr : values_.data(); }
  /// @brief Every sample's code, as an array (a uniform field repeats its value).
  /// @throws std::bad_alloc. @note O(size()); allocates.
  std::vector<Code> codes() const { return values_.empty() ? std::vector<Code>(count_, value_) : values_; }
  /// @brief Same size and the same code at every sample, however each field stores them.
  /// @note O(size()), no allocation.
  friend bool operator==(const SampleField& a, const SampleField& b) noexcept {
    if (a.count_ != b.count_) return false;
    for (size_t k = 0; k < a.count_; ++k)
      if (!same(a[k], b[k])) return false;
    return true;
  }
  /// Heap bytes held: the array's capacity (0 while uniform).
  size_t heap_bytes() const noexcept { return values_.capacity() * sizeof(Code); }

  /// @brief Whether two codes are the same bytes. @note noexcept, O(1).
  static bool same(const Code& a, const Code& b) noexcept { return std::memcmp(&a, &b, sizeof(Code)) == 0; }

 private:
  size_t count_ = 0;
  Code value_{};
  std::vector<Code> values_;  // empty while uniform
  bool kept_ = false;         // materialise() ran: the array stays
};

}  // namespace hdm
