// SPDX-License-Identifier: MIT
// Replay (`hdm feel --replay`): a recorded trajectory is played open loop through the renderer and
// scored against the exact input; bad recordings are refused with the file and line named.
#include "support/test_models.h"

#include <hdm/core/error.h>
#include <hdm/haptics/device.h>
#include <hdm/harness/scenario_sites.h>
#include <hdm/harness/scenarios.h>

#include <gtest/gtest.h>

#include <vector>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace hdm {
namespace {

std::string temp_csv(const std::string& name) { return (std::filesystem::temp_directory_path() / name).string(); }

// A straight press 2 mm deep along the input's normal, held: the proxy force is k·2 mm along the
// exact input normal (k = 1000 N/m, frictionless), with no pop-through.
TEST(Replay, PressIsScoredAgainstTheInput) {
  const SlabModel& model = test::baked_bunny(150, 16);
  const SlabLocator locator(model);
  const ExactMeshQuery reference(test::bunny());
  const SurfacePoint spot = ScenarioSites(reference).press_spot();
  const Workspace ws = fit_workspace(bounds(test::bunny()), 0.16);
  const Vec3 p = ws.to_device(spot.point), n = spot.face_normal;
  const std::string path = temp_csv("hdm_replay_press.csv");
  const int ramp = 400, hold = 200;
  {
    std::ofstream f(path);
    f << "time_s,device_x_m,device_y_m,device_z_m\n";
    for (int k = 0; k < ramp + hold; ++k) {
      const double depth = -0.005 + 0.007 * std::min(1.0, double(k) / ramp);  // 5 mm out to 2 mm in
      const Vec3 x = p - n * depth;
      char line[128];
      std::snprintf(line, sizeof line, "%.6f,%.9f,%.9f,%.9f\n", k * 1e-3, x.x(), x.y(), x.z());
      f << line;
    }
  }
  ReplayDevice device(path);
  ScenarioOptions o;
  const ScenarioReport r = run_replay(model, locator, reference, device, o);
  std::filesystem::remove(path);
  EXPECT_EQ(r.scenario, "replay");
  EXPECT_EQ(r.ticks, ramp + hold);
  EXPECT_NEAR(r.rate_hz, 1000, 1e-6);
  EXPECT_EQ(r.pop_throughs, 0);
  EXPECT_NEAR(r.max_force_n, 1000 * 0.002, 0.3) << "k x 2 mm, within the bake's surface error";
  EXPECT_LT(r.normal_error_p95_deg, 10.0) << "force along the exact input normal";
  EXPECT_LE(r.energy_ratio, 1.0) << "a press and hold returns no energy";
}

TEST(Replay, RefusesBadRecordingsNamingFileAndLine) {
  const std::string path = temp_csv("hdm_replay_bad.csv");
  auto expect_refused = [&](const std::string& body, const std::string& reason) {
    {
      std::ofstream f(path);
      f << "time_s,device_x_m,device_y_m,device_z_m\n" << body;
    }
    try {
      ReplayDevice d(path);
      ADD_FAILURE() << "accepted: " << reason;
    } catch (const InvalidInput& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(path + ":3"), std::string::npos) << what;
      EXPECT_NE(what.find(reason), std::string::npos) << what;
    }
  };
  expect_refused("0,0,0,0\n0.001,nan,0,0\n", "not a finite number");
  expect_refused("0,0,0,0\n0.001,0,inf,0\n", "not a finite number");
  expect_refused("0.002,0,0,0\n0.001,0,0,0\n", "time goes backwards");
  expect_refused("0,0,0,0\n0.001,0,x,0\n", "malformed number");
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace hdm

namespace hdm {
namespace {

// The CSV reader from memory: columns found by name in any order, CRLF line ends, blanks around
// cells, a trailing comma, blank lines; every row read as written.
TEST(Replay, ReadsCsvVariantsFromMemory) {
  const std::string csv =
      "device_z_m, time_s ,device_x_m,device_y_m,extra\r\n"
      "0.03,0,+0.01,-0.02,7\r\n"
      "\r\n"
      " 0.031 , 0.001 , 0.011 , -0.021 , 8 ,\r\n";
  ReplayDevice d = ReplayDevice::from_csv(csv, "memory.csv");
  ASSERT_EQ(d.size(), 2u);
  DeviceState s;
  ASSERT_TRUE(d.begin_frame(s));
  EXPECT_EQ(s.position, Vec3(0.01, -0.02, 0.03));
  EXPECT_EQ(s.time_s, 0.0);
  d.end_frame(Vec3::Zero());
  ASSERT_TRUE(d.begin_frame(s));
  EXPECT_EQ(s.position, Vec3(0.011, -0.021, 0.031));
  EXPECT_EQ(s.time_s, 0.001);
  d.end_frame(Vec3::Zero());
  EXPECT_FALSE(d.begin_frame(s));
  try {
    ReplayDevice::from_csv("time_s,device_x_m,device_y_m,device_z_m\n0,0,0\n", "short.csv");
    ADD_FAILURE() << "a short row was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("short.csv:2: too few columns"), std::string::npos) << e.what();
  }
}

TEST(Replay, ToolOnColumnIsTheToolButton) {
  // The columns `hdm sculpt --forces` writes: the tool button comes back as bit 0.
  const std::string csv =
      "time_s,device_x_m,device_y_m,device_z_m,contact,tool_on\n"
      "0,0,0,0,0,0\n0.001,0,0,0,1,1\n0.002,0,0,0,1,1\n0.003,0,0,0,0,0\n";
  ReplayDevice d = ReplayDevice::from_csv(csv, "tool.csv");
  std::vector<uint32_t> buttons;
  DeviceState s;
  while (d.begin_frame(s)) buttons.push_back(s.buttons), d.end_frame(Vec3::Zero());
  EXPECT_EQ(buttons, (std::vector<uint32_t>{0, 1, 1, 0}));
  try {
    ReplayDevice::from_csv("time_s,device_x_m,device_y_m,device_z_m,tool_on\n0,0,0,0,2\n", "bad.csv");
    ADD_FAILURE() << "tool_on = 2 was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("bad.csv:2: tool_on"), std::string::npos) << e.what();
  }
}

TEST(Replay, SizeLimitIsCheckedBeforeReading) {
  const std::string path = (std::filesystem::temp_directory_path() / "hdm_replay_limit.csv").string();
  {
    std::ofstream f(path);
    f << "time_s,device_x_m,device_y_m,device_z_m\n0,0,0,0\n";
  }
  EXPECT_THROW(ReplayDevice(path, {}, 16), IoError);
  EXPECT_EQ(ReplayDevice(path).size(), 1u);
  std::filesystem::remove(path);
}

// Orientation and torque on the devices: the simulated handle reads its start orientation (unit)
// and zero angular velocity and records the torque clamped to the spec; a force-only end_frame
// drops it; a 3-DOF spec (max_torque_nm 0) renders none; the replay reads identity.
TEST(Device, OrientationAndTorque) {
  SimulatedDeviceOptions o;
  o.orientation = Eigen::Quaterniond(2, 0, 0, 2);  // 90° about z, not unit
  o.spec.max_torque_nm = 0.1;
  const std::vector<Vec3> targets(1, Vec3::Zero());
  SimulatedDevice d(o, targets, Vec3::Zero());
  DeviceState s;
  ASSERT_TRUE(d.begin_frame(s));
  EXPECT_NEAR(s.orientation.norm(), 1.0, 1e-15);
  EXPECT_LT((s.orientation * Vec3::UnitX() - Vec3::UnitY()).norm(), 1e-12);
  EXPECT_EQ(s.angular_velocity, Vec3::Zero());
  HapticDevice& base = d;
  base.end_frame(Vec3::Zero(), Vec3(0.03, 0, 0.04));
  EXPECT_EQ(d.last_torque(), Vec3(0.03, 0, 0.04));
  base.end_frame(Vec3::Zero(), Vec3(0, 0.3, 0));
  EXPECT_NEAR(d.last_torque().y(), 0.1, 1e-15) << "clamped to max_torque_nm";
  base.end_frame(Vec3::Zero(), Vec3(NAN, 0, 0));
  EXPECT_EQ(d.last_torque(), Vec3::Zero());
  base.end_frame(Vec3::Zero(), Vec3(0.01, 0, 0));
  base.end_frame(Vec3::Zero());
  EXPECT_EQ(d.last_torque(), Vec3::Zero()) << "a force-only frame commands no torque";
  o.spec.max_torque_nm = 0;
  SimulatedDevice three_dof(o, targets, Vec3::Zero());
  three_dof.end_frame(Vec3::Zero(), Vec3(0.01, 0, 0));
  EXPECT_EQ(three_dof.last_torque(), Vec3::Zero());
  o.orientation = Eigen::Quaterniond(0, 0, 0, 0);
  EXPECT_THROW(SimulatedDevice(o, targets, Vec3::Zero()), InvalidInput);

  ReplayDevice r = ReplayDevice::from_csv("time_s,device_x_m,device_y_m,device_z_m\n0,0,0,0\n", "mem");
  s.orientation = Eigen::Quaterniond(0, 1, 0, 0);
  s.angular_velocity = Vec3::Ones();
  ASSERT_TRUE(r.begin_frame(s));
  EXPECT_TRUE(s.orientation.coeffs().isApprox(Eigen::Quaterniond::Identity().coeffs()));
  EXPECT_EQ(s.angular_velocity, Vec3::Zero());
  r.end_frame(Vec3(1, 0, 0), Vec3(0, 0, 0.02));
  EXPECT_EQ(r.last_torque(), Vec3(0, 0, 0.02));
}

}  // namespace
}  // namespace hdm
