// SPDX-License-Identifier: MIT
#include "studio_script.h"

#include <hdm/core/error.h>
#include <hdm/io/read_file.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace hdm::studio {
namespace {

double seconds_now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

Eigen::Vector2d point(const nlohmann::json& j, const std::string& where) {
  if (!j.is_array() || j.size() != 2 || !j[0].is_number() || !j[1].is_number())
    throw InvalidInput(where + ": a point is [x, y] in window coordinates [0,1]");
  const Eigen::Vector2d p(j[0].get<double>(), j[1].get<double>());
  if (!(p.minCoeff() >= 0 && p.maxCoeff() <= 1)) throw InvalidInput(where + ": point outside the window [0,1]²");
  return p;
}

float number(const nlohmann::json& j, const std::string& where, double lo, double hi) {
  if (!j.is_number()) throw InvalidInput(where + " must be a number");
  const double v = j.get<double>();
  if (!(v >= lo && v <= hi))
    throw InvalidInput(where + " = " + std::to_string(v) + " is outside [" + std::to_string(lo) + ", " +
                       std::to_string(hi) + "]");
  return static_cast<float>(v);
}

// Linear interpolation along a polyline by arc length, u in [0,1].
Eigen::Vector2d along(const std::vector<Eigen::Vector2d>& p, double u) {
  double total = 0;
  for (size_t k = 1; k < p.size(); ++k) total += (p[k] - p[k - 1]).norm();
  double left = u * total;
  for (size_t k = 1; k < p.size(); ++k) {
    const double len = (p[k] - p[k - 1]).norm();
    if (left <= len && len > 0) return p[k - 1] + (left / len) * (p[k] - p[k - 1]);
    left -= len;
  }
  return p.back();
}

}  // namespace

void apply_tool_json(const nlohmann::json& j, ToolSettings& t, const std::string& where) {
  for (const auto& [key, v] : j.items()) {
    const std::string at = where + ": \"" + key + "\"";
    if (key == "tool") {
      if (!v.is_string()) throw InvalidInput(at + " must be a tool name");
      t.brush = parse_tool(v.get<std::string>());
    } else if (key == "radius_mm")
      t.radius_mm = number(v, at, 0.05, 100);
    else if (key == "strength")
      t.strength = number(v, at, 0, 1);
    else if (key == "depth_mm")
      t.depth_mm = number(v, at, 0, 50);
    else if (key == "height_mm")
      t.height_mm = number(v, at, 0, 50);
    else if (key == "resilience_mm")
      t.resilience_mm = number(v, at, 0, 50);
    else if (key == "value")
      t.value = number(v, at, -1e6, 1e6);
    else if (key == "stiffness")
      t.stiffness = number(v, at, 1, 1e5);
    else if (key == "friction")
      t.friction = number(v, at, 0, 10);
    else if (key == "field") {
      if (!v.is_string()) throw InvalidInput(at + " must be a field name");
      t.field = static_cast<int>(parse_brush_field(v.get<std::string>()));
    } else if (key == "colour") {
      if (!v.is_array() || v.size() != 3) throw InvalidInput(at + " must be [r, g, b] (linear, in [0,1])");
      for (int c = 0; c < 3; ++c) t.colour[c] = number(v[c], at, 0, 1);
    } else if (key != "do") {
      throw InvalidInput(at +
                         " is not a tool setting (tool, radius_mm, strength, depth_mm, height_mm, "
                         "resilience_mm, field, colour, value, stiffness, friction)");
    }
  }
}

