// SPDX-License-Identifier: MIT
#pragma once
// The angle between two directions, as the scenarios score forces and normals.
#include <hdm/core/types.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace hdm::harness::detail {

// Angle between @p a and @p b [degrees, 0..180]; neither needs to be unit length (both non-zero).
inline double angle_deg(const Vec3& a, const Vec3& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180 / std::numbers::pi;
}

}  // namespace hdm::harness::detail
