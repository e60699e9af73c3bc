// SPDX-License-Identifier: MIT
#include "mouse_device.h"

namespace hdm::studio {

bool MouseDevice::begin_frame(DeviceState& state) noexcept {
  const MouseHandle& h = latest_.read();
  const Vec3 p = h.position.allFinite() ? h.position : last_;
  state.velocity = started_ ? Vec3((p - last_) / period_s_) : Vec3::Zero();
  state.position = p;
  state.buttons = h.buttons;
  state.time_s = time_s_;
  time_s_ += period_s_;
  last_ = p;
  started_ = true;
  return true;
}

}  // namespace hdm::studio