std::vector<ScriptStep> read_studio_script(const std::string& path) {
  const std::string bytes = read_file(path);
  nlohmann::json root;
  try {
    root = nlohmann::json::parse(bytes.begin(), bytes.end());
  } catch (const nlohmann::json::exception& e) {
    throw InvalidInput(path + ": not valid JSON (" + e.what() + ")");
  }
  if (!root.is_object() || !root.contains("steps") || !root["steps"].is_array())
    throw InvalidInput(path + ": a studio script is {\"steps\": [...]}");
  std::vector<ScriptStep> steps;
  ToolSettings check;
  for (size_t k = 0; k < root["steps"].size(); ++k) {
    const nlohmann::json& j = root["steps"][k];
    const std::string where = path + ": step " + std::to_string(k + 1);
    if (!j.is_object() || !j.contains("do") || !j["do"].is_string())
      throw InvalidInput(where + ": each step is an object with \"do\": the action");
    const std::string action = j["do"].get<std::string>();
    ScriptStep s;
    if (action == "tool") {
      s.kind = ScriptStep::Tool;
      apply_tool_json(j, check, where);  // refuse a bad setting now, not in the middle of a session
      s.tool = j;
    } else if (action == "cursor") {
      s.kind = ScriptStep::Cursor;
      s.points = {point(j.value("at", nlohmann::json()), where)};
    } else if (action == "stroke") {
      s.kind = ScriptStep::Stroke;
      const nlohmann::json pts = j.value("points", nlohmann::json());
      if (!pts.is_array() || pts.size() < 2)
        throw InvalidInput(where + ": a stroke has \"points\": two or more [x, y]");
      for (const auto& p : pts) s.points.push_back(point(p, where));
      s.frames = static_cast<int>(number(j.value("frames", nlohmann::json(30)), where + ": \"frames\"", 1, 1e6));
    } else if (action == "wait") {
      s.kind = ScriptStep::Wait;
      s.frames = static_cast<int>(number(j.value("frames", nlohmann::json()), where + ": \"frames\"", 0, 1e7));
    } else if (action == "settle")
      s.kind = ScriptStep::Settle;
    else if (action == "undo")
      s.kind = ScriptStep::Undo;
    else if (action == "redo")
      s.kind = ScriptStep::Redo;
    else if (action == "screenshot" || action == "save" || action == "export") {
      s.kind = action == "screenshot" ? ScriptStep::Screenshot
               : action == "save"     ? ScriptStep::Save
                                      : ScriptStep::Export;
      if (!j.contains("path") || !j["path"].is_string())
        throw InvalidInput(where + ": \"" + action + "\" needs \"path\"");
      s.path = j["path"].get<std::string>();
      s.ui = j.value("ui", false);
      s.footprint = j.value("footprint", false);
    } else if (action == "probe") {
      s.kind = ScriptStep::Probe;
      if (!j.contains("name") || !j["name"].is_string()) throw InvalidInput(where + ": \"probe\" needs \"name\"");
      s.path = j["name"].get<std::string>();
    } else if (action == "turn") {
      s.kind = ScriptStep::Turn;
      s.yaw_deg = number(j.value("yaw", nlohmann::json(0)), where + ": \"yaw\"", -360, 360);
      s.pitch_deg = number(j.value("pitch", nlohmann::json(0)), where + ": \"pitch\"", -360, 360);
    } else if (action == "device_end") {
      s.kind = ScriptStep::DeviceEnd;
    } else if (action == "view") {
      s.kind = ScriptStep::View;
      s.azimuth_deg = number(j.value("azimuth", nlohmann::json(0)), where + ": \"azimuth\"", -360, 360);
      s.elevation_deg = number(j.value("elevation", nlohmann::json(15)), where + ": \"elevation\"", -89, 89);
      s.zoom = number(j.value("zoom", nlohmann::json(1)), where + ": \"zoom\"", 0.2, 200);
      s.on_tool = j.value("on_tool", false);
    } else {
      throw InvalidInput(
          where + ": unknown action \"" + action +
          "\" (tool, cursor, stroke, wait, settle, screenshot, undo, redo, save, export, view, probe, turn, "
          "device_end)");
    }
    steps.push_back(std::move(s));
  }
  return steps;
}

bool ScriptPlayer::waited(bool done, double limit_s, const char* what) {
  if (settle_started_ < 0) settle_started_ = seconds_now();
  if (!done && seconds_now() - settle_started_ > limit_s)
    throw InvalidInput("script: step " + std::to_string(next_ + 1) + ": " + what + " in " +
                       std::to_string(static_cast<int>(limit_s)) + " s");
  if (done) settle_started_ = -1;
  return done;
}

bool ScriptPlayer::frame(ScriptHost& host) {
  while (next_ < steps_.size()) {
    const ScriptStep& s = steps_[next_];
    switch (s.kind) {
      case ScriptStep::Tool:
        apply_tool_json(s.tool, host.tool_settings(), "script");
        break;
      case ScriptStep::Cursor:
        host.set_cursor(s.points[0].x(), s.points[0].y(), false);
        break;
      case ScriptStep::Screenshot:
        host.screenshot(s.path, s.ui, s.footprint);
        break;
      case ScriptStep::Undo:
        host.undo();
        break;
      case ScriptStep::Redo:
        host.redo();
        break;
      case ScriptStep::Save:
        host.save(s.path);
        break;
      case ScriptStep::Export:
        host.export_model(s.path);
        break;
      case ScriptStep::View:
        host.view(s.azimuth_deg, s.elevation_deg, s.zoom, s.on_tool);
        break;
      case ScriptStep::Probe:
        host.probe(s.path);
        break;
      case ScriptStep::Turn:
        host.turn_tool(s.yaw_deg, s.pitch_deg);
        break;
      case ScriptStep::DeviceEnd:
        if (!waited(host.device_ended(), 60, "the device did not end")) return true;
        break;
      case ScriptStep::Stroke: {
        // Frames 0..frames with the button held along the path, then one frame to release it.
        if (frame_in_step_ <= s.frames) {
          const Eigen::Vector2d p = along(s.points, double(frame_in_step_) / s.frames);
          host.set_cursor(p.x(), p.y(), true);
          ++frame_in_step_;
          return true;
        }
        host.set_cursor(s.points.back().x(), s.points.back().y(), false);
        frame_in_step_ = 0;
        ++next_;
        return true;
      }
      case ScriptStep::Wait:
        if (frame_in_step_ < s.frames) {
          ++frame_in_step_;
          return true;
        }
        frame_in_step_ = 0;
        break;
      case ScriptStep::Settle:
        if (!waited(host.settled(), 20, "the session did not settle")) return true;
        break;
    }
    ++next_;
  }
  return false;
}

}  // namespace hdm::studio
