// SPDX-License-Identifier: MIT
#pragma once
// Internal to hdm::io: a bounds-checked cursor over the bytes of a text file (OBJ, OFF, ASCII
// PLY) that knows its line number, so every reader's error says "<file>:<line>: <reason>".
// It never reads past the end of the buffer, needs no terminating NUL, and each call moves forward
// (or fails), so a loop over it is bounded by the file's size.

#include <hdm/core/error.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstdint>
#include <string>
#include <string_view>
#include <system_error>

namespace hdm::io::detail {

class TextCursor {
 public:
  TextCursor(std::string_view text, const std::string& name) : text_(text), name_(name) {}

  bool at_end() const { return pos_ >= text_.size(); }
  /// 1-based line of the cursor.
  int64_t line() const { return line_; }
  size_t position() const { return pos_; }
  size_t bytes_left() const { return text_.size() - pos_; }
  const std::string& name() const { return name_; }

  /// Skips spaces, tabs, '\r', '\v' and '\f' on the current line.
  void skip_blanks() {
    while (pos_ < text_.size() && is_blank(text_[pos_])) ++pos_;
  }
  /// True when only blanks or a '#' comment are left on the current line.
  bool at_line_end() {
    skip_blanks();
    return pos_ >= text_.size() || text_[pos_] == '\n' || text_[pos_] == '#';
  }
  /// Moves past the end of the current line; false at the end of the text.
  bool next_line() {
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    if (pos_ >= text_.size()) return false;
    ++pos_;
    ++line_;
    return true;
  }
  /// Moves to the first line at or after the cursor that holds something other than blanks and a
  /// '#' comment; false when there is none.
  bool next_content_line() {
    while (at_line_end())
      if (!next_line()) return false;
    return true;
  }
  /// Skips blanks and line ends (and, with @p comments, '#' comments) up to the next token.
  void skip_space(bool comments) {
    while (pos_ < text_.size()) {
      const char c = text_[pos_];
      if (c == '\n') {
        ++line_;
        ++pos_;
      } else if (is_blank(c)) {
        ++pos_;
      } else if (comments && c == '#') {
        while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
      } else {
        break;
      }
    }
  }
  /// The next run of non-space characters on the current line (empty at the line's end); with
  /// @p comments, a '#' ends the token ("0.5#red" gives "0.5") and the line.
  std::string_view token(bool comments = false) {
    skip_blanks();
    const size_t start = pos_;
    if (comments && pos_ < text_.size() && text_[pos_] == '#') return text_.substr(start, 0);
    while (pos_ < text_.size() && !is_blank(text_[pos_]) && text_[pos_] != '\n' && !(comments && text_[pos_] == '#'))
      ++pos_;
    return text_.substr(start, pos_ - start);
  }
  /// Leaves the cursor just before @p token (which token() returned) so it is read again.
  void unread(std::string_view token) { pos_ = static_cast<size_t>(token.data() - text_.data()); }

  [[noreturn]] void fail(const std::string& reason) const {
    throw IoError(name_ + ":" + std::to_string(line_) + ": " + reason);
  }

 private:
  static bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

  std::string_view text_;
  const std::string& name_;
  size_t pos_ = 0;
  int64_t line_ = 1;
};

/// Parses all of @p token as a decimal floating-point number (a leading '+' is allowed; "nan" and
/// "inf" parse, the readers refuse them later with the vertex they belong to).
inline bool parse_double(std::string_view token, double& value) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-') token.remove_prefix(1);
  const char* end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), end, value);
  if (ec == std::errc::result_out_of_range && ptr == end) {
    // Too large or too small for a double: strtod gives the C library's ±HUGE_VAL or (sub)normal.
    const std::string copy(token);
    value = std::strtod(copy.c_str(), nullptr);
    return true;
  }
  return ec == std::errc() && ptr == end && !token.empty();
}

/// Parses all of @p token as a decimal integer (a leading '+' is allowed) that fits int64.
inline bool parse_int(std::string_view token, int64_t& value) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-') token.remove_prefix(1);
  const char* end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), end, value);
  return ec == std::errc() && ptr == end && !token.empty();
}

/// "12,345,678": counts in messages are easier to read with thousands separators.
inline std::string with_commas(uint64_t n) {
  std::string digits = std::to_string(n), out;
  for (size_t k = 0; k < digits.size(); ++k) {
    if (k > 0 && (digits.size() - k) % 3 == 0) out += ',';
    out += digits[k];
  }
  return out;
}

/// An integer-valued double read from a file, for an error message (no conversion overflow).
inline std::string integer_text(double v) {
  if (std::abs(v) < 1e18) return std::to_string(static_cast<long long>(v));
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

/// A token for an error message: at most 24 characters, non-printable bytes as '?'.
inline std::string quoted(std::string_view token) {
  std::string out = "\"";
  for (size_t k = 0; k < token.size() && k < 24; ++k) out += (token[k] >= 0x20 && token[k] < 0x7f) ? token[k] : '?';
  if (token.size() > 24) out += "...";
  return out + "\"";
}

}  // namespace hdm::io::detail
