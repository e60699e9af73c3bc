// SPDX-License-Identifier: MIT
// hdm sculpt MODEL.hdm: a servo loop drives a simulated device along a script's strokes; forces are
// rendered, and carve/add/paint edits are applied at the edit rate.
#include "commands.h"
#include "sculpt_script.h"

#include <hdm/core/error.h>
#include <hdm/edit/edit_tools.h>
#include <hdm/haptics/force.h>
#include <hdm/haptics/proxy.h>
#include <hdm/haptics/servo_loop.h>
#include <hdm/io/hdm_file.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>

namespace hdm::app {
namespace {

struct SculptArgs {
  std::string model, script, output, forces, mode = "proxy", solver = "newton";
  double rate = 1000, edit_rate = 10;
  bool fast = false, every_tick = false, json = false;
  InputLimit limit;
};

// One CSV row, recorded in preallocated storage by the servo thread and written afterwards.
struct TickRecord {
  float t;
  Vec3f device;
  int8_t contact;
  float depth_m;
  Vec3f force;
};

// Everything the tick touches, set up before the loop so that the tick never allocates.
struct TickState {
  SlabModel* model;
  const SlabLocator* locator;
  const Script* script;
  const Trajectory* path;
  Workspace ws;
  double dt;
  int64_t edit_every;
  EditScratch* scratch;
  QueryCache cache;
  RenderMode mode = RenderMode::Proxy;
  ProxyParams proxy;
  ProxyState proxy_state;
  std::vector<TickRecord> records;
  std::vector<double> query_ns;
  int64_t contact_ticks = 0, edits = 0, samples_changed = 0, texels_painted = 0;
};

void tick(void* user, const ServoTick& servo) noexcept {
  auto& s = *static_cast<TickState*>(user);
  const int64_t k = servo.tick;
  const double t = servo.time_s;
  const Vec3 dev = s.path->position[k];
  const Vec3 vel = k > 0 ? Vec3((dev - s.path->position[k - 1]) / s.dt) : Vec3::Zero();
  const auto q0 = std::chrono::steady_clock::now();
  Contact c;
  Vec3 force;
  if (s.mode == RenderMode::Proxy) {  // god-object: the proxy's contact drives the edits
    const ProxyOutput out = proxy_step(*s.model, *s.locator, s.ws, dev, vel, s.proxy, s.proxy_state);
    c = out.contact;
    force = out.force;
  } else {  // the paper's penalty force on the HIP's own query
    c = query(*s.model, *s.locator, s.ws.to_model(dev), s.cache, s.proxy.solver);
    force = penalty_force(c, vel, s.script->force, s.ws).force;
  }
  force *= servo.force_gain;  // ramp-in/out and the watchdog of the servo loop
  s.query_ns[k] = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - q0).count();
  s.records[k] = {static_cast<float>(t), dev.cast<float>(), static_cast<int8_t>(c.penetrating()),
                  static_cast<float>(c.penetrating() ? c.depth / s.ws.scale : 0.0), force.cast<float>()};
  if (!c.penetrating()) return;
  ++s.contact_ticks;
  const int16_t stroke = s.path->stroke[k];
  if (stroke < 0 || k % s.edit_every != 0) return;
  const Stroke& st = s.script->strokes[stroke];
  const double mm = s.ws.scale / 1000;  // model units per device millimetre
  EditResult r;
  switch (st.tool) {
    case Tool::Carve:
      r = carve(*s.model, *s.scratch, c, s.ws.to_model(dev), st.radius_mm * mm, st.resilience_mm * mm);
      s.samples_changed += r.changed;
      break;
    case Tool::Add:
      r = add_material(*s.model, *s.scratch, c, st.radius_mm * mm, st.height_mm * mm);
      s.samples_changed += r.changed;
      break;
    case Tool::Paint:
      r = paint(*s.model, *s.scratch, c, st.radius_mm * mm, st.colour,
                paint_pressure(c.depth, 0.1 * st.depth_mm * mm, st.depth_mm * mm));
      s.texels_painted += r.changed;
      break;
    default:
      return;
  }
  ++s.edits;
}

void write_csv(const std::string& path, const std::vector<TickRecord>& rows) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    if (!out) throw IoError(path + ": cannot write");
    out << "time_s,device_x_m,device_y_m,device_z_m,contact,depth_m,force_x_n,force_y_n,force_z_n\n";
    char line[256];
    for (const TickRecord& r : rows) {
      std::snprintf(line, sizeof line, "%.4f,%.6f,%.6f,%.6f,%d,%.7f,%.5f,%.5f,%.5f\n", r.t, r.device.x(), r.device.y(),
                    r.device.z(), r.contact, r.depth_m, r.force.x(), r.force.y(), r.force.z());
      out << line;
    }
    if (!out) throw IoError(path + ": write failed");
  }
  std::filesystem::rename(tmp, path);
}

