// SPDX-License-Identifier: MIT
#pragma once
// The newest value of something one thread writes and one other thread reads, without either
// ever waiting (a triple buffer): the mouse position from the render thread to the servo thread,
// the tool state from the servo thread to the render thread.
#include <atomic>
#include <cstdint>
#include <type_traits>

namespace hdm::studio {

/// One writer thread, one reader thread; T a fixed-size value (copying never allocates). write() and read() are
/// wait-free, never allocate, and a read never sees a half-written value.
template <class T>
class LatestValue {
  static_assert(std::is_copy_assignable_v<T>);  // fixed-size values: copying never allocates

 public:
  explicit LatestValue(const T& initial = T{}) {
    for (T& s : slots_) s = initial;
  }
  /// Writer: publishes @p value (the reader sees it from its next read()).
  void write(const T& value) noexcept {
    slots_[back_] = value;
    // Swap the back slot with the middle one, flagging it fresh.
    const uint32_t old = middle_.exchange(back_ | kFresh, std::memory_order_acq_rel);
    back_ = old & kIndex;
  }
  /// Reader: the newest value written (or the last one read when nothing new came).
  const T& read() noexcept {
    if (middle_.load(std::memory_order_relaxed) & kFresh) {
      const uint32_t old = middle_.exchange(front_, std::memory_order_acq_rel);
      front_ = old & kIndex;
    }
    return slots_[front_];
  }

 private:
  static constexpr uint32_t kFresh = 4, kIndex = 3;
  T slots_[3];
  uint32_t back_ = 0, front_ = 1;  // owned by the writer / the reader
  std::atomic<uint32_t> middle_{2};
};

}  // namespace hdm::studio
