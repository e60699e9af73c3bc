// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Scalar, vector and index aliases used at every hdm interface (Eigen fixed-size types: they never
/// allocate, so they are safe in the servo loop).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>

namespace hdm {

/// 3D vector in double precision [model units or SI, as each field states].
using Vec3 = Eigen::Vector3d;
/// 3D vector in single precision (per-sample normals, colours).
using Vec3f = Eigen::Vector3f;
/// Triangle as three vertex ids, counter-clockwise seen from outside.
using Tri = std::array<int32_t, 3>;

/// Axis-aligned bounding box [model units].
struct Aabb {
  Vec3 min = Vec3::Constant(1e300);   ///< lower corner
  Vec3 max = Vec3::Constant(-1e300);  ///< upper corner
  /// Grows the box to contain @p p.
  void extend(const Vec3& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  /// True if @p p lies in the box (closed). noexcept; a NaN point is never inside.
  bool contains(const Vec3& p) const noexcept {
    return p.x() >= min.x() && p.y() >= min.y() && p.z() >= min.z() && p.x() <= max.x() && p.y() <= max.y() &&
           p.z() <= max.z();
  }
  /// Length of the diagonal [model units]; 0 for an empty box.
  double diagonal() const { return min.x() <= max.x() ? (max - min).norm() : 0.0; }
};

}  // namespace hdm
