// SPDX-License-Identifier: MIT
// hdm sculpt MODEL.hdm: the servo loop (hdm::SculptSession) drives a simulated hand along a
// script's strokes in closed loop (the rendered force acts back on the handle); the tool button is
// held during each stroke, and the strokes carve, add, smooth, flatten, paint and drill at haptic rate.
#include "commands.h"
#include "memory_budget.h"
#include "output_guard.h"
#include "sculpt_script.h"

#include <hdm/analysis/edit_fidelity.h>
#include <hdm/core/error.h>
#include <hdm/core/write_file_atomic.h>
#include <hdm/edit/edit_tools.h>
#include <hdm/io/hdm_file.h>
#include <hdm/io/read_mesh.h>
#include <hdm/session/sculpt_session.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <thread>

namespace hdm::app {
namespace {

struct SculptArgs {
  std::string model, script, output, forces, mode = "proxy", solver = "newton", check_against;
  double rate = 1000, edit_rate = 0, budget_us = 25, save_every = 0;
  bool fast = false, every_tick = false, json = false, cpu_time = false;
  InputLimit limit;
  MemoryBudget budget;
};

// One CSV row, recorded in preallocated storage by the servo thread and written afterwards.
struct TickRecord {
  float t;
  Vec3f device;
  int8_t contact;
  float depth_m;
  Vec3f force;
  int8_t tool_on, carried;
  int16_t sweeps;
  std::array<float, 4> orientation;  // the handle's (w, x, y, z), tool → device frame
};

// What the hooks touch, set up before the loop so that the tick never allocates.
struct Run {
  const Trajectory* path;
  const Script* script;
  const std::vector<Brush>* brushes;  // one per script step
  double scale;                       // model units per metre
  size_t next_command = 0;
  int16_t brush_set = -1;
  std::vector<TickRecord> records;
};

void before_tick(void* user, SculptSession& session, const ServoTick& t) noexcept {
  Run& r = *static_cast<Run*>(user);
  const size_t k = std::min<size_t>(static_cast<size_t>(t.tick), r.path->stroke.size() - 1);
  const int16_t stroke = r.path->stroke[k];
  if (stroke >= 0 && stroke != r.brush_set) {  // set before the button goes down on this tick
    session.set_brush((*r.brushes)[static_cast<size_t>(stroke)]);
    r.brush_set = stroke;
  }
  while (r.next_command < r.path->commands.size() && r.path->commands[r.next_command].first <= t.tick) {
    const int16_t step = r.path->commands[r.next_command].second;
    if (r.script->strokes[static_cast<size_t>(step)].tool == Tool::Undo)
      session.undo();
    else
      session.redo();
    ++r.next_command;
  }
}

void after_tick(void* user, const ServoTick& t, const SessionTick& out) noexcept {
  Run& r = *static_cast<Run*>(user);
  if (static_cast<size_t>(t.tick) >= r.records.size()) return;
  const bool contact = out.out.contact.in_shell() && out.out.status != ProxyStatus::Free;
  const Eigen::Quaterniond& q = out.device.orientation;
  r.records[static_cast<size_t>(t.tick)] = {
      static_cast<float>(t.time_s),
      out.device.position.cast<float>(),
      static_cast<int8_t>(contact),
      static_cast<float>(contact ? out.out.contact.depth / r.scale : 0.0),
      out.force.cast<float>(),
      static_cast<int8_t>(out.tool_on),
      static_cast<int8_t>(out.edit_pending),
      static_cast<int16_t>(std::min(out.sweeps, 32767)),
      {static_cast<float>(q.w()), static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z())}};
}

void write_csv(const std::string& path, const std::vector<TickRecord>& rows) {
  std::string out =
      "time_s,device_x_m,device_y_m,device_z_m,contact,depth_m,force_x_n,force_y_n,force_z_n,tool_on,sweeps,"
      "carried,device_qw,device_qx,device_qy,device_qz\n";
  out.reserve(out.size() + rows.size() * 140);  // rows take about 120 bytes, 140 at most: one allocation
  char line[320];
  for (const TickRecord& r : rows) {
    const std::array<float, 4>& q = r.orientation;
    std::snprintf(line, sizeof line, "%.4f,%.6f,%.6f,%.6f,%d,%.7f,%.5f,%.5f,%.5f,%d,%d,%d,%.7f,%.7f,%.7f,%.7f\n", r.t,
                  r.device.x(), r.device.y(), r.device.z(), r.contact, r.depth_m, r.force.x(), r.force.y(), r.force.z(),
                  r.tool_on, r.sweeps, r.carried, q[0], q[1], q[2], q[3]);
    out += line;
  }
  write_file_atomic(path, out.data(), out.size());
}

nlohmann::json stats_json(const LatencyStats& s) { return {{"median", s.median}, {"p99", s.p99}, {"max", s.max}}; }

// The sweeps of the strokes that are applied at the end (undone strokes dropped, redone ones kept).
std::vector<const BrushSweep*> applied_sweeps(const std::vector<EditLogEntry>& log) {
  std::vector<std::vector<const BrushSweep*>> strokes, undone;
  for (const EditLogEntry& e : log) switch (e.kind) {
      case EditLogEntry::Begin:
        strokes.emplace_back();
        undone.clear();
        break;
      case EditLogEntry::Sweep:
        if (!strokes.empty()) strokes.back().push_back(&e.sweep);
        break;
      case EditLogEntry::Undo:
        if (!strokes.empty()) undone.push_back(std::move(strokes.back())), strokes.pop_back();
        break;
      case EditLogEntry::Redo:
        if (!undone.empty()) strokes.push_back(std::move(undone.back())), undone.pop_back();
        break;
      default:
        break;
    }
  std::vector<const BrushSweep*> out;
  for (const auto& s : strokes) out.insert(out.end(), s.begin(), s.end());
  return out;
}

// The carve (or add) sweeps of the session against the exact boolean of the input with them
// (every applied carve and add shapes the exact solid; the band measured is around this tool's).
nlohmann::json check_strokes(const SlabModel& model, const ExactMeshQuery& exact, const std::vector<EditLogEntry>& log,
                             BrushTool tool, double spacing) {
  std::vector<ToolCapsule> tools;
  double radius = 0;
  int64_t measured = 0;
  for (const BrushSweep* sw : applied_sweeps(log))
    if (sw->brush.tool == BrushTool::Carve || sw->brush.tool == BrushTool::Add) {
      const bool mine = sw->brush.tool == tool;
      tools.push_back({sw->from, sw->to, sw->brush.radius, sw->brush.tool == BrushTool::Add, mine});
      if (mine) radius = std::max(radius, sw->brush.radius), ++measured;
    }
  if (measured == 0) return nullptr;
  const EditFidelity f = measure_edit_fidelity(model, exact, tools, radius, spacing);
  return {{"sweeps", measured},
          {"rms_pct", f.rms_pct},
          {"max_pct", f.max_pct},
          {"rms_back_pct", f.rms_back_pct},
          {"max_back_pct", f.max_back_pct},
          {"points", f.points},
          {"back_points", f.back_points}};
}

// The trajectory, the simulated hand's copy of it, the button per tick and the tick records; the
// CSV text and the sweep log when asked for.
void require_sculpt_memory(const SculptArgs& a, int64_t ticks) {
  const int64_t per_tick = sizeof(Vec3) * 2 + sizeof(Tool) + sizeof(int16_t) + sizeof(uint32_t) + sizeof(TickRecord) +
                           (a.forces.empty() ? 0 : 156) + (a.check_against.empty() ? 0 : int64_t(sizeof(EditLogEntry)));
  require_memory(sculpt_peak_bytes(file_bytes(a.model), ticks, per_tick), a.budget, "hdm sculpt " + a.model,
                 std::to_string(ticks) + " ticks of the script at " + std::to_string(int64_t(a.rate)) + " Hz");
}

// The model as the script sets it up: an under-layer, a surface colour and roughness.
void apply_script_surface(SlabModel& model, const Script& script, double mm) {
  if (script.layer.present) set_under_layer(model, script.layer.thickness_mm * mm, script.layer.material);
  if (script.surface.has_colour) model.colour.assign(model.colour.size(), encode_srgb8(script.surface.colour));
  if (script.surface.has_roughness)
    model.roughness.assign(model.roughness.size(), unit_to_unorm8(script.surface.roughness));
}

// The hand holds the tool button down during each editing stroke (not while probing or travelling).
std::vector<uint32_t> tool_buttons(const Trajectory& path) {
  std::vector<uint32_t> buttons(path.position.size(), 0);
  for (size_t k = 0; k < buttons.size(); ++k) {
    buttons[k] = path.tool[k] == Tool::Brush;
  }
  return buttons;
}

SessionOptions session_options(const SculptArgs& a, const Script& script) {
  SessionOptions so;
  so.mode = parse_render_mode(a.mode);
  so.proxy.force = script.force;
  so.rigid.stiffness = script.force.stiffness;  // the rigid tool's coupling: the script's contact
  so.rigid.damping = script.force.damping;
  so.rigid.max_force = script.force.max_force;
  so.proxy.solver = parse_alpha_solver(a.solver);
  so.edit_budget_s = a.budget_us * 1e-6;
  so.edit_every = a.edit_rate > 0 ? std::max<int64_t>(1, std::llround(a.rate / a.edit_rate)) : 1;
  so.publish = a.save_every > 0;  // snapshots only when another thread reads them
  return so;
}

// Runs the servo loop; with --save-every, another thread saves each published epoch meanwhile.
ServoStats run_with_autosave(SculptSession& session, HapticDevice& device, const ServoOptions& opt, Run& run,
                             const SculptArgs& a, int& autosaves, const char*& note) {
  std::atomic<bool> done{false};
  std::atomic<int> saves{0};
  std::thread saver;
  if (a.save_every > 0 && !a.output.empty()) {
    saver = std::thread([&] {
      auto next = std::chrono::steady_clock::now();
      while (!done.load()) {
        next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(
            std::chrono::duration<double>(a.save_every));
        while (!done.load() && std::chrono::steady_clock::now() < next)
          std::this_thread::sleep_for(std::chrono::milliseconds(5));
        if (done.load()) break;
        SlabModel copy;
        {
          SnapshotReader reader(*session.snapshots());
          copy = reader.stored_model();
        }
        save_model(copy, a.output);
        saves.fetch_add(1);
      }
    });
  }
  ServoStats st;
  try {
    st = run_session(session, device, opt, SessionHooks{before_tick, after_tick, &run}, &note);
  } catch (...) {
    done = true;
    if (saver.joinable()) saver.join();
    throw;
  }
  done = true;
  if (saver.joinable()) saver.join();
  autosaves = saves.load();
  return st;
}

// --check-against: the carve and add sweeps measured against the exact boolean on the input.
nlohmann::json check_against_exact(const SculptArgs& a, SculptSession& session,
                                   const std::vector<EditLogEntry>& sweep_log) {
  nlohmann::json check;
  if (a.check_against.empty()) return check;
  const TriangleMesh input = read_mesh(a.check_against, {a.limit.bytes()});
  const ExactMeshQuery exact(input);
  const double spacing = 0.5 * session.editor().scratch().sample_spacing;
  for (BrushTool t : {BrushTool::Carve, BrushTool::Add}) {
    nlohmann::json c = check_strokes(session.model(), exact, sweep_log, t, spacing);
    if (!c.is_null()) check[brush_tool_name(t)] = c;
  }
  return check;
}

nlohmann::json sculpt_report(const SculptArgs& a, const std::string& script_path, const ServoStats& st,
                             SculptSession& session, int64_t edit_every, int autosaves) {
  const SessionStats& ss = session.stats();
  const UndoHistory& h = session.editor().history();
  return {{"model", a.model},
          {"script", script_path},
          {"ticks", st.ticks},
          {"seconds", st.seconds},
          {"rate_hz", st.rate_hz},
          {"target_rate_hz", a.rate},
          {"realtime", !a.fast},
          {"mode", a.mode},
          {"solver", a.solver},
          {"tick_ns", stats_json(st.compute_ns)},
          {"period_ns", stats_json(st.period_ns)},
          {"overruns", st.overruns},
          {"long_ticks", st.long_ticks},
          {"cpu_long_ticks", st.cpu_long_ticks},
          {"tick_cpu_ns", stats_json(st.cpu_ns)},
          {"watchdog_trips", st.watchdog_trips},
          {"contact_ticks", ss.contact_ticks},
          {"edit_every_ticks", edit_every},
          {"edit_budget_us", a.budget_us},
          {"sweeps", ss.sweeps},
          {"changed", ss.changed},
          {"carried_ticks", ss.carried_ticks},
          {"max_edit_ns", ss.max_edit_ns},
          {"publications", ss.publications},
          {"slabs_published", ss.slabs_published},
          {"edits_refused", ss.edits_refused},
          {"publish_deferred", ss.publish_deferred},
          {"autosaves", autosaves},
          {"undo_strokes", h.undo_count()},
          {"undo_records_bytes", h.records_held() * sizeof(UndoRecord)},
          {"output", a.output},
          {"forces", a.forces}};
}

// The report as text, from its JSON form.
void print_sculpt_report(const nlohmann::json& j, const SculptArgs& a) {
  const auto d = [](const nlohmann::json& v) { return v.get<double>(); };
  const auto n = [](const nlohmann::json& v) { return static_cast<long long>(v.get<int64_t>()); };
  std::printf("sculpted %s with %s\n", a.model.c_str(), j["script"].get<std::string>().c_str());
  std::printf(
      "  ticks            %lld in %.2f s: %.0f Hz (target %.0f Hz%s), %lld overruns, %lld ticks longer than a "
      "period\n",
      n(j["ticks"]), d(j["seconds"]), d(j["rate_hz"]), a.rate, a.fast ? ", --fast" : "", n(j["overruns"]),
      n(j["long_ticks"]));
  const nlohmann::json& tick = j["tick_ns"];
  std::printf("  tick compute     median %.0f ns, p99 %.0f ns, max %.0f ns (%s, edits within %.0f µs, publication)\n",
              d(tick["median"]), d(tick["p99"]), d(tick["max"]), a.mode == "sphere" ? "ball" : a.mode.c_str(),
              a.budget_us);
  std::printf("  contact ticks    %lld\n", n(j["contact_ticks"]));
  std::printf(
      "  edits            %lld sweeps (tool position every %lld ticks), %lld samples/texels changed, "
      "%lld ticks carried work over\n",
      n(j["sweeps"]), n(j["edit_every_ticks"]), n(j["changed"]), n(j["carried_ticks"]));
  std::printf("  undo history     %d strokes, %.1f MB of records\n", j["undo_strokes"].get<int>(),
              d(j["undo_records_bytes"]) / 1e6);
  if (a.cpu_time) {
    const nlohmann::json& cpu = j["tick_cpu_ns"];
    std::printf(
        "  tick CPU time    median %.0f ns, p99 %.0f ns, max %.0f ns; %lld ticks computed longer than a period\n",
        d(cpu["median"]), d(cpu["p99"]), d(cpu["max"]), n(j["cpu_long_ticks"]));
  }
  if (a.save_every > 0)
    std::printf("  published        %lld epochs, %lld slab versions; %d autosaves while sculpting\n",
                n(j["publications"]), n(j["slabs_published"]), j["autosaves"].get<int>());
  for (const char* t : {"carve", "add"})
    if (j.contains("against_exact_boolean") && j["against_exact_boolean"].contains(t)) {
      const nlohmann::json& c = j["against_exact_boolean"][t];
      std::printf(
          "  %-5s vs exact   model->exact RMS %.4f%% max %.4f%%, exact->model RMS %.4f%% max %.4f%% of the "
          "diagonal (%lld sweeps, against %s)\n",
          t, d(c["rms_pct"]), d(c["max_pct"]), d(c["rms_back_pct"]), d(c["max_back_pct"]), n(c["sweeps"]),
          a.check_against.c_str());
    }
  if (j.contains("realtime_note"))
    std::printf("  note             %s\n", j["realtime_note"].get<std::string>().c_str());
  if (!a.output.empty()) std::printf("  wrote            %s\n", a.output.c_str());
  if (!a.forces.empty()) std::printf("  wrote            %s\n", a.forces.c_str());
}

void run_sculpt(const SculptArgs& a) {
  check_outputs({a.output, a.forces}, {a.model, a.script, a.check_against});
  check_model_output(a.output);
  SlabModel model = load_model(a.model, {a.limit.bytes()});
  const std::string script_path = a.script.empty() ? HDM_DEFAULT_SCRIPT : a.script;
  const Script script = read_script(script_path, a.limit.bytes());
  const Aabb box = surface_box(model);
  const Workspace ws = fit_workspace(box, script.workspace_m);
  const double mm = ws.scale / 1000;  // model units per device millimetre
  apply_script_surface(model, script, mm);
  Trajectory path;
  {
    const SlabLocator locator(model);
    const int64_t ticks = count_trajectory_ticks(script, model, locator, ws, a.rate);
    require_sculpt_memory(a, ticks);
    path = build_trajectory(script, model, locator, ws, a.rate, ticks);
  }
  std::vector<Brush> brushes;
  for (const Stroke& st : script.strokes) brushes.push_back(stroke_brush(st, mm));
  const std::vector<uint32_t> buttons = tool_buttons(path);

  const SessionOptions so = session_options(a, script);
  SculptSession session(std::move(model), ws, so);
  std::vector<EditLogEntry> sweep_log;
  if (!a.check_against.empty()) {
    sweep_log.reserve(path.position.size() + 4 * script.strokes.size() + 16);  // at most one sweep per tick
    session.editor().record_log(&sweep_log);
  }

  SimulatedDeviceOptions dopt;
  dopt.rate_hz = a.rate;
  dopt.spec.max_force_n = script.force.max_force;
  dopt.hand_stiffness = script.hand_stiffness;
  dopt.hand_damping = script.hand_damping;
  // The rigid tool is a 6-DOF device: its torque reaches the hand's wrist and turns the handle.
  if (so.mode == RenderMode::RigidTool) dopt.spec.max_torque_nm = so.rigid.max_torque;
  SimulatedDevice device(dopt, path.position, path.position.front(), buttons);

  Run run;
  run.path = &path;
  run.script = &script;
  run.brushes = &brushes;
  run.scale = ws.scale;
  run.records.resize(path.position.size());
  ServoOptions opt;
  opt.rate_hz = a.rate;
  opt.realtime = !a.fast;
  opt.ticks = static_cast<int64_t>(path.position.size());
  opt.cpu_time = a.cpu_time;

  const char* note = nullptr;
  int autosaves = 0;
  const ServoStats st = run_with_autosave(session, device, opt, run, a, autosaves, note);
  session.finish();  // sweeps still queued when the loop ended

  if (!a.forces.empty()) write_csv(a.forces, run.records);
  if (!a.output.empty()) save_model(session.model(), a.output);
  const nlohmann::json check = check_against_exact(a, session, sweep_log);
  nlohmann::json j = sculpt_report(a, script_path, st, session, so.edit_every, autosaves);
  if (!check.is_null()) j["against_exact_boolean"] = check;
  if (note) j["realtime_note"] = note;
  if (a.json)
    std::printf("%s\n", j.dump(2).c_str());
  else
    print_sculpt_report(j, a);
}

}  // namespace

