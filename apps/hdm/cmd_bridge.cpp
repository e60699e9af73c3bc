// SPDX-License-Identifier: MIT
// hdm bridge MODEL.hdm --device udp:PORT|shm:NAME: sculpt a model with a device driven by another
// process through the device bridge (docs/bridge.md), without a window: one servo tick per device
// packet (run_bridge_session) until the driver's end packet or its silence, then save the model.
#include "commands.h"
#include "output_guard.h"

#include <hdm/bridge/bridge_secret.h>
#include <hdm/bridge/bridge_session.h>
#include <hdm/io/hdm_file.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <vector>

namespace hdm::app {
namespace {

struct BridgeArgs {
  std::string model, device, output, tool = "carve", secret_file;
  double radius_mm = 3, strength = 1, workspace_m = 0.16, stiffness = 1000, watchdog_ms = 5, give_up_s = 10;
  bool json = false, spin = false, no_realtime = false;
  InputLimit limit;
};

// Tick work [ns], recorded by the servo thread into preallocated storage.
struct Timing {
  std::vector<uint32_t> work_ns;
  int64_t start_ns = 0;
  static int64_t now() noexcept {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
  }
  static void before(void* user, SculptSession&, const ServoTick&) noexcept {
    static_cast<Timing*>(user)->start_ns = now();
  }
  static void after(void* user, const ServoTick&, const SessionTick&) noexcept {
    Timing& t = *static_cast<Timing*>(user);
    if (t.work_ns.size() < t.work_ns.capacity())
      t.work_ns.push_back(static_cast<uint32_t>(std::min<int64_t>(now() - t.start_ns, UINT32_MAX)));
  }
};

void run_bridge(const BridgeArgs& a) {
  check_outputs({a.output}, {a.model});
  check_model_output(a.output);
  SlabModel model = load_model(a.model, {a.limit.bytes()});
  const Aabb box = surface_box(model);
  const Workspace ws = fit_workspace(box, a.workspace_m);
  SessionOptions so;
  so.proxy.force.stiffness = a.stiffness;
  so.publish = false;
  SculptSession session(std::move(model), ws, so);
  Brush brush;
  brush.tool = parse_brush_tool(a.tool);
  brush.radius = a.radius_mm * ws.scale / 1000;
  brush.strength = a.strength;
  session.set_brush(brush);

  bridge::BridgeOptions bo;
  bo.watchdog_s = a.watchdog_ms * 1e-3;
  bo.secret = bridge::load_bridge_secret(a.secret_file);
  auto device = bridge::BridgeDevice::open(a.device, bo);
  if (!a.json) {
    std::printf("listening on %s (workspace %.3f m, %s, radius %.1f mm)\n", device->endpoint().c_str(), a.workspace_m,
                a.tool.c_str(), a.radius_mm);
    std::fflush(stdout);
  }
  Timing timing;
  timing.work_ns.reserve(10'000'000);  // about 40 MB: 10^7 ticks (2.8 hours at 1 kHz)
  bridge::BridgeLoopOptions lo;
  lo.give_up_s = a.give_up_s;
  lo.spin = a.spin;
  lo.realtime = !a.no_realtime;
  const bridge::BridgeLoopStats st =
      bridge::run_bridge_session(session, *device, lo, SessionHooks{Timing::before, Timing::after, &timing});
  session.finish();
  if (!a.output.empty()) save_model(session.model(), a.output);

  const LatencyStats work = latency_stats(std::vector<double>(timing.work_ns.begin(), timing.work_ns.end()));
  const bridge::BridgeCounters c = device->counters();
  const SessionStats& ss = session.stats();
  nlohmann::json j = {{"model", a.model},
                      {"device", device->endpoint()},
                      {"ticks", st.ticks},
                      {"idle_ticks", st.idle_ticks},
                      {"realtime", st.realtime},
                      {"ended", st.ended     ? "end packet"
                                : st.gave_up ? "silence"
                                             : "stopped"},
                      {"tick_ns", {{"median", work.median}, {"p99", work.p99}, {"max", work.max}}},
                      {"packets",
                       {{"accepted", c.accepted},
                        {"bad_size", c.bad_size},
                        {"bad_magic", c.bad_magic},
                        {"bad_version", c.bad_version},
                        {"bad_kind", c.bad_kind},
                        {"non_finite", c.non_finite},
                        {"out_of_order", c.out_of_order},
                        {"bad_secret", c.bad_secret},
                        {"wrong_session", c.wrong_session},
                        {"sessions", c.sessions}}},
                      {"watchdog_trips", c.watchdog_trips},
                      {"contact_ticks", ss.contact_ticks},
                      {"sweeps", ss.sweeps},
                      {"changed", ss.changed},
                      {"output", a.output}};
  if (a.json) {
    std::printf("%s\n", j.dump(2).c_str());
    return;
  }
  std::printf("  ticks            %lld (%lld idle, while the watchdog held), ended by %s%s\n", (long long)st.ticks,
              (long long)st.idle_ticks, j["ended"].get<std::string>().c_str(),
              st.realtime ? "" : " (normal priority: SCHED_FIFO not permitted or not asked)");
  std::printf("  tick work        median %.0f ns, p99 %.0f ns, max %.0f ns\n", work.median, work.p99, work.max);
  std::printf("  packets          %lld accepted, %lld dropped (%lld wrong secret, %lld of another session), %lld "
              "driver sessions, %lld watchdog trips\n",
              (long long)c.accepted, (long long)c.dropped(), (long long)c.bad_secret, (long long)c.wrong_session,
              (long long)c.sessions, (long long)c.watchdog_trips);
  std::printf("  edits            %lld contact ticks, %lld sweeps, %lld samples/texels changed\n",
              (long long)ss.contact_ticks, (long long)ss.sweeps, (long long)ss.changed);
  if (!a.output.empty()) std::printf("  wrote            %s\n", a.output.c_str());
}

}  // namespace

void add_bridge_command(CLI::App& app) {
  auto a = std::make_shared<BridgeArgs>();
  CLI::App* cmd = app.add_subcommand(
      "bridge", "Sculpt a model with a device driven by another process through the device bridge (docs/bridge.md)");
  cmd->add_option("model", a->model, "slab model (.hdm)")->required();
  cmd->add_option("--device", a->device, "udp:PORT (127.0.0.1) or shm:NAME")->required();
  cmd->add_option("-o,--output", a->output, "write the edited model here (.hdm) when the driver ends");
  cmd->add_option("--secret-file", a->secret_file,
                  "the shared secret a driver must present, created with mode 0600 when missing (default: the "
                  "HDM_BRIDGE_SECRET environment variable)");
  cmd->add_option("--tool", a->tool, "brush held by the tool button: carve (default), add, smooth, flatten, paint");
  cmd->add_option("--radius-mm", a->radius_mm, "brush radius at the device [mm]")->check(CLI::Range(0.01, 1000.0));
  cmd->add_option("--strength", a->strength, "brush strength in [0,1]")->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--workspace-m", a->workspace_m, "the model's diagonal fitted into this device workspace [m]")
      ->check(CLI::Range(0.001, 100.0));
  cmd->add_option("--stiffness", a->stiffness, "proxy stiffness at the device [N/m]")->check(CLI::Range(1.0, 1e5));
  cmd->add_option("--watchdog-ms", a->watchdog_ms, "release the tool and ramp the force out after this silence [ms]")
      ->check(CLI::Range(0.1, 60000.0));
  cmd->add_option("--give-up-s", a->give_up_s, "end after this long without a packet [s]")
      ->check(CLI::Range(0.01, 1e6));
  cmd->add_flag("--spin", a->spin,
                "spin between packets instead of sleeping 50 µs between looks (lowest latency; a core kept busy)");
  cmd->add_flag("--no-realtime", a->no_realtime,
                "leave the servo thread at normal priority (default: SCHED_FIFO when permitted)");
  cmd->add_flag("--json", a->json, "print the summary as one JSON object");
  add_input_limit(cmd, a->limit);
  cmd->callback([a] { run_bridge(*a); });
}

}  // namespace hdm::app
