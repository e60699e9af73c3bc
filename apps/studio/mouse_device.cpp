// SPDX-License-Identifier: MIT
#include "mouse_device.h"

#include <algorithm>

namespace hdm::studio {

void MouseDevice::push(const MouseHandle& h) noexcept {
  if (count_ == kQueue) {  // far behind (the servo was starved): drop the oldest point
    head_ = (head_ + 1) % kQueue, --count_;
    play_ = std::max(play_, at(0).tick);
  }
  if (count_ == 1) {
    // Holding at the only point: the segment to the new one starts now, or at most 100 ms ago.
    Point& front = queue_[head_];
    front.tick = std::max(front.tick, tick_ - max_ticks_);
    play_ = std::max(play_, front.tick);
  }
  const Eigen::Quaterniond q = h.orientation.coeffs().allFinite() && h.orientation.norm() > 0.5
                                   ? h.orientation.normalized()
                                   : Eigen::Quaterniond::Identity();
  queue_[(head_ + count_) % kQueue] = Point{h.position, q, h.buttons, tick_};
  ++count_;
}

bool MouseDevice::begin_frame(DeviceState& state) noexcept {
  const MouseHandle& h = latest_.read();
  ++tick_;
  if (h.serial != seen_ && h.position.allFinite()) push(h);
  seen_ = h.serial;
  const bool started = count_ > 0;
  Vec3 p = last_;
  Eigen::Quaterniond q = last_orientation_;
  if (started) {
    // Advance the playback (twice as fast while more than one segment waits), never past the
    // newest point; pass the points reached, taking their buttons.
    play_ = std::min(play_ + (count_ > 2 ? 2 : 1), at(count_ - 1).tick);
    while (count_ > 1 && play_ >= at(1).tick) head_ = (head_ + 1) % kQueue, --count_;
    const Point& a = at(0);
    buttons_ = a.buttons;
    p = a.position;
    q = a.orientation;
    if (count_ > 1) {
      const Point& b = at(1);
      const double w = double(play_ - a.tick) / double(b.tick - a.tick);
      p = a.position + (b.position - a.position) * w;
      q = a.orientation.slerp(w, b.orientation);
    }
  }
  const bool moving = started && moved_before_;  // the first position is where the handle starts
  moved_before_ = started;
  if (moving) {
    const double moved = (p - last_).norm();
    if (moved > max_step_.load(std::memory_order_relaxed)) max_step_.store(moved, std::memory_order_relaxed);
  }
  state.velocity = moving ? Vec3((p - last_) / period_s_) : Vec3::Zero();
  state.position = p;
  state.orientation = q;
  // The turn from the last tick's orientation, as a rotation vector per period [rad/s].
  const Eigen::AngleAxisd turn(q * last_orientation_.conjugate());
  state.angular_velocity = moving ? Vec3(turn.axis() * (turn.angle() / period_s_)) : Vec3::Zero();
  state.buttons = buttons_;
  state.time_s = time_s_;
  time_s_ += period_s_;
  last_ = p;
  last_orientation_ = q;
  return true;
}

}  // namespace hdm::studio
