// SPDX-License-Identifier: MIT
#pragma once
// Internal: 63-bit Morton codes of points in a box (21 bits per axis, interleaved x, y, z from the
// lowest bit), the order that keeps points near each other near each other in a list: spatial parts
// of a large mesh, and queries made in an order that reuses what the last one read.

#include <hdm/core/types.h>

#include <cstdint>

namespace hdm::core::detail {

// The low 21 bits of @p x with two zero bits after each.
inline uint64_t morton_spread(uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

// The Morton code of @p p in @p box (points outside it are clamped to its faces).
inline uint64_t morton_code(const Vec3& p, const Aabb& box) {
  const Vec3 size = (box.max - box.min).cwiseMax(Vec3::Constant(1e-300));
  const Vec3 u = ((p - box.min).cwiseQuotient(size) * double((1 << 21) - 1)).cwiseMax(0.0).cwiseMin(double((1 << 21) - 1));
  return morton_spread(uint64_t(u.x())) | morton_spread(uint64_t(u.y())) << 1 | morton_spread(uint64_t(u.z())) << 2;
}

}  // namespace hdm::core::detail
