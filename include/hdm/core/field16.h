// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// 16-bit per-sample field values: SlabModel stores its surface fields (friction, stiffness
/// scale, under-layer top, hardness) in these, 2 bytes per sample instead of a 4-byte float.
/// Both convert implicitly from and to float, so code reads and writes them as floats; each
/// write rounds once, to nearest.

#include <Eigen/Core>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

namespace hdm {

/// A value in [0, 1] as an unsigned 16-bit code: round(x·65535), clamped (a NaN stores 0).
/// Within 7.7e-6 (half a step) of the value written; every code reads back as itself.
/// Used where the range is [0, 1]: SlabModel::stiffness_scale, SlabModel::layer_displacement.
struct Unorm16 {
  uint16_t code = 0;  ///< the stored code; the value is code / 65535

  Unorm16() = default;
  /// @brief Rounds @p x, clamped to [0, 1], to the nearest code. @note noexcept, O(1).
  Unorm16(float x) noexcept  // NOLINT(google-explicit-constructor): a field written as a float
      : code(x > 0 ? static_cast<uint16_t>(std::lrint(std::min(x, 1.0f) * 65535.0f)) : uint16_t(0)) {}
  /// @brief The value the code stands for, in [0, 1]. @note noexcept, O(1).
  operator float() const noexcept { return float(code) * (1.0f / 65535.0f); }  // NOLINT
};

/// A value as an IEEE 754 binary16 (Eigen::half's conversion, rounding to nearest even): 11
/// significant bits (relative error at most 2^-11 = 4.9e-4), finite up to 65,504. Used where the
/// range has no fixed bound: SlabModel::friction_static, friction_dynamic and hardness [HV].
/// Values above 65,504 in magnitude store ±infinity (the model's validation refuses them).
struct Half16 {
  Eigen::half value;  ///< the stored binary16

  /// The largest finite binary16, 65,504: writers of these fields refuse values beyond ±max.
  static constexpr float max = 65504.0f;

  Half16() = default;
  /// @brief Rounds @p x to the nearest binary16. @note noexcept, O(1).
  Half16(float x) noexcept : value(x) {}  // NOLINT(google-explicit-constructor): a field written as a float
  /// @brief The value, exactly. @note noexcept, O(1).
  operator float() const noexcept { return static_cast<float>(value); }  // NOLINT
  /// @brief The binary16's 16 bits (what a `.hdm` file of version 5 stores). @note noexcept, O(1).
  uint16_t bits() const noexcept { return std::bit_cast<uint16_t>(value); }
  /// @brief The value whose binary16 bits are @p b. @note noexcept, O(1).
  static Half16 from_bits(uint16_t b) noexcept {
    Half16 h;
    h.value = std::bit_cast<Eigen::half>(b);
    return h;
  }
};

static_assert(sizeof(Unorm16) == 2 && sizeof(Half16) == 2, "2 bytes per sample");

}  // namespace hdm
