// SPDX-License-Identifier: MIT
// The reference Python client (examples/python/bridge_client.py) plays a carving trajectory through
// the bridge, over UDP and over shared memory, in lockstep (each packet's force before the next
// packet), and the servo loop clocked by its packets (run_bridge_session) carves a sphere. The
// resulting displacements must equal, bit for bit, those of the same trajectory replayed from its
// CSV by ReplayDevice: the bridge carries every double exactly (the CSV is written with 17
// significant digits, which Python's float() and the C++ reader both round to the same double), and
// with one tick per packet the session sees the same inputs in the same order.
#include <hdm/bridge/bridge_session.h>
#include <hdm/slab/bake.h>

#include "support/test_models.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <thread>

namespace hdm::bridge {
namespace {

const SlabModel& sphere_model() {
  static const SlabModel m = [] {
    BakeOptions o;
    o.slabs = 120;
    o.grid_n = 8;
    return bake_slabs(test::icosphere(4, 1.0), "icosphere", o);
  }();
  return m;
}

Workspace sphere_workspace() {  // the unit sphere is 0.1 m in radius at the device
  Workspace ws;
  ws.scale = 10.0;
  return ws;
}

// Approach the north pole from 1 cm above, press 3 mm in, hold the tool button and slide 0.3 rad
// towards +x at that depth, release and lift: one row per millisecond.
std::string write_trajectory() {
  const std::string path =
      (std::filesystem::temp_directory_path() / ("hdm-bridge-carve-" + std::to_string(::getpid()) + ".csv")).string();
  std::ofstream out(path);
  out << "time_s,device_x_m,device_y_m,device_z_m,tool_on\n";
  int k = 0;
  auto row = [&](const Vec3& p, int tool) {
    char line[160];
    std::snprintf(line, sizeof line, "%.17g,%.17g,%.17g,%.17g,%d\n", 0.001 * k++, p.x(), p.y(), p.z(), tool);
    out << line;
  };
  for (int i = 0; i <= 100; ++i) row(Vec3(0, 0, 0.11 - (0.11 - 0.097) * i / 100.0), 0);
  for (int i = 0; i <= 300; ++i) {
    const double a = 0.3 * i / 300.0;
    row(0.097 * Vec3(std::sin(a), 0, std::cos(a)), 1);
  }
  for (int i = 0; i <= 100; ++i) row(Vec3(0.097 * std::sin(0.3), 0, 0.097 * std::cos(0.3) + 0.02 * i / 100.0), 0);
  return path;
}

SessionOptions session_options() {
  SessionOptions o;
  o.publish = false;
  // Every tick finishes its edits: the proxy then feels the same model on every tick whatever the
  // machine's speed, so the result depends on the inputs only.
  o.edit_budget_s = 1.0;  // normals are refreshed by the stroke's time (the default interval)
  return o;
}

Brush carve() {
  Brush b;
  b.tool = BrushTool::Carve;
  b.radius = 0.15;  // 15 mm at the device
  return b;
}

SlabModel replayed(const std::string& csv, size_t rows = 0) {
  SculptSession session(sphere_model(), sphere_workspace(), session_options());
  session.set_brush(carve());
  ReplayDevice device(csv);
  if (rows > 0) {  // the first rows only
    std::ifstream in(csv);
    std::string text, line;
    for (size_t k = 0; k <= rows && std::getline(in, line); ++k) text += line + "\n";
    device = ReplayDevice::from_csv(text, csv);
  }
  ServoTick t;
  for (;; ++t.tick) {
    t.time_s = 1e-3 * double(t.tick);
    if (session.tick(device, t).ended) break;
  }
  session.finish();
  return session.model();
}

const std::string kCarveSecret = "carve-test-secret-0123456789";

// The reference client with the shared secret in its environment.
std::string client_command() {
  return "HDM_BRIDGE_SECRET=" + kCarveSecret + " " + std::string(HDM_PYTHON3) + " " + HDM_BRIDGE_CLIENT;
}

SlabModel bridged(const std::string& csv, const std::string& endpoint, BridgeCounters& counters, int& client_status) {
  SculptSession session(sphere_model(), sphere_workspace(), session_options());
  session.set_brush(carve());
  BridgeOptions bo;
  bo.secret = kCarveSecret;
  bo.watchdog_s = 1.0;  // a Python pause on a loaded machine must not release the tool here
  auto device = BridgeDevice::open(endpoint, bo);
  const std::string target =
      device->port() > 0 ? "--udp " + std::to_string(device->port()) : "--shm " + endpoint.substr(4);
  const std::string cmd = client_command() + " " + target + " " + csv + " --lockstep --timeout 10 > /dev/null";
  std::thread client([&] { client_status = std::system(cmd.c_str()); });
  BridgeLoopOptions lo;
  lo.give_up_s = 30;
  lo.spin = false;  // the client needs the other core
  const BridgeLoopStats st = run_bridge_session(session, *device, lo);
  client.join();
  EXPECT_TRUE(st.ended) << "the client's end packet never came";
  session.finish();
  counters = device->counters();
  return session.model();
}

void expect_same_carve(const std::string& endpoint) {
  const std::string csv = write_trajectory();
  const SlabModel reference = replayed(csv);
  size_t carved = 0;
  for (size_t i = 0; i < reference.displacement.size(); ++i)
    carved += reference.displacement[i] != sphere_model().displacement[i];
  ASSERT_GT(carved, 10u) << "the trajectory must carve";

  BridgeCounters c;
  int status = -1;
  const SlabModel model = bridged(csv, endpoint, c, status);
  EXPECT_EQ(status, 0) << "the client failed (lost forces or could not connect)";
  EXPECT_EQ(c.accepted, 503 + 1);  // every row, then the end packet
  EXPECT_EQ(c.dropped(), 0);
  ASSERT_EQ(model.displacement.size(), reference.displacement.size());
  size_t differ = 0;
  for (size_t i = 0; i < model.displacement.size(); ++i)
    differ += model.displacement[i].code != reference.displacement[i].code;
  EXPECT_EQ(differ, 0u) << "of " << carved << " samples carved by the replay";
  std::filesystem::remove(csv);
}

// What the after-hook sees of the watchdog: the last tick's tool button and the device's gain
// against the driver's time since its last packet.
struct WatchdogProbe {
  BridgeDevice* device = nullptr;
  double last_packet_s = 0;  // the driver's time of its last row
  double window_s = 0;       // watchdog + ramp
  int64_t late_ticks = 0, late_tool_on = 0, late_force = 0;
  bool tool_seen = false;
  static void after(void* user, const ServoTick& t, const SessionTick& r) noexcept {
    WatchdogProbe& p = *static_cast<WatchdogProbe*>(user);
    p.tool_seen |= r.tool_on;
    if (t.time_s > p.last_packet_s + p.device->options().watchdog_s + 0.0005) p.late_tool_on += r.tool_on;
    if (t.time_s > p.last_packet_s + p.window_s + 0.001) {
      ++p.late_ticks;
      p.late_force += p.device->gain() != 0.0;
    }
  }
};

// The driver goes silent in the middle of the stroke (row 250 of 503): the watchdog releases the
// tool, so the stroke ends where the packets stopped (the model equals the replay of the first 250
// rows), and the force gain is zero from watchdog + ramp after the last packet on.
TEST(BridgeCarve, LostPacketsEndTheStrokeAndRampTheForceOut) {
  const std::string csv = write_trajectory();
  const size_t rows = 250;
  const SlabModel reference = replayed(csv, rows);

  SculptSession session(sphere_model(), sphere_workspace(), session_options());
  session.set_brush(carve());
  BridgeOptions bo;
  bo.secret = kCarveSecret;
  bo.watchdog_s = 0.2;  // long enough for a Python pause on a loaded machine, short for the test
  bo.ramp_s = 0.01;
  const std::string name = "hdm-test-silent-" + std::to_string(::getpid());
  auto device = BridgeDevice::open("shm:" + name, bo);
  const std::string cmd = client_command() + " --shm " + name + " " + csv + " --lockstep --timeout 10 --stop-after " +
                          std::to_string(rows) + " --no-end > /dev/null";
  int status = -1;
  std::thread client([&] { status = std::system(cmd.c_str()); });
  WatchdogProbe probe;
  probe.device = device.get();
  probe.last_packet_s = 0.001 * double(rows - 1);
  probe.window_s = bo.watchdog_s + bo.ramp_s;
  BridgeLoopOptions lo;
  lo.give_up_s = 0.4;      // then the loop ends
  lo.first_packet_s = 30;  // the Python client may take seconds to start beside other tests
  lo.spin = false;
  const BridgeLoopStats st =
      run_bridge_session(session, *device, lo, SessionHooks{nullptr, WatchdogProbe::after, &probe});
  client.join();
  EXPECT_EQ(status, 0);
  EXPECT_TRUE(st.gave_up);
  EXPECT_TRUE(probe.tool_seen);
  EXPECT_GT(probe.late_ticks, 50);  // idle ticks every millisecond after the window
  EXPECT_EQ(probe.late_force, 0);
  EXPECT_EQ(probe.late_tool_on, 0);
  EXPECT_EQ(device->counters().watchdog_trips, 1);
  session.finish();
  const SlabModel& model = session.model();
  size_t differ = 0;
  for (size_t i = 0; i < model.displacement.size(); ++i)
    differ += model.displacement[i].code != reference.displacement[i].code;
  EXPECT_EQ(differ, 0u);
  std::filesystem::remove(csv);
}

TEST(BridgeCarve, UdpEqualsReplay) { expect_same_carve("udp:0"); }

TEST(BridgeCarve, SharedMemoryEqualsReplay) { expect_same_carve("shm:hdm-test-carve-" + std::to_string(::getpid())); }

}  // namespace
}  // namespace hdm::bridge