void add_sculpt_command(CLI::App& app) {
  auto a = std::make_shared<SculptArgs>();
  CLI::App* cmd = app.add_subcommand(
      "sculpt", "Run the servo loop with a simulated hand that follows a sculpting script (closed loop)");
  cmd->add_option("model", a->model, "slab model (.hdm)")->required();
  cmd->add_option("--script", a->script, "sculpting script (JSON); default: the shipped bunny script");
  cmd->add_option("-o,--output", a->output, "write the edited model here (.hdm)");
  auto* rate = cmd->add_option("--rate", a->rate, "servo rate [Hz]")->check(CLI::Range(1.0, 1e6));
  cmd->add_flag("--fast", a->fast, "run ticks back to back instead of in real time")->excludes(rate);
  auto* every = cmd->add_flag("--edit-every-tick", a->every_tick, "feed a tool position on every tick (the default)");
  cmd->add_option("--edit-rate", a->edit_rate, "feed tool positions at this rate [Hz] instead (paper: 10)")
      ->check(CLI::Range(0.1, 1e6))
      ->excludes(every);
  cmd->add_option("--budget-us", a->budget_us, "edit and publication work per tick [µs] (the rest carries over)")
      ->check(CLI::Range(1.0, 1e6));
  cmd->add_option("--save-every", a->save_every,
                  "save the model to -o from another thread every S seconds while sculpting")
      ->check(CLI::Range(0.01, 1e6));
  cmd->add_option("--mode", a->mode,
                  "force model: proxy (a point god-object, default), penalty (the paper's), sphere (the brush felt as "
                  "a ball of its radius held outside the surface, which carves with it) or rigid (a 6-DOF dental burr, "
                  "head radius 1 % of the model's diagonal, force and torque, the torque turning the simulated hand's "
                  "handle against its wrist; its head drills with the drill brush)")
      ->check(CLI::IsMember({"proxy", "penalty", "sphere", "rigid"}));
  cmd->add_option("--solver", a->solver, "alpha-plane root finder: newton (default) or bisection (the paper's)")
      ->check(CLI::IsMember({"newton", "bisection"}));
  cmd->add_option("--forces", a->forces, "write one CSV row per tick here");
  cmd->add_option("--check-against", a->check_against,
                  "measure the carved and added strokes against the exact boolean of this input mesh with the "
                  "swept tools (RMS and max, % of the diagonal; smooth and flatten strokes near them count as error)");
  cmd->add_flag("--cpu-time", a->cpu_time,
                "also time each tick with the servo thread's CPU clock (tells long ticks from preempted ones)");
  cmd->add_flag("--json", a->json, "print the summary as one JSON object");
  add_input_limit(cmd, a->limit);
  add_memory_budget(cmd, a->budget);
  cmd->callback([a] { run_sculpt(*a); });
}

}  // namespace hdm::app
