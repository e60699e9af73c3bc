// SPDX-License-Identifier: MIT
#include "sculpt_script.h"

#include <hdm/core/error.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>

namespace hdm::app {
namespace {

Vec3 vec3(const nlohmann::json& j, const std::string& where) {
  if (!j.is_array() || j.size() != 3) throw InvalidInput(where + ": expected an array of three numbers");
  Vec3 v(j[0].get<double>(), j[1].get<double>(), j[2].get<double>());
  if (!v.allFinite()) throw InvalidInput(where + ": not finite");
  return v;
}

Tool tool_named(const std::string& s, const std::string& where) {
  if (s == "probe") return Tool::Probe;
  if (s == "carve") return Tool::Carve;
  if (s == "add") return Tool::Add;
  if (s == "paint") return Tool::Paint;
  if (s == "smooth") return Tool::Smooth;
  if (s == "flatten") return Tool::Flatten;
  throw InvalidInput(where + ": unknown tool '" + s + "' (probe, carve, add, paint, smooth, flatten)");
}

// The brush fields of a stroke (strength, falloff, paint field and value, pressure).
void read_brush_fields(const nlohmann::json& js, const std::string& where, Stroke& st) {
  st.strength = js.value("strength", st.strength);
  st.pressure_force_n = js.value("pressure_force_n", st.pressure_force_n);
  const bool boolean = st.tool == Tool::Carve || st.tool == Tool::Add;
  try {
    st.falloff = parse_falloff(js.value("falloff", boolean ? "constant" : "linear"));
    st.field = parse_brush_field(js.value("field", "colour"));
  } catch (const InvalidInput& e) {
    throw InvalidInput(where + ": " + e.what());
  }
  st.value = js.value("value", st.value);
  if (!(st.strength >= 0 && st.strength <= 1) || !(st.pressure_force_n > 0) || !std::isfinite(st.value))
    throw InvalidInput(where + ": strength must be in [0, 1], pressure_force_n > 0 and value finite");
}

// The under-layer: {"thickness_mm", "colour", "stiffness", "friction_static", "friction_dynamic", "roughness"}.
ScriptLayer read_layer(const nlohmann::json& j, const std::string& where) {
  ScriptLayer l;
  l.present = true;
  l.thickness_mm = j.value("thickness_mm", l.thickness_mm);
  if (j.contains("colour")) l.material.colour = vec3(j["colour"], where + ".colour").cast<float>();
  l.material.stiffness_scale = j.value("stiffness", l.material.stiffness_scale);
  l.material.friction_static = j.value("friction_static", l.material.friction_static);
  l.material.friction_dynamic = j.value("friction_dynamic", l.material.friction_dynamic);
  l.material.roughness = j.value("roughness", l.material.roughness);
  const UnderLayer& m = l.material;
  if (!(l.thickness_mm >= 0) || !(m.stiffness_scale >= 0 && m.stiffness_scale <= 1) || !(m.friction_static >= 0) ||
      !(m.friction_dynamic >= 0) || !(m.roughness >= 0 && m.roughness <= 1))
    throw InvalidInput(where + ": thickness_mm and frictions must be >= 0, stiffness and roughness in [0, 1]");
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

Script read_script(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InvalidInput(path + ": cannot open script");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const std::exception& e) {
    throw InvalidInput(path + ": not valid JSON: " + e.what());
  }
  Script s;
  try {
    s.name = j.value("name", path);
    s.workspace_m = j.value("workspace_m", 0.16);
    s.hand_stiffness = j.value("hand_stiffness_n_per_m", s.hand_stiffness);
    s.hand_damping = j.value("hand_damping_ns_per_m", s.hand_damping);
    s.force.stiffness = j.value("stiffness_n_per_m", s.force.stiffness);
    s.force.damping = j.value("damping_ns_per_m", s.force.damping);
    s.force.max_force = j.value("max_force_n", s.force.max_force);
    if (j.contains("under_layer")) s.layer = read_layer(j["under_layer"], path + ": under_layer");
    if (j.contains("surface")) {  // {"colour": [r, g, b], "roughness": x}
      const auto& js = j["surface"];
      if (js.contains("colour")) {
        s.surface.has_colour = true;
        s.surface.colour = vec3(js["colour"], path + ": surface.colour").cast<float>();
      }
      if (js.contains("roughness")) {
        s.surface.has_roughness = true;
        s.surface.roughness = js["roughness"].get<float>();
        if (!(s.surface.roughness >= 0 && s.surface.roughness <= 1))
          throw InvalidInput(path + ": surface.roughness must be in [0, 1]");
      }
    }
    if (!j.contains("strokes") || !j["strokes"].is_array() || j["strokes"].empty())
      throw InvalidInput(path + ": 'strokes' must be a non-empty array");
    for (size_t k = 0; k < j["strokes"].size(); ++k) {
      const auto& js = j["strokes"][k];
      const std::string where = path + ": strokes[" + std::to_string(k) + "]";
      Stroke st;
      if (js.is_object() && (js.contains("undo") || js.contains("redo"))) {  // {"undo": n} / {"redo": n}
        st.tool = js.contains("undo") ? Tool::Undo : Tool::Redo;
        st.count = js.value(js.contains("undo") ? "undo" : "redo", 1);
        if (st.count < 1 || st.count > 1000) throw InvalidInput(where + ": undo / redo count must be in [1, 1000]");
        s.strokes.push_back(st);
        continue;
      }
      st.tool = tool_named(js.value("tool", "probe"), where + ".tool");
      st.from = vec3(js.at("from"), where + ".from");
      st.to = vec3(js.at("to"), where + ".to");
      st.radius_mm = js.value("radius_mm", st.radius_mm);
      st.depth_mm = js.value("depth_mm", st.depth_mm);
      st.speed_mm_s = js.value("speed_mm_s", st.speed_mm_s);
      st.resilience_mm = js.value("resilience_mm", st.resilience_mm);
      st.height_mm = js.value("height_mm", st.height_mm);
      if (js.contains("colour")) st.colour = vec3(js["colour"], where + ".colour").cast<float>();
      read_brush_fields(js, where, st);
      if (!(st.radius_mm > 0) || !(st.speed_mm_s > 0) || !(st.depth_mm >= 0))
        throw InvalidInput(where + ": radius_mm and speed_mm_s must be > 0, depth_mm >= 0");
      s.strokes.push_back(st);
    }
  } catch (const nlohmann::json::exception& e) {
    throw InvalidInput(path + ": " + e.what());
  }
  if (!(s.workspace_m > 0) || !(s.force.stiffness > 0) || !(s.force.max_force > 0) || !(s.hand_stiffness > 0) ||
      !(s.hand_damping >= 0))
    throw InvalidInput(path + ": workspace_m, stiffness_n_per_m, max_force_n and hand_stiffness_n_per_m must be > 0, "
                              "hand_damping_ns_per_m >= 0");
  return s;
}

Brush stroke_brush(const Stroke& s, double mm) {
  Brush b;
  switch (s.tool) {
    case Tool::Carve: b.tool = BrushTool::Carve; break;
    case Tool::Add: b.tool = BrushTool::Add; break;
    case Tool::Smooth: b.tool = BrushTool::Smooth; break;
    case Tool::Flatten: b.tool = BrushTool::Flatten; break;
    default: b.tool = BrushTool::Paint; break;
  }
  b.radius = s.radius_mm * mm;
  b.strength = s.strength;
  b.falloff = s.falloff;
  b.resilience = s.resilience_mm * mm;
  b.height = s.height_mm * mm;
  b.field = s.field;
  b.colour = s.colour;
  b.value = s.field == BrushField::LayerThickness ? static_cast<float>(s.value * mm) : s.value;
  b.pressure_force_n = s.pressure_force_n;
  return b;
}

Trajectory build_trajectory(const Script& script, const SlabModel& m, const SlabLocator& loc, const Workspace& ws,
                            double rate_hz) {
  Aabb box;
  for (const Vec3f& p : m.positions) box.extend(p.cast<double>());
  Trajectory tr;
  const double dt = 1.0 / rate_hz;
  auto move = [&](const Vec3& a, const Vec3& b, double seconds, Tool tool, int stroke) {
    const int n = std::max(1, static_cast<int>(std::ceil(seconds / dt)));
    for (int k = 1; k <= n; ++k) {
      tr.position.push_back(a + (b - a) * (double(k) / n));
      tr.tool.push_back(tool);
      tr.stroke.push_back(static_cast<int16_t>(stroke));
    }
  };
  Vec3 here = ws.to_device(box.max + 0.1 * (box.max - box.min));  // start above the model
  tr.position.push_back(here);
  tr.tool.push_back(Tool::None);
  tr.stroke.push_back(-1);
  for (size_t k = 0; k < script.strokes.size(); ++k) {
    const Stroke& st = script.strokes[k];
    if (st.tool == Tool::Undo || st.tool == Tool::Redo) {  // a pause above the model, the command at its start
      for (int c = 0; c < st.count; ++c) {
        tr.commands.emplace_back(static_cast<int64_t>(tr.position.size()), static_cast<int16_t>(k));
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
        move(above, path[0], 0.3, st.tool, static_cast<int>(k));                        // press in
      }
      retract = above;
    }
    for (size_t i = 1; i < path.size(); ++i)
      move(path[i - 1], path[i], (path[i] - path[i - 1]).norm() / (st.speed_mm_s / 1000), st.tool, static_cast<int>(k));
    move(path.back(), retract, 0.2, Tool::None, -1);  // lift off 5 mm along the normal
    here = retract;
  }
  return tr;
}

}  // namespace hdm::app
