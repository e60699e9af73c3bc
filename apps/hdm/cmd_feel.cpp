// SPDX-License-Identifier: MIT
// hdm feel MODEL.hdm --scenario NAME | --replay CSV: a simulated hand (or a recorded trajectory)
// drives the proxy (or the paper's penalty force); the run is scored against the exact input mesh.
#include "commands.h"
#include "output_guard.h"

#include <hdm/core/write_file_atomic.h>

#include <hdm/core/error.h>
#include <hdm/harness/scenarios.h>
#include <hdm/harness/tool_scenarios.h>
#include <hdm/io/hdm_file.h>
#include <hdm/io/read_mesh.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>

namespace hdm::app {
namespace {

struct FeelArgs {
  std::string model, scenario, mode = "proxy", input, trace, replay, solver = "newton";
  double rate = 1000, stiffness = 1000, damping = 1, damping_force = 0.2, max_force = 3.3, speed = 0.1, press = 1.0;
  double radius = 0;  // the ball's radius (--mode sphere) [model units]; 0: 1 % of the diagonal
  bool friction = false, json = false;
  InputLimit limit;
};

// The input named in model.source: as written, else next to the model file.
std::string find_input(const SlabModel& m, const FeelArgs& a) {
  if (!a.input.empty()) return a.input;
  namespace fs = std::filesystem;
  const fs::path src(m.source);
  if (fs::exists(src)) return src.string();
  const fs::path next = fs::path(a.model).parent_path() / src.filename();
  if (fs::exists(next)) return next.string();
  throw InvalidInput(a.model + ": input mesh '" + m.source + "' not found; pass it with --input");
}

void write_trace(const std::string& path, const ScenarioReport& r) {
  std::string out;
  // force_first_n: the force along the direction of the run's first contact force, so that a force
  // that flips (pop-through) shows as negative.
  out +=
      "time_s,device_x_m,device_y_m,device_z_m,force_x_n,force_y_n,force_z_n,force_n,force_first_n,depth_mm,"
      "status,slab,proxy_x_m,proxy_y_m,proxy_z_m,normal_x,normal_y,normal_z\n";
  Vec3 first = Vec3::Zero();
  for (const ScenarioTraceRow& t : r.trace)
    if (t.force.norm() > 0.05) {
      first = t.force.normalized();
      break;
    }
  char line[256];
  for (const ScenarioTraceRow& t : r.trace) {
    std::snprintf(line, sizeof line,
                  "%.5f,%.6f,%.6f,%.6f,%.5f,%.5f,%.5f,%.5f,%.5f,%.4f,%d,%d,%.6f,%.6f,%.6f,%.4f,%.4f,%.4f\n", t.t,
                  t.device.x(), t.device.y(), t.device.z(), t.force.x(), t.force.y(), t.force.z(), t.force.norm(),
                  t.force.dot(first), t.depth_mm, t.status, t.slab, t.proxy.x(), t.proxy.y(), t.proxy.z(), t.normal.x(),
                  t.normal.y(), t.normal.z());
    out += line;
  }
  write_file_atomic(path, out.data(), out.size());
}

// The renderer's parameters the options give: solver, stiffness, damping and its ramp, force limit.
ProxyParams proxy_params(const FeelArgs& a) {
  ProxyParams p;
  p.solver = parse_alpha_solver(a.solver);
  p.force.stiffness = a.stiffness;
  p.force.damping = a.damping;
  p.damping_force_n = a.damping_force;
  p.force.max_force = a.max_force;
  return p;
}

// The tool scenario's report as `hdm feel --json` prints it.
nlohmann::json tool_report_json(const ToolScenarioReport& r) {
  return {{"scenario", r.scenario},
          {"rate_hz", r.rate_hz},
          {"mode", r.scenario == "shaft_edge" || r.scenario == "drill_layers" ? "rigid" : "sphere"},
          {"radius", r.radius},
          {"ticks", r.ticks},
          {"contact_ticks", r.contact_ticks},
          {"max_penetration_pct_r", r.max_penetration_pct_r},
          {"rest_height_error_pct_r", r.rest_height_error_pct_r},
          {"entered", r.entered},
          {"max_force_step_pct", r.max_force_step_pct},
          {"max_direction_step_deg", r.max_direction_step_deg},
          {"normal_error_p95_deg", r.normal_error_p95_deg},
          {"normal_error_max_deg", r.normal_error_max_deg},
          {"max_force_n", r.max_force_n},
          {"energy_ratio", r.energy_ratio},
          {"mean_contact_force_n", r.mean_contact_force_n},
          {"head_contacts", r.head_contacts},
          {"shaft_contacts", r.shaft_contacts},
          {"torque_error_pct", r.torque_error_pct},
          {"torque_sense_ok", r.torque_sense_ok},
          {"torque_nm", {r.tool_torque.x(), r.tool_torque.y(), r.tool_torque.z()}},
          {"force_n", {r.tool_force.x(), r.tool_force.y(), r.tool_force.z()}},
          {"tool_tip", {r.tool_tip.x(), r.tool_tip.y(), r.tool_tip.z()}},
          {"tool_axis", {r.tool_axis.x(), r.tool_axis.y(), r.tool_axis.z()}},
          {"enamel_rate_mm3_per_ns", r.enamel_rate},
          {"dentin_rate_mm3_per_ns", r.dentin_rate},
          {"enamel_archard_mm3_per_ns", r.enamel_archard},
          {"dentin_archard_mm3_per_ns", r.dentin_archard},
          {"ratio_error_pct", r.ratio_error_pct},
          {"note", r.note}};
}

// The tool scenario's report as `hdm feel` prints it.
void print_tool_report(const ToolScenarioReport& r) {
  if (r.scenario == "drill_layers") {
    std::printf("feel drill_layers: rigid burr drilling, %.0f Hz (%s)\n", r.rate_hz, r.note.c_str());
    std::printf("  enamel              %.5f mm3/(N s), Archard %.5f (%.3f)\n", r.enamel_rate, r.enamel_archard,
                r.enamel_rate / r.enamel_archard);
    std::printf("  dentin              %.5f mm3/(N s), Archard %.5f (%.3f)\n", r.dentin_rate, r.dentin_archard,
                r.dentin_rate / r.dentin_archard);
    std::printf("  dentin / enamel     %.3f against the hardness ratio %.3f: %.2f %% off\n",
                r.enamel_rate > 0 ? r.dentin_rate / r.enamel_rate : 0.0, 300.0 / 55.0, r.ratio_error_pct);
    return;
  }
  if (r.scenario == "shaft_edge") {
    std::printf("feel shaft_edge: rigid burr, %.0f Hz (%s)\n", r.rate_hz, r.note.c_str());
    std::printf("  contacts            %d on the head, %d on the shaft\n", r.head_contacts, r.shaft_contacts);
    std::printf("  tip height error    %.3f %% of r\n", r.rest_height_error_pct_r);
    std::printf("  torque              (%.5f, %.5f, %.5f) N m, %.2f %% from the lever-arm reference, sense %s\n",
                r.tool_torque.x(), r.tool_torque.y(), r.tool_torque.z(), r.torque_error_pct,
                r.torque_sense_ok ? "right" : "wrong");
    std::printf("  force               (%.4f, %.4f, %.4f) N\n", r.tool_force.x(), r.tool_force.y(), r.tool_force.z());
    return;
  }
  std::printf("feel %s: sphere proxy, %.0f Hz (%s)\n", r.scenario.c_str(), r.rate_hz, r.note.c_str());
  std::printf("  ticks               %lld (%lld in contact)\n", (long long)r.ticks, (long long)r.contact_ticks);
  std::printf("  penetration         max %.3f %% of r (exact input)%s\n", r.max_penetration_pct_r,
              r.entered ? "; the ball entered the slot" : "");
  if (r.scenario == "slot") std::printf("  rest height error   %.3f %% of r\n", r.rest_height_error_pct_r);
  std::printf("  max force step      %.2f %% of max force, direction %.2f deg per tick\n", r.max_force_step_pct,
              r.max_direction_step_deg);
  if (r.scenario != "slot")  // in the slot two rims hold the ball: no single contact normal
    std::printf("  normal error        p95 %.2f deg, max %.2f deg (against the exact input's contact normal)\n",
                r.normal_error_p95_deg, r.normal_error_max_deg);
  std::printf("  force               max %.3f N, mean in contact %.3f N\n", r.max_force_n, r.mean_contact_force_n);
  if (r.scenario != "drill_layers") std::printf("  energy ratio        %.3f (returned / absorbed)\n", r.energy_ratio);
}

// The tool scenarios (slot, roll_edge): their own analytic block, no model file.
void run_tool_feel(const FeelArgs& a) {
  if (!a.model.empty() || !a.replay.empty() || !a.trace.empty() || !a.input.empty() || a.radius != 0)
    throw InvalidInput("--scenario " + a.scenario +
                       ": a tool scenario builds its own block and tool; give no model, --input, --replay, --trace "
                       "or --radius");
  ToolScenarioOptions o;
  o.scenario = parse_tool_scenario(a.scenario);
  o.rate_hz = a.rate;
  o.proxy = proxy_params(a);
  o.press_force_n = a.press;
  o.speed_m_s = a.speed;
  const ToolScenarioReport r = run_tool_scenario(o);
  if (a.json)
    std::printf("%s\n", tool_report_json(r).dump(2).c_str());
  else
    print_tool_report(r);
}

void run_feel(const FeelArgs& a) {
  if (is_tool_scenario(a.scenario)) return run_tool_feel(a);
  if (a.model.empty())
    if (a.model.empty())  // a usage error (exit 2), as when CLI11 finds a required argument missing
      throw CLI::RequiredError(
          "model (.hdm): needed by every scenario but the tool scenarios slot, roll_edge, shaft_edge and drill_layers");
  const RenderMode mode = parse_render_mode(a.mode);
  if (mode == RenderMode::RigidTool)
    throw InvalidInput("--mode " + a.mode +
                       ": scored by the tool scenarios shaft_edge and drill_layers only (the scenarios on a model "
                       "score a point or a ball against the exact input); use proxy, penalty or sphere");
  check_outputs({a.trace}, {a.model, a.input, a.replay}, "--trace");
  const SlabModel model = load_model(a.model, {a.limit.bytes()});
  const SlabLocator locator(model);
  const std::string input = find_input(model, a);
  const ExactMeshQuery reference(read_mesh(input, {a.limit.bytes()}));
  if (a.scenario.empty() == a.replay.empty())
    throw InvalidInput("hdm feel: give either --scenario NAME or --replay CSV (exactly one)");
  ScenarioOptions o;
  if (!a.scenario.empty()) o.scenario = parse_scenario(a.scenario);
  o.mode = mode;
  o.ball_radius = a.radius;
  o.proxy = proxy_params(a);
  o.rate_hz = a.rate;
  o.friction = a.friction;
  o.speed_m_s = a.speed;
  o.press_force_n = a.press;
  o.keep_trace = !a.trace.empty();
  ScenarioReport r;
  if (!a.replay.empty()) {
    ReplayDevice device(a.replay, {}, a.limit.bytes());  // throws naming the file and line on bad rows
    r = run_replay(model, locator, reference, device, o);
  } else {
    r = run_scenario(model, locator, reference, o);
  }
  if (!a.trace.empty()) write_trace(a.trace, r);
  const nlohmann::json j = {{"model", a.model},
                            {"input", input},
                            {"scenario", r.scenario},
                            {"rate_hz", r.rate_hz},
                            {"mode", r.mode},
                            {"ball_radius", r.ball_radius},
                            {"solver", a.solver},
                            {"replay", a.replay},
                            {"friction", a.friction},
                            {"ticks", r.ticks},
                            {"contact_ticks", r.contact_ticks},
                            {"pop_throughs", r.pop_throughs},
                            {"max_force_step_pct", r.max_force_step_pct},
                            {"reference_force_step_pct", r.reference_force_step_pct},
                            {"reference_facet_force_step_pct", r.reference_facet_force_step_pct},
                            {"normal_error_p95_deg", r.normal_error_p95_deg},
                            {"normal_error_smooth_p95_deg", r.normal_error_smooth_p95_deg},
                            {"normal_floor_p95_deg", r.normal_floor_p95_deg},
                            {"energy_ratio", r.energy_ratio},
                            {"stable_stiffness_n_per_m", r.stable_stiffness_n_per_m},
                            {"passive_stiffness_n_per_m", r.passive_stiffness_n_per_m},
                            {"max_force_n", r.max_force_n},
                            {"mean_contact_force_n", r.mean_contact_force_n},
                            {"force_cv", r.force_cv},
                            {"max_penetration_mm", r.max_penetration_mm},
                            {"proxy_surface_error_max", r.proxy_surface_error_max},
                            {"slab_crossings", r.slab_crossings},
                            {"bad_input_ticks", r.bad_input_ticks},
                            {"tick_ns", {{"median", r.tick_ns_median}, {"p99", r.tick_ns_p99}, {"max", r.tick_ns_max}}},
                            {"note", r.note},
                            {"trace", a.trace}};
  if (a.json) {
    std::printf("%s\n", j.dump(2).c_str());
    return;
  }
  std::printf("feel %s: %s, %s, %.0f Hz (%s)\n", a.model.c_str(), r.scenario.c_str(), r.mode.c_str(), r.rate_hz,
              r.note.c_str());
  if (r.ball_radius > 0) std::printf("  ball radius         %.4g model units\n", r.ball_radius);
  std::printf("  ticks               %lld (%lld in contact)\n", (long long)r.ticks, (long long)r.contact_ticks);
  std::printf("  pop-throughs        %d\n", r.pop_throughs);
  std::printf(
      "  max force step      %.2f %% of max force (handle still); exact input's own %.2f %% (smooth), "
      "%.2f %% (facets)\n",
      r.max_force_step_pct, r.reference_force_step_pct, r.reference_facet_force_step_pct);
  std::printf(
      "  normal error p95    %.2f deg (face), %.2f deg (smooth input normal); input's own face vs smooth %.2f deg\n",
      r.normal_error_p95_deg, r.normal_error_smooth_p95_deg, r.normal_floor_p95_deg);
  std::printf("  energy ratio        %.3f (returned / absorbed)\n", r.energy_ratio);
  std::printf("  force               max %.3f N, mean in contact %.3f N, cv %.3f\n", r.max_force_n,
              r.mean_contact_force_n, r.force_cv);
  std::printf("  max penetration     %.3f mm\n", r.max_penetration_mm);
  std::printf("  slab crossings      %lld\n", (long long)r.slab_crossings);
  if (r.scenario == "stiff")
    std::printf("  stiffness           %.0f N/m highest stable, %.0f N/m highest passive\n", r.stable_stiffness_n_per_m,
                r.passive_stiffness_n_per_m);
  else
    std::printf("  stiffness           %.0f N/m\n", r.stable_stiffness_n_per_m);
  std::printf("  tick compute        median %.0f ns, p99 %.0f ns, max %.0f ns\n", r.tick_ns_median, r.tick_ns_p99,
              r.tick_ns_max);
}

}  // namespace

void add_feel_command(CLI::App& app) {
  auto a = std::make_shared<FeelArgs>();
  CLI::App* cmd = app.add_subcommand("feel", "Score haptic rendering on a scripted scenario with a simulated hand");
  cmd->add_option("model", a->model,
                  "slab model (.hdm); none for the tool scenarios slot, roll_edge, shaft_edge and drill_layers");
  cmd->add_option(
      "--scenario", a->scenario,
      "slide, press, thin, edges or stiff (on the model); slot, roll_edge (the sphere proxy), shaft_edge or "
      "drill_layers (the rigid burr) on a block built in code");
  cmd->add_option("--replay", a->replay,
                  "play this recorded trajectory (CSV with time_s,device_x_m,device_y_m,device_z_m, e.g. from --trace) "
                  "instead of a scenario");
  cmd->add_option("--solver", a->solver, "alpha-plane root finder: newton (default) or bisection (the paper's)");
  cmd->add_option("--rate", a->rate, "servo rate [Hz]")->check(CLI::Range(100.0, 1e6));
  cmd->add_option("--mode", a->mode,
                  "proxy (god-object, default), penalty (the paper's SCP) or sphere (a ball of --radius held outside "
                  "the surface)");
  cmd->add_option("--radius", a->radius,
                  "--mode sphere: the ball's radius [model units] (default 0: 1 % of the model's diagonal)")
      ->check(CLI::Range(0.0, 1e300));
  cmd->add_option("--input", a->input, "input mesh for the exact reference (default: model.source)");
  cmd->add_option("--stiffness", a->stiffness, "rendered stiffness [N/m] (default 1000)");
  cmd->add_option("--damping", a->damping, "normal damping [N·s/m] (default 1)");
  cmd->add_option("--damping-force", a->damping_force,
                  "spring force [N] over which the damping ramps in from 0 at contact (default 0.2; 0: full at once)")
      ->check(CLI::Range(0.0, 100.0));
  cmd->add_option("--max-force", a->max_force, "device force limit [N] (default 3.3)");
  cmd->add_option("--speed", a->speed, "slide/edges hand speed [m/s] (default 0.1)");
  cmd->add_option("--press", a->press, "slide/edges hand force [N] (default 1)");
  cmd->add_flag("--friction", a->friction, "use the model's friction fields (default: frictionless)");
  cmd->add_option("--trace", a->trace, "write one CSV row per tick here");
  cmd->add_flag("--json", a->json, "print the report as one JSON object");
  add_input_limit(cmd, a->limit);
  cmd->callback([a] { run_feel(*a); });
}

}  // namespace hdm::app
