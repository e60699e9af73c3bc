// SPDX-License-Identifier: MIT
#pragma once
// Internal to hdm::io: text files written in UTF-16 (as assimp's box_UTF16BE.obj), read by
// transcoding them to UTF-8 (text_encoding.cpp).

#include <optional>
#include <string>
#include <string_view>

namespace hdm::io::detail {

/// @brief The UTF-8 text of @p bytes when they are UTF-16, else nullopt.
///
/// UTF-16 is recognised by its byte-order mark (FE FF big-endian, FF FE little-endian), or, without
/// one, by its first 64 code units: at least three quarters of them ASCII characters, all with
/// their zero byte on the same side (a UTF-8 or ASCII text file holds no zero bytes). The mark is
/// dropped; surrogate pairs become 4-byte sequences, an unpaired surrogate U+FFFD.
/// @throws IoError "<name>: ..." when UTF-16 text has an odd number of bytes (truncated).
/// @note O(bytes.size()); allocates at most 1.5 bytes per input byte.
/// @see The Unicode Standard, section 3.9 (UTF-16 and UTF-8 encoding forms); RFC 2781.
std::optional<std::string> utf16_to_utf8(std::string_view bytes, const std::string& name);

/// @p text without a leading UTF-8 byte-order mark (EF BB BF).
std::string_view without_utf8_bom(std::string_view text);

}  // namespace hdm::io::detail
