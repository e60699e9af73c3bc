// SPDX-License-Identifier: MIT
// libFuzzer target for the replay device's CSV reader (ReplayDevice::from_csv), played to its end.
#include <hdm/core/error.h>
#include <hdm/haptics/device.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    hdm::ReplayDevice d = hdm::ReplayDevice::from_csv({reinterpret_cast<const char*>(data), size}, "fuzz.csv");
    // What the reader promises: at least one row, finite positions, time that never goes back.
    if (d.size() == 0 || !std::isfinite(d.rate_hz())) __builtin_trap();
    hdm::DeviceState s;
    double last = -INFINITY;
    size_t rows = 0;
    while (d.begin_frame(s)) {
      if (!s.position.allFinite() || !(s.time_s >= last)) __builtin_trap();
      last = s.time_s;
      d.end_frame(hdm::Vec3::Zero());
      ++rows;
    }
    if (rows != d.size()) __builtin_trap();
  } catch (const hdm::InvalidInput&) {
  } catch (const hdm::IoError&) {}
  return 0;
}
