// SPDX-License-Identifier: MIT
// libFuzzer target for the sculpt script reader (parse_script, apps/hdm/sculpt_script.cpp).
#include "sculpt_script.h"

#include <hdm/core/error.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  hdm::app::Script s;
  try {
    s = hdm::app::parse_script({reinterpret_cast<const char*>(data), size}, "fuzz.json");
  } catch (const hdm::InvalidInput&) {
    return 0;
  }
  // What parse_script() promises: strokes, and every number finite and inside its range.
  if (s.strokes.empty() || !(s.workspace_m > 0 && s.workspace_m <= 10)) __builtin_trap();
  for (const hdm::app::Stroke& st : s.strokes)
    if (!st.from.allFinite() || !st.to.allFinite() || !(st.speed_mm_s >= 1e-2) || !(st.radius_mm > 0) ||
        !std::isfinite(st.depth_mm) || !st.colour.allFinite())
      __builtin_trap();
  return 0;
}
