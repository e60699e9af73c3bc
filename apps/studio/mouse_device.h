// SPDX-License-Identifier: MIT
#pragma once
// The mouse as a 3-DOF haptic device: the render thread turns the cursor into a handle position
// (the cursor ray meets the surface, pushed in along the view ray by the tool depth) and the
// servo thread reads it through the same HapticDevice interface a real device uses.
#include "latest_value.h"

#include <hdm/haptics/device.h>

#include <atomic>
#include <cstdint>

namespace hdm::studio {

/// What the render thread sets: the handle pose and the buttons held.
struct MouseHandle {
  Vec3 position = Vec3::Zero();  ///< device frame [m]
  /// The handle's orientation (handle frame → device frame, unit); the mouse turns it with a
  /// modifier key held (a rigid tool reads it, the point and ball proxies ignore it).
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  uint32_t buttons = 0;  ///< bit 0: the tool button (left mouse button)
  uint64_t serial = 0;   ///< increases with every set() (the servo thread tells new frames by it)
};

/// A HapticDevice fed by the render thread. No force comes out (a mouse cannot push back); the
/// proxy still holds the rendered tool on the surface, so probe, carve and paint follow the same
/// code paths as with a real device.
///
/// Smoothing: the render thread sets a position once per frame (20 to 100 Hz), the servo reads
/// one per tick (1 or 10 kHz). Read as is, the handle would stand still and then jump by a frame's
/// motion in one tick, and the velocity the damping sees would spike to that jump over one period.
/// Instead the servo thread plays the positions back one frame late, as a piecewise-linear path in
/// time: each position is stamped with the tick it arrived at, and the handle is the path at a
/// playback time that advances one tick per tick and holds at the newest position when a frame is
/// late (a segment lasts at most 100 ms). The position is continuous and the velocity is the
/// cursor's over each frame. The orientation follows the same path (spherical interpolation), and
/// the angular velocity is its backward difference over one period. A position's buttons take
/// effect when the playback reaches it, so a stroke starts and ends exactly where the cursor
/// pressed and released. When frames come faster
/// than they are played (the queue of 8 grows past 2), the playback goes at double speed to catch up.
class MouseDevice final : public HapticDevice {
 public:
  /// @param rate_hz  servo rate, for the backward-difference velocity and the smoothing [Hz], > 0.
  explicit MouseDevice(double rate_hz) : period_s_(1.0 / rate_hz), max_ticks_(std::max(1.0, 0.1 * rate_hz)) {}
  /// Render thread: the newest handle position and buttons (serial set here). Wait-free.
  void set(MouseHandle handle) noexcept {
    handle.serial = ++serial_;
    latest_.write(handle);
  }
  /// Servo thread: the handle, one tick further along the line to the newest position (see the
  /// class), velocity by backward difference over one period; a non-finite position is ignored
  /// (the handle stays). Always true. noexcept, O(1), no allocation.
  bool begin_frame(DeviceState& state) noexcept override;
  using HapticDevice::end_frame;  // the torque overload: dropped (no torque to render)
  /// Servo thread: keeps @p force_n for last_force() (nothing to command). noexcept.
  void end_frame(const Vec3& force_n) noexcept override { force_ = force_n; }
  /// A desktop device's spec (the workspace the model is fitted to).
  DeviceSpec spec() const noexcept override { return {}; }
  /// The largest move of the handle from one tick to the next so far [m]. Any thread.
  double max_tick_step_m() const noexcept { return max_step_.load(std::memory_order_relaxed); }

 private:
  struct Point {
    Vec3 position;
    Eigen::Quaterniond orientation;
    uint32_t buttons;
    int64_t tick;  // playback time of the point [ticks]
  };
  static constexpr int kQueue = 8;
  const Point& at(int k) const noexcept { return queue_[(head_ + k) % kQueue]; }
  void push(const MouseHandle& h) noexcept;

  LatestValue<MouseHandle> latest_;
  uint64_t serial_ = 0;  // render thread
  double period_s_;
  int64_t max_ticks_;  // longest segment [ticks]
  // servo thread
  Point queue_[kQueue];
  int head_ = 0, count_ = 0;
  int64_t tick_ = 0, play_ = 0;  // ticks so far; playback time
  uint64_t seen_ = 0;
  double time_s_ = 0;
  Vec3 last_ = Vec3::Zero(), force_ = Vec3::Zero();
  Eigen::Quaterniond last_orientation_ = Eigen::Quaterniond::Identity();
  uint32_t buttons_ = 0;
  bool moved_before_ = false;
  std::atomic<double> max_step_{0.0};
};

}  // namespace hdm::studio
