// SPDX-License-Identifier: MIT
// The sculpting-script parser's refusals (apps/hdm/sculpt_script.h): every one is an InvalidInput
// naming the file, the key and the reason, checked against the documented ranges and types.
#include "sculpt_script_test_util.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace hdm::app {
namespace {

using namespace hdm::app::test;
using ::testing::HasSubstr;
using ::testing::Not;

// A ranged number key: where it lives and its documented closed range.
struct RangedKey {
  enum Place { Top, Layer, Surface, Stroke } place;
  std::string key;
  double lo, hi;
};

const std::vector<RangedKey>& ranged_keys() {
  static const std::vector<RangedKey> keys = {
      {RangedKey::Top, "workspace_m", 0.001, 10},
      {RangedKey::Top, "stiffness_n_per_m", 0.001, 1e7},
      {RangedKey::Top, "hand_stiffness_n_per_m", 0.001, 1e7},
      {RangedKey::Top, "damping_ns_per_m", 0, 1e5},
      {RangedKey::Top, "hand_damping_ns_per_m", 0, 1e5},
      {RangedKey::Top, "max_force_n", 0.001, 1e4},
      {RangedKey::Surface, "roughness", 0, 1},
      {RangedKey::Layer, "thickness_mm", 0, 1e4},
      {RangedKey::Layer, "stiffness", 0, 1},
      {RangedKey::Layer, "roughness", 0, 1},
      {RangedKey::Layer, "friction_static", 0, 10},
      {RangedKey::Layer, "friction_dynamic", 0, 10},
      {RangedKey::Stroke, "radius_mm", 0.001, 1e4},
      {RangedKey::Stroke, "depth_mm", 0, 1e4},
      {RangedKey::Stroke, "resilience_mm", 0, 1e4},
      {RangedKey::Stroke, "height_mm", 0, 1e4},
      {RangedKey::Stroke, "speed_mm_s", 0.01, 1e5},
      {RangedKey::Stroke, "strength", 0, 1},
      {RangedKey::Stroke, "pressure_force_n", 0.001, 1e4},
      {RangedKey::Stroke, "value", -1e4, 1e4},
  };
  return keys;
}

// A script with @p k set to @p x; the ranged stroke is the second one, so that its index shows.
json script_with(const RangedKey& k, double x) {
  json j = with_strokes({plain_stroke(), plain_stroke()});
  switch (k.place) {
    case RangedKey::Top:
      j[k.key] = x;
      break;
    case RangedKey::Layer:
      j["under_layer"] = {{k.key, x}};
      break;
    case RangedKey::Surface:
      j["surface"] = {{k.key, x}};
      break;
    case RangedKey::Stroke:
      j["strokes"][1][k.key] = x;
      break;
  }
  return j;
}

// How the message names the key: "<name>: key", "<name>: under_layer.key", "<name>: strokes[1].key".
std::string key_path(const RangedKey& k) {
  switch (k.place) {
    case RangedKey::Top:
      return kName + ": " + k.key;
    case RangedKey::Layer:
      return kName + ": under_layer." + k.key;
    case RangedKey::Surface:
      return kName + ": surface." + k.key;
    case RangedKey::Stroke:
      break;
  }
  return kName + ": strokes[1]." + k.key;
}

TEST(SculptScript, RangeEndsAreAccepted) {
  for (const RangedKey& k : ranged_keys())
    for (double x : {k.lo, k.hi}) EXPECT_NO_THROW(parse(script_with(k, x))) << k.key << " = " << x;
  for (int n : {1, 1000}) {
    EXPECT_NO_THROW(parse(with_strokes({{{"undo", n}}}))) << n;
    EXPECT_NO_THROW(parse(with_strokes({{{"redo", n}}}))) << n;
  }
  EXPECT_NO_THROW(parse(with_strokes({{{"from", {-1, -1, -1}}, {"to", {2, 2, 2}}}})));
}

TEST(SculptScript, EveryRangeErrorNamesFileKeyAndReason) {
  for (const RangedKey& k : ranged_keys()) {
    // Just outside each end: a relative step, so that it shows at every magnitude.
    const double below = k.lo - std::max(std::abs(k.lo), 1.0) * 1e-3;
    const double above = k.hi + std::max(std::abs(k.hi), 1.0) * 1e-3;
    for (double x : {below, above}) {
      const std::string m = refusal(script_with(k, x));
      EXPECT_THAT(m, HasSubstr(key_path(k))) << k.key << " = " << x;
      EXPECT_THAT(m, HasSubstr("must lie in [")) << k.key << " = " << x;
      EXPECT_EQ(occurrences(m, kName), 1u) << m;
    }
  }
  for (const char* key : {"undo", "redo"})
    for (int n : {0, -2, 1001}) {
      const std::string m = refusal(with_strokes({plain_stroke(), {{key, n}}}));
      EXPECT_THAT(m, HasSubstr(kName + ": strokes[1]." + key)) << n;
      EXPECT_THAT(m, HasSubstr("must lie in [")) << n;
    }
}

TEST(SculptScript, VectorOutOfRangeNamesFileKeyAndReason) {
  // Stroke ends in [-1, 2] (normalised box coordinates), colours in [0, 1].
  for (const char* key : {"from", "to"})
    for (double x : {-1.01, 2.01}) {
      json j = with_strokes({plain_stroke(), plain_stroke()});
      j["strokes"][1][key] = {0.5, x, 0.5};
      const std::string m = refusal(j);
      EXPECT_THAT(m, HasSubstr(kName + ": strokes[1]." + key)) << x;
      EXPECT_THAT(m, HasSubstr("each number must lie in")) << x;
    }
  for (double x : {-0.01, 1.01}) {
    json j = with_strokes({plain_stroke(), plain_stroke()});
    j["strokes"][1]["colour"] = {0.5, 0.5, x};
    std::string m = refusal(j);
    EXPECT_THAT(m, HasSubstr(kName + ": strokes[1].colour"));
    EXPECT_THAT(m, HasSubstr("each number must lie in"));

    j = with_strokes({plain_stroke()});
    j["surface"] = {{"colour", {x, 0.5, 0.5}}};
    m = refusal(j);
    EXPECT_THAT(m, HasSubstr(kName + ": surface.colour"));
    EXPECT_THAT(m, HasSubstr("each number must lie in"));

    j = with_strokes({plain_stroke()});
    j["under_layer"] = {{"colour", {0.5, x, 0.5}}};
    m = refusal(j);
    EXPECT_THAT(m, HasSubstr(kName + ": under_layer.colour"));
    EXPECT_THAT(m, HasSubstr("each number must lie in"));
  }
}

TEST(SculptScript, UnknownKeyNamesTheNearestKnownOne) {
  // A misspelt key would otherwise leave its default in force without a word.
  json j = with_strokes({plain_stroke()});
  j["workspace_mm"] = 0.2;
  std::string m = refusal(j);
  EXPECT_THAT(m, HasSubstr(kName + ": unknown key 'workspace_mm'"));
  EXPECT_THAT(m, HasSubstr("did you mean 'workspace_m'?"));

  j = with_strokes({plain_stroke(), plain_stroke()});
  j["strokes"][1]["radius_m"] = 3;
  m = refusal(j);
  EXPECT_THAT(m, HasSubstr(kName + ": strokes[1]: unknown key 'radius_m'"));
  EXPECT_THAT(m, HasSubstr("did you mean 'radius_mm'?"));

  j = with_strokes({plain_stroke()});
  j["strokes"][0]["falof"] = "linear";
  m = refusal(j);
  EXPECT_THAT(m, HasSubstr("unknown key 'falof'"));
  EXPECT_THAT(m, HasSubstr("did you mean 'falloff'?"));

  j = with_strokes({plain_stroke()});
  j["under_layer"] = {{"thickness", 1.0}};
  m = refusal(j);
  EXPECT_THAT(m, HasSubstr(kName + ": under_layer: unknown key 'thickness'"));
  EXPECT_THAT(m, HasSubstr("did you mean 'thickness_mm'?"));

  j = with_strokes({plain_stroke()});
  j["surface"] = {{"color", {0.5, 0.5, 0.5}}};
  m = refusal(j);
  EXPECT_THAT(m, HasSubstr(kName + ": surface: unknown key 'color'"));
  EXPECT_THAT(m, HasSubstr("did you mean 'colour'?"));

  // An undo step holds its count and nothing else.
  m = refusal(with_strokes({{{"undo", 1}, {"tool", "carve"}}}));
  EXPECT_THAT(m, HasSubstr(kName + ": strokes[0]: unknown key 'tool'"));
  EXPECT_THAT(m, HasSubstr("did you mean 'undo'?"));
}

TEST(SculptScript, MalformedJsonNamesTheFile) {
  for (const std::string text : {"", "{", "{\"strokes\": [}", "not json", "{\"strokes\": []} trailing"}) {
    const std::string m = refusal(text);
    EXPECT_THAT(m, HasSubstr(kName + ": not valid JSON")) << text;
  }
  // Valid JSON that is not an object.
  for (const std::string text : {"[]", "3", "\"strokes\"", "null"}) {
    const std::string m = refusal(text);
    EXPECT_THAT(m, HasSubstr(kName + ": expected a JSON object with 'strokes'")) << text;
  }
}

TEST(SculptScript, StrokesMustBeANonEmptyArrayOfBoundedSize) {
  for (const json& strokes : {json::array(), json(3), json::object(), json("carve")}) {
    const std::string m = refusal(with_strokes_value(strokes));
    EXPECT_THAT(m, HasSubstr(kName + ": 'strokes' must be a non-empty array")) << strokes.dump();
  }
  EXPECT_THAT(refusal(json{{"workspace_m", 0.2}}), HasSubstr(kName + ": 'strokes' must be a non-empty array"));

  // Trajectory numbers the steps in 16 bits: one step past the limit is refused before any is read.
  json many = json::array();
  for (size_t k = 0; k <= max_script_strokes; ++k) many.push_back({{"undo", 1}});
  const std::string m = refusal(with_strokes_value(many));
  EXPECT_THAT(m, HasSubstr(kName + ": " + std::to_string(max_script_strokes + 1) + " strokes"));
  EXPECT_THAT(m, HasSubstr("more than the " + std::to_string(max_script_strokes)));
  many.erase(many.begin());
  EXPECT_EQ(parse(with_strokes_value(many)).strokes.size(), max_script_strokes);
}

TEST(SculptScript, WrongTypeNamesFileAndKey) {
  struct Case {
    json script;
    std::string expected;
  };
  auto stroke_with = [](const char* key, const json& v) {
    json j = with_strokes({plain_stroke()});
    j["strokes"][0][key] = v;
    return j;
  };
  auto top_with = [](const char* key, const json& v) {
    json j = with_strokes({plain_stroke()});
    j[key] = v;
    return j;
  };
  const std::vector<Case> cases = {
      {top_with("name", 5), kName + ": name: expected a string"},
      {top_with("workspace_m", "0.2"), kName + ": workspace_m: expected a number"},
      {top_with("max_force_n", true), kName + ": max_force_n: expected a number"},
      {top_with("under_layer", 1.5), kName + ": under_layer: expected an object"},
      {top_with("under_layer", {{"stiffness", "soft"}}), kName + ": under_layer.stiffness: expected a number"},
      {top_with("under_layer", {{"colour", "red"}}),
       kName + ": under_layer.colour: expected an array of three numbers"},
      {top_with("surface", {0.5, 0.5, 0.5}), kName + ": surface: expected an object"},
      {top_with("surface", {{"roughness", "matte"}}), kName + ": surface.roughness: expected a number"},
      {top_with("surface", {{"colour", {0.5, 0.5}}}), kName + ": surface.colour: expected an array of three numbers"},
      {with_strokes({3}), kName + ": strokes[0]: expected an object"},
      {stroke_with("tool", 1), kName + ": strokes[0].tool: expected a string"},
      {stroke_with("from", {0.5, 0.5}), kName + ": strokes[0].from: expected an array of three numbers"},
      {stroke_with("to", {0.5, "0.5", 0.5}), kName + ": strokes[0].to: expected an array of three numbers"},
      {stroke_with("to", {0.5, 0.5, 0.5, 0.5}), kName + ": strokes[0].to: expected an array of three numbers"},
      {stroke_with("radius_mm", "3"), kName + ": strokes[0].radius_mm: expected a number"},
      {stroke_with("speed_mm_s", nullptr), kName + ": strokes[0].speed_mm_s: expected a number"},
      {stroke_with("strength", json::array()), kName + ": strokes[0].strength: expected a number"},
      {stroke_with("colour", 0.5), kName + ": strokes[0].colour: expected an array of three numbers"},
      {stroke_with("falloff", 1), kName + ": strokes[0].falloff: expected a string"},
      {stroke_with("field", false), kName + ": strokes[0].field: expected a string"},
      {stroke_with("value", "1"), kName + ": strokes[0].value: expected a number"},
      {with_strokes({{{"undo", 1.5}}}), kName + ": strokes[0].undo: expected a whole number"},
      {with_strokes({{{"redo", "2"}}}), kName + ": strokes[0].redo: expected a whole number"},
  };
  for (const Case& c : cases) {
    const std::string m = refusal(c.script);
    EXPECT_THAT(m, HasSubstr(c.expected)) << c.script.dump();
    // The file is named once, not once per layer of the parser the error passed through.
    EXPECT_EQ(occurrences(m, kName), 1u) << m;
  }
}

TEST(SculptScript, UnknownNamesAndMissingEndsAreRefused) {
  json j = with_strokes({plain_stroke()});
  j["strokes"][0]["tool"] = "chisel";
  std::string m = refusal(j);
  EXPECT_THAT(m, HasSubstr(kName + ": strokes[0].tool: unknown tool 'chisel'"));

  j = with_strokes({plain_stroke()});
  j["strokes"][0]["falloff"] = "cubic";
  m = refusal(j);
  EXPECT_THAT(m, HasSubstr(kName + ": strokes[0]"));
  EXPECT_THAT(m, HasSubstr("falloff 'cubic'"));

  j = with_strokes({plain_stroke()});
  j["strokes"][0]["field"] = "height";
  m = refusal(j);
  EXPECT_THAT(m, HasSubstr(kName + ": strokes[0]"));
  EXPECT_THAT(m, HasSubstr("field 'height'"));

  for (const char* end : {"from", "to"}) {
    j = with_strokes({plain_stroke()});
    j["strokes"][0].erase(end);
    EXPECT_THAT(refusal(j), HasSubstr(kName + ": strokes[0]: needs 'from' and 'to'")) << end;
  }
}

TEST(SculptScript, ReadScriptNamesTheFile) {
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) / "hdm_sculpt_script_test";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "script.json").string();
  const std::string text = with_strokes({plain_stroke()}).dump();
  { std::ofstream(path, std::ios::binary) << text; }
  const Script s = read_script(path);
  EXPECT_EQ(s.name, path);
  EXPECT_EQ(s.strokes.size(), 1u);

  // Size limit and missing file: read_file's IoError comes back as InvalidInput naming the file.
  try {
    read_script(path, text.size() - 1);
    ADD_FAILURE() << "a script over the size limit was read";
  } catch (const InvalidInput& e) {
    EXPECT_THAT(e.what(), HasSubstr(path + ": "));
    EXPECT_THAT(e.what(), HasSubstr("more than the input limit"));
  }
  const std::string missing = (dir / "missing.json").string();
  try {
    read_script(missing);
    ADD_FAILURE() << "a missing script was read";
  } catch (const InvalidInput& e) {
    EXPECT_THAT(e.what(), HasSubstr(missing + ": no such file"));
  }
  // Parse errors name the path too.
  { std::ofstream(path, std::ios::binary) << "{\"strokes\": ["; }
  try {
    read_script(path);
    ADD_FAILURE() << "a truncated script was read";
  } catch (const InvalidInput& e) {
    EXPECT_THAT(e.what(), HasSubstr(path + ": not valid JSON"));
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace hdm::app
