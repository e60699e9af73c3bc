// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// 16-bit per-sample field values: SlabModel stores its per-sample fields (displacement,
/// friction, stiffness scale, under-layer top, hardness) in these, 2 bytes per sample instead of
/// a 4-byte float.
/// Both convert implicitly from and to float, so code reads and writes them as floats; each
/// write rounds once, to nearest.

#include <Eigen/Core>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace hdm {

/// @brief @p x rounded to the nearest integer, ties to even (std::lrint in the default rounding
/// mode), inline: the edits write a field per changed sample. @pre |x| < 2^31. @note noexcept, O(1).
inline int round_to_int(double x) noexcept {
#if defined(__SSE2__)
  return _mm_cvtsd_si32(_mm_set_sd(x));
#else
  return static_cast<int>(std::lrint(x));
#endif
}

/// A value in [0, 1] as an unsigned 16-bit code: round(x·65535), clamped (a NaN stores 0).
/// Within 7.7e-6 (half a step) of the value written, read back as a float to an ulp; every code
/// reads back as itself. Used where the range is [0, 1]: SlabModel::displacement,
/// SlabModel::stiffness_scale, SlabModel::layer_displacement.
struct Unorm16 {
  uint16_t code = 0;  ///< the stored code; the value is code / 65535

  Unorm16() = default;
  /// @brief Rounds @p x, clamped to [0, 1], to the nearest code. @note noexcept, O(1).
  Unorm16(float x) noexcept  // NOLINT(google-explicit-constructor): a field written as a float
      : code(x > 0 ? static_cast<uint16_t>(round_to_int(double(std::min(x, 1.0f)) * 65535.0)) : uint16_t(0)) {}
  /// @brief The value the code stands for, in [0, 1]. @note noexcept, O(1).
  operator float() const noexcept { return float(code) * (1.0f / 65535.0f); }  // NOLINT
  /// @brief The value in double, code/65535 rounded once to double (one conversion and one
  /// multiplication, for the edits' point tests; within a float ulp of the float value).
  /// @note noexcept, O(1).
  double value() const noexcept { return double(code) * (1.0 / 65535.0); }

  /// @brief @p x, clamped to [0, 1], rounded down or up to a neighbouring code with the
  /// probabilities that make the expected code x·65535 exactly (stochastic rounding, for
  /// increments far below a code step that must add up, as a drill's removal per servo tick).
  /// @param x  the value to store.
  /// @param u  uniform in [0, 1): the rounding's random draw.
  /// @note noexcept, O(1); within one step (1.5e-5) of @p x.
  static Unorm16 dithered(float x, float u) noexcept {
    Unorm16 q;
    const double c = x > 0 ? std::floor(double(std::min(x, 1.0f)) * 65535.0 + double(u)) : 0.0;
    q.code = static_cast<uint16_t>(std::min(c, 65535.0));
    return q;
  }
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