void run_sculpt(const SculptArgs& a) {
  SlabModel model = load_model(a.model, {a.limit.bytes()});
  const std::string script_path = a.script.empty() ? HDM_DEFAULT_SCRIPT : a.script;
  const Script script = read_script(script_path, a.limit.bytes());
  const SlabLocator locator(model);
  Aabb box;
  for (const Vec3f& p : model.positions) box.extend(p.cast<double>());
  TickState s;
  s.ws = fit_workspace(box, script.workspace_m);
  const Trajectory path = build_trajectory(script, model, locator, s.ws, a.rate);
  EditScratch scratch(model);
  s.model = &model;
  s.locator = &locator;
  s.script = &script;
  s.path = &path;
  s.dt = 1.0 / a.rate;
  s.mode = parse_render_mode(a.mode);
  s.proxy.force = script.force;
  s.proxy.solver = parse_alpha_solver(a.solver);
  s.edit_every = a.every_tick ? 1 : std::max<int64_t>(1, std::llround(a.rate / a.edit_rate));
  s.scratch = &scratch;
  s.records.resize(path.position.size());
  s.query_ns.resize(path.position.size());

  ServoOptions so;
  so.rate_hz = a.rate;
  so.realtime = !a.fast;
  so.ticks = static_cast<int64_t>(path.position.size());
  const char* note = nullptr;
  const ServoStats st = run_servo_loop(so, tick, &s, &note);

  if (!a.forces.empty()) write_csv(a.forces, s.records);
  if (!a.output.empty()) save_model(model, a.output);
  const LatencyStats q = latency_stats(s.query_ns);
  nlohmann::json j = {{"model", a.model},
                      {"script", script_path},
                      {"ticks", st.ticks},
                      {"seconds", st.seconds},
                      {"rate_hz", st.rate_hz},
                      {"target_rate_hz", a.rate},
                      {"realtime", !a.fast},
                      {"mode", a.mode},
                      {"solver", a.solver},
                      {"query_ns", {{"median", q.median}, {"p99", q.p99}, {"max", q.max}}},
                      {"tick_ns", {{"median", st.compute_ns.median}, {"p99", st.compute_ns.p99}, {"max", st.compute_ns.max}}},
                      {"period_ns", {{"median", st.period_ns.median}, {"p99", st.period_ns.p99}, {"max", st.period_ns.max}}},
                      {"overruns", st.overruns},
                      {"contact_ticks", s.contact_ticks},
                      {"edits", s.edits},
                      {"edit_every_ticks", s.edit_every},
                      {"samples_changed", s.samples_changed},
                      {"texels_painted", s.texels_painted},
                      {"output", a.output},
                      {"forces", a.forces}};
  if (note) j["realtime_note"] = note;
  if (a.json) {
    std::printf("%s\n", j.dump(2).c_str());
    return;
  }
  std::printf("sculpted %s with %s\n", a.model.c_str(), script_path.c_str());
  std::printf("  ticks            %lld in %.2f s: %.0f Hz (target %.0f Hz%s)\n", (long long)st.ticks, st.seconds,
              st.rate_hz, a.rate, a.fast ? ", --fast" : "");
  // In proxy mode the timed section is the whole proxy step (its slab queries included).
  std::printf("  %s median %.0f ns, p99 %.0f ns, max %.0f ns\n",
              s.mode == RenderMode::Proxy ? "query + proxy   " : "query latency   ", q.median, q.p99, q.max);
  std::printf("  tick compute     median %.0f ns, p99 %.0f ns, max %.0f ns\n", st.compute_ns.median,
              st.compute_ns.p99, st.compute_ns.max);
  std::printf("  contact ticks    %lld\n", (long long)s.contact_ticks);
  std::printf("  edits            %lld (every %lld ticks), samples changed %lld, texels painted %lld\n",
              (long long)s.edits, (long long)s.edit_every, (long long)s.samples_changed, (long long)s.texels_painted);
  if (note) std::printf("  note             %s\n", note);
  if (!a.output.empty()) std::printf("  wrote            %s\n", a.output.c_str());
  if (!a.forces.empty()) std::printf("  wrote            %s\n", a.forces.c_str());
}

}  // namespace

void add_sculpt_command(CLI::App& app) {
  auto a = std::make_shared<SculptArgs>();
  CLI::App* cmd = app.add_subcommand("sculpt", "Run the servo loop with a simulated device that follows a sculpting script");
  cmd->add_option("model", a->model, "slab model (.hdm)")->required();
  cmd->add_option("--script", a->script, "sculpting script (JSON); default: the shipped bunny script");
  cmd->add_option("-o,--output", a->output, "write the edited model here (.hdm)");
  auto* rate = cmd->add_option("--rate", a->rate, "servo rate [Hz]")->check(CLI::Range(1.0, 1e6));
  cmd->add_flag("--fast", a->fast, "run ticks back to back instead of in real time")->excludes(rate);
  cmd->add_option("--edit-rate", a->edit_rate, "edit rate [Hz] (paper: 10)")->check(CLI::Range(0.1, 1e6));
  cmd->add_flag("--edit-every-tick", a->every_tick, "apply edits on every tick");
  cmd->add_option("--mode", a->mode, "force model: proxy (god-object, default) or penalty (the paper's)")
      ->check(CLI::IsMember({"proxy", "penalty"}));
  cmd->add_option("--solver", a->solver, "alpha-plane root finder: newton (default) or bisection (the paper's)")
      ->check(CLI::IsMember({"newton", "bisection"}));
  cmd->add_option("--forces", a->forces, "write one CSV row per tick here");
  cmd->add_flag("--json", a->json, "print the summary as one JSON object");
  add_input_limit(cmd, a->limit);
  cmd->callback([a] { run_sculpt(*a); });
}

}  // namespace hdm::app
