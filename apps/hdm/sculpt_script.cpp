// SPDX-License-Identifier: MIT
#include "sculpt_script.h"

#include <hdm/core/error.h>
#include <hdm/edit/brush_registry.h>
#include <hdm/io/read_file.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <string_view>

namespace hdm::app {
namespace {

// Stroke ends may lie up to one box size outside the normalised box [0,1]³: enough for any stroke
// that reaches the surface, and it bounds the number of points a stroke is sampled at.
constexpr double min_coordinate = -1, max_coordinate = 2;

// Edit distance between two keys (a misspelt key is refused naming the nearest known one).
size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// Refuses a key of the object @p j that is not in @p known: a misspelt key would otherwise be
// ignored and its default used without a word.
void check_keys(const nlohmann::json& j, std::initializer_list<std::string_view> known, const std::string& where) {
  for (const auto& item : j.items()) {
    const std::string& key = item.key();
    if (std::find(known.begin(), known.end(), key) != known.end()) continue;
    std::string_view nearest = *known.begin();
    for (std::string_view k : known)
      if (edit_distance(key, k) < edit_distance(key, nearest)) nearest = k;
    throw InvalidInput(where + ": unknown key '" + key + "' (did you mean '" + std::string(nearest) + "'?)");
  }
}

Vec3 vec3(const nlohmann::json& j, const std::string& where, double lo, double hi) {
  if (!j.is_array() || j.size() != 3 || !j[0].is_number() || !j[1].is_number() || !j[2].is_number())
    throw InvalidInput(where + ": expected an array of three numbers");
  Vec3 v(j[0].get<double>(), j[1].get<double>(), j[2].get<double>());
  if (!v.allFinite() || v.minCoeff() < lo || v.maxCoeff() > hi)
    throw InvalidInput(where + ": each number must lie in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return v;
}

// A number field with its default, refused unless finite and in [lo, hi]; @p prefix names the
// object ("<file>: " or "<file>: strokes[3].").
double number(const nlohmann::json& j, const char* key, double fallback, double lo, double hi,
              const std::string& prefix) {
  if (!j.contains(key)) return fallback;
  const nlohmann::json& v = j[key];
  if (!v.is_number()) throw InvalidInput(prefix + key + ": expected a number");
  const double x = v.get<double>();
  if (!std::isfinite(x) || x < lo || x > hi)
    throw InvalidInput(prefix + key + " = " + v.dump() + ": must lie in [" + nlohmann::json(lo).dump() + ", " +
                       nlohmann::json(hi).dump() + "]");
  return x;
}

// "probe" or a registered brush's name.
void read_tool(const std::string& s, const std::string& where, Stroke& st) {
  if (s == "probe") {
    st.tool = Tool::Probe;
    return;
  }
  const BrushInfo* b = find_brush(s);
  if (!b) throw InvalidInput(where + ": unknown tool '" + s + "' (probe, " + brush_names() + ")");
  st.tool = Tool::Brush;
  st.brush = b->tool;
}

// A string field with its default; @p prefix names the object.
std::string text(const nlohmann::json& j, const char* key, const std::string& fallback, const std::string& prefix) {
  if (!j.contains(key)) return fallback;
  if (!j[key].is_string()) throw InvalidInput(prefix + key + ": expected a string");
  return j[key].get<std::string>();
}

// The brush fields of a stroke (strength, falloff, paint field and value, pressure, drill's K and rpm).
void read_brush_fields(const nlohmann::json& js, const std::string& where, Stroke& st) {
  const std::string field = where + ".";
  const BrushParamRange& strength = brush_param_range(BrushParam::Strength);
  st.strength = number(js, "strength", st.strength, strength.lo, strength.hi, field);
  st.pressure_force_n = number(js, "pressure_force_n", st.pressure_force_n, 1e-3, 1e4, field);
  st.wear_coefficient = number(js, "wear_coefficient", st.wear_coefficient, 1e-9, 1.0, field);
  st.rpm = number(js, "rpm", st.rpm, 1e-3, 1e6, field);
  // Constant for the boolean brushes (their default: the exact boolean), linear otherwise (a
  // probe's brush is never used). Scripts keep linear where the studio and Python default to
  // smoothstep, so that a script's strokes stay what they were.
  const BrushInfo* info = st.tool == Tool::Brush ? find_brush(st.brush) : nullptr;
  const bool boolean = info && info->falloff == Falloff::Constant;
  // The strings are read outside the try: text() names the file and key itself, and only the
  // name parsers' messages need the stroke prefixed.
  const std::string falloff = text(js, "falloff", boolean ? "constant" : "linear", field);
  const std::string paint_field = text(js, "field", "colour", field);
  try {
    st.falloff = parse_falloff(falloff);
    st.field = parse_brush_field(paint_field);
  } catch (const InvalidInput& e) {
    throw InvalidInput(where + ": " + e.what());
  }
  st.value = static_cast<float>(number(js, "value", st.value, -1e4, 1e4, field));
}

// The under-layer: {"thickness_mm", "colour", "stiffness", "friction_static", "friction_dynamic", "roughness",
// "hardness_hv"}.
ScriptLayer read_layer(const nlohmann::json& j, const std::string& where) {
  if (!j.is_object()) throw InvalidInput(where + ": expected an object");
  check_keys(j,
             {"thickness_mm", "colour", "stiffness", "friction_static", "friction_dynamic", "roughness", "hardness_hv"},
             where);
  ScriptLayer l;
  l.present = true;
  const std::string field = where + ".";
  UnderLayer& m = l.material;
  l.thickness_mm = number(j, "thickness_mm", l.thickness_mm, 0.0, 1e4, field);
  if (j.contains("colour")) m.colour = vec3(j["colour"], where + ".colour", 0.0, 1.0).cast<float>();
  m.stiffness_scale = static_cast<float>(number(j, "stiffness", m.stiffness_scale, 0.0, 1.0, field));
  m.friction_static = static_cast<float>(number(j, "friction_static", m.friction_static, 0.0, 10.0, field));
  m.friction_dynamic = static_cast<float>(number(j, "friction_dynamic", m.friction_dynamic, 0.0, 10.0, field));
  m.roughness = static_cast<float>(number(j, "roughness", m.roughness, 0.0, 1.0, field));
  m.hardness_hv = static_cast<float>(number(j, "hardness_hv", m.hardness_hv, 1.0, 1e5, field));
  return l;
}

// Surface point and normal under normalised box point u: march from the box point towards the box
// centre with the haptic query until the point penetrates, then bisect the crossing.
bool project(const SlabModel& m, const SlabLocator& loc, const Aabb& box, const Vec3& u, Vec3& point, Vec3& normal) {
  const Vec3 start = box.min + u.cwiseProduct(box.max - box.min), centre = 0.5 * (box.min + box.max);
  const int steps = 4000;
  QueryCache cache;
  Vec3 prev = start;
  for (int k = 1; k <= steps; ++k) {
    const Vec3 p = start + (centre - start) * (double(k) / steps);
    if (query(m, loc, p, cache).penetrating()) {
      Vec3 lo = prev, hi = p;
      for (int it = 0; it < 40; ++it) {
        const Vec3 mid = 0.5 * (lo + hi);
        (query(m, loc, mid, cache).penetrating() ? hi : lo) = mid;
      }
      const Contact c = query(m, loc, hi, cache);
      point = c.surface_point;
      normal = c.normal;
      return true;
    }
    prev = p;
  }
  return false;
}

}  // namespace

Script parse_script(std::string_view text, const std::string& path) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text.begin(), text.end());
  } catch (const std::exception& e) {
    throw InvalidInput(path + ": not valid JSON: " + e.what());
  }
  if (!j.is_object()) throw InvalidInput(path + ": expected a JSON object with 'strokes'");
  Script s;
  try {
    if (j.contains("name") && !j["name"].is_string()) throw InvalidInput(path + ": name: expected a string");
    check_keys(j,
               {"name", "workspace_m", "hand_stiffness_n_per_m", "hand_damping_ns_per_m", "stiffness_n_per_m",
                "damping_ns_per_m", "max_force_n", "under_layer", "surface", "strokes"},
               path);
    s.name = j.value("name", path);
    const std::string top = path + ": ";
    s.workspace_m = number(j, "workspace_m", 0.16, 1e-3, 10.0, top);
    s.hand_stiffness = number(j, "hand_stiffness_n_per_m", s.hand_stiffness, 1e-3, 1e7, top);
    s.hand_damping = number(j, "hand_damping_ns_per_m", s.hand_damping, 0.0, 1e5, top);
    s.force.stiffness = number(j, "stiffness_n_per_m", s.force.stiffness, 1e-3, 1e7, top);
    s.force.damping = number(j, "damping_ns_per_m", s.force.damping, 0.0, 1e5, top);
    s.force.max_force = number(j, "max_force_n", s.force.max_force, 1e-3, 1e4, top);
    if (j.contains("under_layer")) s.layer = read_layer(j["under_layer"], path + ": under_layer");
    if (j.contains("surface")) {  // {"colour": [r, g, b], "roughness": x}
      const auto& js = j["surface"];
      if (!js.is_object()) throw InvalidInput(path + ": surface: expected an object");
      check_keys(js, {"colour", "roughness"}, path + ": surface");
      if (js.contains("colour")) {
        s.surface.has_colour = true;
        s.surface.colour = vec3(js["colour"], path + ": surface.colour", 0.0, 1.0).cast<float>();
      }
      if (js.contains("roughness")) {
        s.surface.has_roughness = true;
        s.surface.roughness = static_cast<float>(number(js, "roughness", 1.0, 0.0, 1.0, path + ": surface."));
      }
    }
    if (!j.contains("strokes") || !j["strokes"].is_array() || j["strokes"].empty())
      throw InvalidInput(path + ": 'strokes' must be a non-empty array");
    if (j["strokes"].size() > max_script_strokes)
      throw InvalidInput(path + ": " + std::to_string(j["strokes"].size()) + " strokes, more than the " +
                         std::to_string(max_script_strokes) + " a script may hold");
    for (size_t k = 0; k < j["strokes"].size(); ++k) {
      const auto& js = j["strokes"][k];
      const std::string where = path + ": strokes[" + std::to_string(k) + "]";
      if (!js.is_object()) throw InvalidInput(where + ": expected an object");
      Stroke st;
      if (js.contains("undo") || js.contains("redo")) {  // {"undo": n} / {"redo": n}
        const char* key = js.contains("undo") ? "undo" : "redo";
        check_keys(js, {key}, where);
        st.tool = js.contains("undo") ? Tool::Undo : Tool::Redo;
        if (!js[key].is_number_integer()) throw InvalidInput(where + "." + key + ": expected a whole number");
        st.count = static_cast<int>(number(js, key, 1, 1, 1000, where + "."));
        s.strokes.push_back(st);
        continue;
      }
      check_keys(js,
                 {"tool", "from", "to", "radius_mm", "depth_mm", "speed_mm_s", "resilience_mm", "height_mm", "colour",
                  "strength", "pressure_force_n", "falloff", "field", "value", "wear_coefficient", "rpm"},
                 where);
      if (js.contains("tool") && !js["tool"].is_string()) throw InvalidInput(where + ".tool: expected a string");
      read_tool(js.value("tool", "probe"), where + ".tool", st);
      if (!js.contains("from") || !js.contains("to")) throw InvalidInput(where + ": needs 'from' and 'to'");
      st.from = vec3(js["from"], where + ".from", min_coordinate, max_coordinate);
      st.to = vec3(js["to"], where + ".to", min_coordinate, max_coordinate);
      // Device-space millimetres and mm/s: bounds far outside any device, so a typo cannot ask for
      // years of device time or a brush larger than the workspace.
      const std::string field = where + ".";
      st.radius_mm = number(js, "radius_mm", st.radius_mm, 1e-3, 1e4, field);
      st.depth_mm = number(js, "depth_mm", st.depth_mm, 0.0, 1e4, field);
      st.speed_mm_s = number(js, "speed_mm_s", st.speed_mm_s, 1e-2, 1e5, field);
      st.resilience_mm = number(js, "resilience_mm", st.resilience_mm, 0.0, 1e4, field);
      st.height_mm = number(js, "height_mm", st.height_mm, 0.0, 1e4, field);
      if (js.contains("colour")) st.colour = vec3(js["colour"], where + ".colour", 0.0, 1.0).cast<float>();
      read_brush_fields(js, where, st);
      s.strokes.push_back(st);
    }
  } catch (const nlohmann::json::exception& e) {
    throw InvalidInput(path + ": " + e.what());
  }
  return s;
}

