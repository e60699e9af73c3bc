// SPDX-License-Identifier: MIT
#include <hdm/core/srgb.h>

#include <array>
#include <cmath>
#include <limits>

namespace hdm {
namespace {

// sRGB-encoded s in [0,1] → linear and back (IEC 61966-2-1), in double so the tables round once.
double srgb_to_linear(double s) noexcept { return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4); }
long code_of(float c) noexcept {
  const double s = c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(double(c), 1.0 / 2.4) - 0.055;
  return std::lround(s * 255.0);
}

// bound[k], k < 255: the least float whose code by the formula is above k, so a value's code is
// the number of bounds at or below it; bound[255] = +inf pads the search. Nudging the inverse to
// the exact float keeps the search equal to the formula at every float, not only between codes.
std::array<float, 256> make_bounds() noexcept {
  std::array<float, 256> t{};
  for (int k = 0; k < 255; ++k) {
    float b = static_cast<float>(srgb_to_linear((k + 0.5) / 255.0));
    while (code_of(b) > k) b = std::nextafter(b, 0.0f);
    while (code_of(b) <= k) b = std::nextafter(b, 2.0f);
    t[size_t(k)] = b;
  }
  t[255] = std::numeric_limits<float>::infinity();
  return t;
}

std::array<float, 256> make_decode() noexcept {
  std::array<float, 256> t{};
  for (int k = 0; k < 256; ++k) t[size_t(k)] = static_cast<float>(srgb_to_linear(k / 255.0));
  return t;
}

}  // namespace

// Built before main; nothing runs encode or decode during static initialisation.
const std::array<float, 256> core::detail::srgb_bound = make_bounds();
const std::array<float, 256> core::detail::srgb_decode = make_decode();

namespace {

// The code of each bucket's lower end, linear [i/kBuckets, (i+1)/kBuckets): the steepest part of the
// curve (12.92·255 codes per unit near 0) crosses fewer than one code boundary per bucket, so a
// value's code is its bucket's plus at most one. A binary search over srgb_bound alone is 8 dependent
// loads per channel, which doubled the paint brush's cost per texel.
constexpr int kBuckets = 4096;
static_assert(12.92 * 255 < kBuckets && kBuckets == 4096);
// One entry per bucket plus linear 1.0 itself, so that the clamped value needs no test.
std::array<uint8_t, kBuckets + 1> make_buckets() noexcept {
  std::array<uint8_t, kBuckets + 1> t{};
  unsigned c = 0;
  for (int i = 0; i <= kBuckets; ++i) {
    const float x = float(i) / kBuckets;
    while (core::detail::srgb_bound[c] <= x) ++c;
    t[size_t(i)] = static_cast<uint8_t>(c);
  }
  return t;
}

}  // namespace

const std::array<uint8_t, kBuckets + 1> core::detail::srgb_bucket = make_buckets();

}  // namespace hdm
