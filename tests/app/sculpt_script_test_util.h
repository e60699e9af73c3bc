// SPDX-License-Identifier: MIT
#pragma once
// Helpers of the sculpting-script parser's tests (sculpt_script_test.cpp, the keys read, and
// sculpt_script_refusal_test.cpp, the refusals).
#include "sculpt_script.h"

#include <hdm/core/error.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace hdm::app::test {

using json = nlohmann::json;

// The name every error message starts with: not a path, so that it cannot be confused with one
// the parser made up.
inline const std::string kName = "brush.json";

inline Script parse(const json& j) { return parse_script(j.dump(), kName); }

// A stroke that is valid with every optional key absent.
inline json plain_stroke() { return {{"from", {0.5, 0.5, 1.0}}, {"to", {0.5, 0.6, 1.0}}}; }

// A script of the given strokes. (A vector, because a braced json list of one element is that
// element, not an array of it.)
inline json with_strokes(const std::vector<json>& strokes) { return {{"strokes", json(strokes)}}; }
// A script whose "strokes" is @p value, array or not.
inline json with_strokes_value(const json& value) { return {{"strokes", value}}; }

// The message of the InvalidInput that parsing @p text throws ("" and a failure when none is).
inline std::string refusal(const std::string& text) {
  try {
    parse_script(text, kName);
  } catch (const InvalidInput& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "threw something other than InvalidInput: " << e.what();
    return e.what();
  }
  ADD_FAILURE() << "accepted: " << text;
  return "";
}
inline std::string refusal(const json& j) { return refusal(j.dump()); }

inline size_t occurrences(const std::string& s, const std::string& part) {
  size_t n = 0;
  for (size_t at = s.find(part); at != std::string::npos; at = s.find(part, at + part.size())) ++n;
  return n;
}

}  // namespace hdm::app::test
