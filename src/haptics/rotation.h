// SPDX-License-Identifier: MIT
#pragma once
// Rotation vectors of unit quaternions and back (internal): the rigid tool's coupling and the
// simulated and replayed devices' orientations share them.

#include <hdm/core/types.h>

#include <cmath>

namespace hdm::haptics_detail {

// Rotation vector (axis × angle [rad], angle in [0, π]) of a unit quaternion: the shorter way.
inline Vec3 rotation_vector(Eigen::Quaterniond q) noexcept {
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  const double s = q.vec().norm();
  if (s < 1e-12) return 2 * q.vec();
  return (2 * std::atan2(s, q.w()) / s) * q.vec();
}

// The unit quaternion of a rotation vector [rad].
inline Eigen::Quaterniond from_rotation_vector(const Vec3& w) noexcept {
  const double a = w.norm();
  if (a < 1e-12) return Eigen::Quaterniond(1, 0.5 * w.x(), 0.5 * w.y(), 0.5 * w.z()).normalized();
  const Vec3 axis = w / a;
  return Eigen::Quaterniond(Eigen::AngleAxisd(a, axis));
}

}  // namespace hdm::haptics_detail
