// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// 8-bit texel encodings: sRGB colour (IEC 61966-2-1) and unorm8 scalars. SlabModel stores its
/// per-texel colour and roughness in them; everything that reads a colour as linear RGB decodes.

#include <hdm/core/types.h>

#include <array>
#include <cstdint>

namespace hdm {

/// An 8-bit sRGB colour texel: each channel is round(255 · oetf(linear)) with the sRGB transfer
/// function of IEC 61966-2-1 (no alpha). 3 bytes; trivially copyable, so arrays of it can be
/// uploaded as GL_SRGB8 / written to PNG as they are.
struct Srgb8 {
  /// @{ encoded red, green and blue (0 → linear 0, 255 → linear 1)
  uint8_t r = 0, g = 0, b = 0;
  /// @}
  /// @brief Channel-wise equality of the codes.
  friend bool operator==(const Srgb8&, const Srgb8&) = default;
};

namespace core::detail {
/// @{ Tables of the sRGB encodings (src/core/srgb.cpp), built before main: srgb_bound[k] is the
/// least float whose code is above k (srgb_bound[255] = +inf), srgb_bucket[i] the code of linear
/// i/4096 (i = 0..4096), srgb_decode[k] the linear value of code k. Inline so that paint's
/// per-texel blend needs no call.
extern const std::array<float, 256> srgb_bound, srgb_decode;
extern const std::array<uint8_t, 4097> srgb_bucket;
/// @}
}  // namespace core::detail

/// @brief Encodes a linear colour channel in [0,1] as an 8-bit sRGB value (IEC 61966-2-1):
/// round(255 · s) with s = 12.92·c for c ≤ 0.0031308, else 1.055·c^(1/2.4) − 0.055, exactly
/// (every float agrees with the formula evaluated in double). Values outside [0,1] are clamped,
/// NaN gives 0.
/// @note noexcept, no allocation, no branch: two dependent table lookups (the code at the lower end
/// of the value's 1/4096 bucket, then the one code boundary the bucket may hold), ~2 ns; usable in
/// the servo tick.
inline uint8_t linear_to_srgb8(float linear) noexcept {
  // Clamped with selects (minss / maxss), not branches: paint encodes each channel of every texel
  // it blends, and the branches cost more than the lookups. NaN fails `>` and becomes 0.
  const float c = linear > 0.0f ? (linear < 1.0f ? linear : 1.0f) : 0.0f;
  // A bucket spans less than one code boundary (12.92·255 codes per unit at the steepest), so the
  // code is the bucket's or the next; 1.0 indexes the last entry (code 255, below bound +inf).
  const unsigned code = core::detail::srgb_bucket[static_cast<uint32_t>(static_cast<int32_t>(c * 4096.0f))];
  return static_cast<uint8_t>(code + (core::detail::srgb_bound[code] <= c ? 1u : 0u));
}

/// @brief Decodes an 8-bit sRGB value to a linear channel in [0,1] (the inverse transfer function
/// of IEC 61966-2-1); linear_to_srgb8(srgb8_to_linear(c)) == c for every code.
/// @note noexcept, a table lookup.
inline float srgb8_to_linear(uint8_t code) noexcept { return core::detail::srgb_decode[code]; }

/// @brief linear_to_srgb8() of each channel of the linear RGB colour @p linear.
/// @note noexcept, no allocation.
inline Srgb8 encode_srgb8(const Vec3f& linear) noexcept {
  return {linear_to_srgb8(linear.x()), linear_to_srgb8(linear.y()), linear_to_srgb8(linear.z())};
}

/// @brief srgb8_to_linear() of each channel: the linear RGB colour @p c stands for.
/// @note noexcept, three table lookups.
inline Vec3f decode_srgb8(Srgb8 c) noexcept {
  return {core::detail::srgb_decode[c.r], core::detail::srgb_decode[c.g], core::detail::srgb_decode[c.b]};
}

/// @brief Encodes @p v in [0,1] as unorm8, round(255 · v) with halves up; outside [0,1] clamped,
/// NaN gives 0.
/// @note noexcept, O(1), no branch.
inline uint8_t unit_to_unorm8(float v) noexcept {
  const float c = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;
  // 255 · c and the added half are exact in double (8 + 24 bits), so truncation rounds 255 · c
  // itself, not a float product already rounded.
  return static_cast<uint8_t>(static_cast<int32_t>(static_cast<double>(c) * 255.0 + 0.5));
}

/// @brief Decodes a unorm8 value: @p code / 255, in [0,1].
/// @note noexcept, O(1).
inline float unorm8_to_unit(uint8_t code) noexcept { return static_cast<float>(code) * (1.0f / 255.0f); }

}  // namespace hdm
