// SPDX-License-Identifier: MIT
// UTF-16 text (with or without a byte-order mark, either byte order) to UTF-8, for the OBJ reader.
#include "text_encoding.h"
#include "text_cursor.h"

#include <hdm/core/error.h>

#include <algorithm>
#include <cstdint>

namespace hdm::io::detail {
namespace {

enum class Order { None, Big, Little };

Order utf16_order(std::string_view b) {
  if (b.size() < 2) return Order::None;
  const auto u0 = static_cast<uint8_t>(b[0]), u1 = static_cast<uint8_t>(b[1]);
  if (u0 == 0xFE && u1 == 0xFF) return Order::Big;
  if (u0 == 0xFF && u1 == 0xFE) return Order::Little;
  // No mark: ASCII characters as code units, their zero byte first (big) or second (little).
  const size_t units = std::min<size_t>(b.size() / 2, 64);
  size_t big = 0, little = 0;
  for (size_t i = 0; i < units; ++i) {
    const auto hi = static_cast<uint8_t>(b[2 * i]), lo = static_cast<uint8_t>(b[2 * i + 1]);
    big += hi == 0 && lo != 0 && lo < 0x80;
    little += lo == 0 && hi != 0 && hi < 0x80;
  }
  if (4 * big >= 3 * units && little == 0) return Order::Big;
  if (4 * little >= 3 * units && big == 0) return Order::Little;
  return Order::None;
}

void append_utf8(std::string& out, uint32_t c) {
  if (c < 0x80) {
    out += static_cast<char>(c);
  } else if (c < 0x800) {
    out += static_cast<char>(0xC0 | (c >> 6));
    out += static_cast<char>(0x80 | (c & 0x3F));
  } else if (c < 0x10000) {
    out += static_cast<char>(0xE0 | (c >> 12));
    out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (c & 0x3F));
  } else {
    out += static_cast<char>(0xF0 | (c >> 18));
    out += static_cast<char>(0x80 | ((c >> 12) & 0x3F));
    out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (c & 0x3F));
  }
}

}  // namespace

std::optional<std::string> utf16_to_utf8(std::string_view b, const std::string& name) {
  const Order order = utf16_order(b);
  if (order == Order::None) return std::nullopt;
  if (b.size() % 2 != 0)
    throw IoError(name + ": UTF-16 text of an odd number of bytes (" + with_commas(b.size()) + "): truncated");
  const bool big = order == Order::Big;
  auto unit = [&](size_t i) {
    const auto a = static_cast<uint8_t>(b[2 * i]), c = static_cast<uint8_t>(b[2 * i + 1]);
    return static_cast<uint32_t>(big ? (a << 8) | c : (c << 8) | a);
  };
  const size_t n = b.size() / 2;
  std::string out;
  out.reserve(n + n / 2);
  for (size_t i = unit(0) == 0xFEFF ? 1 : 0; i < n; ++i) {
    const uint32_t u = unit(i);
    if (u >= 0xD800 && u < 0xDC00 && i + 1 < n && unit(i + 1) >= 0xDC00 && unit(i + 1) < 0xE000) {
      append_utf8(out, 0x10000 + ((u - 0xD800) << 10) + (unit(i + 1) - 0xDC00));
      ++i;
    } else {
      append_utf8(out, u >= 0xD800 && u < 0xE000 ? 0xFFFD : u);
    }
  }
  return out;
}

std::string_view without_utf8_bom(std::string_view text) {
  return text.substr(0, 3) == "\xEF\xBB\xBF" ? text.substr(3) : text;
}

}  // namespace hdm::io::detail