Script read_script(const std::string& path, uint64_t max_bytes) {
  try {
    return parse_script(read_file(path, max_bytes), path);
  } catch (const IoError& e) {
    throw InvalidInput(e.what());  // read_script's documented error type
  }
}
Brush stroke_brush(const Stroke& s, double mm) {
  Brush b;
  b.tool = s.brush;
  b.radius = s.radius_mm * mm;
  b.strength = s.strength;
  b.falloff = s.falloff;
  b.resilience = s.resilience_mm * mm;
  b.height = s.height_mm * mm;
  b.field = s.field;
  b.colour = s.colour;
  b.value = s.field == BrushField::LayerThickness ? static_cast<float>(s.value * mm) : s.value;
  b.pressure_force_n = s.pressure_force_n;
  b.wear_coefficient = s.wear_coefficient;
  b.rpm = s.rpm;
  return b;
}

namespace {

// Walks the script's hand path: calls @p move(a, b, seconds, tool, stroke) for every piece, in
// order (the undo / redo commands through @p command(step)). Once to count the ticks, once to
// record them, so that the memory a script needs is known before it is allocated.
template <class Move, class Command>
void walk_trajectory(const Script& script, const SlabModel& m, const SlabLocator& loc, const Workspace& ws,
                     const Vec3& start, Move&& move, Command&& command) {
  const Aabb box = surface_box(m);
  Vec3 here = start;
  for (size_t k = 0; k < script.strokes.size(); ++k) {
    const Stroke& st = script.strokes[k];
    if (st.tool == Tool::Undo || st.tool == Tool::Redo) {  // a pause above the model, the command at its start
      for (int c = 0; c < st.count; ++c) {
        command(static_cast<int16_t>(k));
        move(here, here, 0.05, Tool::None, -1);
      }
      continue;
    }
    const double len_u = (st.to - st.from).norm();
    // Sample the stroke about every 0.5 mm of device space.
    const double len_mm = len_u * (box.max - box.min).norm() / ws.scale * 1000;
    const int pieces = std::max(2, static_cast<int>(len_mm / 0.5));
    std::vector<Vec3> path;
    Vec3 retract = here;
    for (int i = 0; i <= pieces; ++i) {
      Vec3 p, n;
      const Vec3 u = st.from + (st.to - st.from) * (double(i) / pieces);
      if (!project(m, loc, box, u, p, n))
        throw InvalidInput(script.name + ": stroke " + std::to_string(k) + " point (" + std::to_string(u.x()) + ", " +
                           std::to_string(u.y()) + ", " + std::to_string(u.z()) + ") does not reach the surface");
      path.push_back(ws.to_device(p - n * (st.depth_mm / 1000 * ws.scale)));
      const Vec3 above = ws.to_device(p + n * (5.0 / 1000 * ws.scale));
      if (i == 0) {
        move(here, above, std::max(0.05, (above - here).norm() / 0.2), Tool::None, -1);  // travel at 20 cm/s
        move(above, path[0], 0.3, st.tool, static_cast<int>(k));                         // press in
      }
      retract = above;
    }
    for (size_t i = 1; i < path.size(); ++i)
      move(path[i - 1], path[i], (path[i] - path[i - 1]).norm() / (st.speed_mm_s / 1000), st.tool, static_cast<int>(k));
    move(path.back(), retract, 0.2, Tool::None, -1);  // lift off 5 mm along the normal
    here = retract;
  }
}

Vec3 start_point(const SlabModel& m, const Workspace& ws) {
  const Aabb box = surface_box(m);
  return ws.to_device(box.max + 0.1 * (box.max - box.min));  // start above the model
}

}  // namespace

