// SPDX-License-Identifier: MIT
#include <hdm/edit/undo_history.h>

#include <algorithm>

namespace hdm {

UndoHistory::UndoHistory(size_t cap_bytes, int max_strokes)
    : records_(std::max<size_t>(1, cap_bytes / sizeof(UndoRecord))),
      strokes_(static_cast<size_t>(std::max(1, max_strokes))) {}

void UndoHistory::forget_oldest() noexcept {
  ++first_stroke_;
  begin_ = first_stroke_ < stroke_end_ ? stroke(first_stroke_).first : end_;
  top_ = std::max(top_, first_stroke_);
  ++dropped_;
}

void UndoHistory::begin_stroke() noexcept {
  if (open_) end_stroke();
  // New work after undo: the undone strokes can no longer be redone.
  stroke_end_ = top_;
  end_ = top_ > first_stroke_ ? stroke(top_ - 1).last : begin_;
  if (stroke_end_ - first_stroke_ >= static_cast<int>(strokes_.size())) forget_oldest();
  stroke(stroke_end_) = {end_, end_};
  open_ = true;
  overflow_ = false;
}

void UndoHistory::record(const UndoRecord& r) noexcept {
  if (!open_ || overflow_) return;
  while (end_ - begin_ >= records_.size()) {
    if (first_stroke_ < stroke_end_) {
      forget_oldest();
      continue;
    }
    // The open stroke alone fills the ring: it cannot be undone (and nothing before it can).
    overflow_ = true;
    ++dropped_;
    end_ = begin_ = stroke(stroke_end_).first;
    return;
  }
  records_[end_ % records_.size()] = r;
  ++end_;
}

void UndoHistory::end_stroke() noexcept {
  if (!open_) return;
  open_ = false;
  StrokeRange& s = stroke(stroke_end_);
  if (overflow_ || end_ == s.first) {  // nothing to undo
    end_ = s.first;
    if (first_stroke_ == stroke_end_) begin_ = end_;
    return;
  }
  s.last = end_;
  ++stroke_end_;
  top_ = stroke_end_;
}

void UndoHistory::undo_range(uint64_t& first, uint64_t& last) const noexcept {
  const StrokeRange& s = stroke(top_ - 1);
  first = s.first, last = s.last;
}

void UndoHistory::redo_range(uint64_t& first, uint64_t& last) const noexcept {
  const StrokeRange& s = stroke(top_);
  first = s.first, last = s.last;
}

}  // namespace hdm
