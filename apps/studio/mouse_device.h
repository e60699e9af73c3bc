// SPDX-License-Identifier: MIT
#pragma once
// The mouse as a 3-DOF haptic device: the render thread turns the cursor into a handle position
// (the cursor ray meets the surface, pushed in along the view ray by the tool depth) and the
// servo thread reads it through the same HapticDevice interface a real device uses.
#include "latest_value.h"

#include <hdm/haptics/device.h>

namespace hdm::studio {

/// What the render thread sets: the handle position and the buttons held.
struct MouseHandle {
  Vec3 position = Vec3::Zero();  ///< device frame [m]
  uint32_t buttons = 0;          ///< bit 0: the tool button (left mouse button)
};

/// A HapticDevice fed by the render thread. No force comes out (a mouse cannot push back); the
/// proxy still holds the rendered tool on the surface, so probe, carve and paint follow the same
/// code paths as with a real device.
class MouseDevice final : public HapticDevice {
 public:
  /// @param rate_hz  servo rate, for the backward-difference velocity [Hz], > 0.
  explicit MouseDevice(double rate_hz) : period_s_(1.0 / rate_hz) {}
  /// Render thread: the newest handle position and buttons. Wait-free.
  void set(const MouseHandle& handle) noexcept { latest_.write(handle); }
  /// Servo thread: the newest handle (velocity by backward difference over one period); a
  /// non-finite position reads as the last finite one. Always true. noexcept, O(1).
  bool begin_frame(DeviceState& state) noexcept override;
  /// Servo thread: keeps @p force_n for last_force() (nothing to command). noexcept.
  void end_frame(const Vec3& force_n) noexcept override { force_ = force_n; }
  /// A desktop device's spec (the workspace the model is fitted to).
  DeviceSpec spec() const noexcept override { return {}; }

 private:
  LatestValue<MouseHandle> latest_;
  double period_s_;
  double time_s_ = 0;
  Vec3 last_ = Vec3::Zero(), force_ = Vec3::Zero();
  bool started_ = false;
};

}  // namespace hdm::studio