int64_t count_trajectory_ticks(const Script& script, const SlabModel& m, const SlabLocator& loc, const Workspace& ws,
                               double rate_hz) {
  const double dt = 1.0 / rate_hz;
  int64_t ticks = 1;
  auto move = [&](const Vec3&, const Vec3&, double seconds, Tool, int stroke) {
    const double t = std::ceil(seconds / dt);
    if (!(t <= double(int64_t(max_trajectory_ticks) - ticks)))
      throw InvalidInput(script.name + ": stroke " + std::to_string(stroke) + " takes the device past " +
                         std::to_string(max_trajectory_ticks) + " ticks at " + std::to_string(rate_hz) +
                         " Hz (too slow or too long a script)");
    ticks += std::max<int64_t>(1, static_cast<int64_t>(t));
  };
  walk_trajectory(script, m, loc, ws, start_point(m, ws), move, [](int16_t) {});
  return ticks;
}

Trajectory build_trajectory(const Script& script, const SlabModel& m, const SlabLocator& loc, const Workspace& ws,
                            double rate_hz, int64_t ticks) {
  if (ticks <= 0) ticks = count_trajectory_ticks(script, m, loc, ws, rate_hz);
  Trajectory tr;
  tr.position.reserve(static_cast<size_t>(ticks));
  tr.tool.reserve(static_cast<size_t>(ticks));
  tr.stroke.reserve(static_cast<size_t>(ticks));
  const double dt = 1.0 / rate_hz;
  auto move = [&](const Vec3& a, const Vec3& b, double seconds, Tool tool, int stroke) {
    const int n = std::max(1, static_cast<int>(std::ceil(seconds / dt)));
    for (int k = 1; k <= n; ++k) {
      tr.position.push_back(a + (b - a) * (double(k) / n));
      tr.tool.push_back(tool);
      tr.stroke.push_back(static_cast<int16_t>(stroke));
    }
  };
  const Vec3 here = start_point(m, ws);
  tr.position.push_back(here);
  tr.tool.push_back(Tool::None);
  tr.stroke.push_back(-1);
  walk_trajectory(script, m, loc, ws, here, move,
                  [&](int16_t step) { tr.commands.emplace_back(static_cast<int64_t>(tr.position.size()), step); });
  return tr;
}

}  // namespace hdm::app
