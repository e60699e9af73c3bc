// SPDX-License-Identifier: MIT
// The simulated handle's rotation against the analytic rigid body: a constant torque from rest
// turns a free handle by τ·t²/(2I), the wrist's spring holds it τ/k from its target, an undamped
// (and a damped) wrist rings with period 2π/ω, a NaN torque turns nothing; a rigid hold follows its
// targets. The replay's orientation columns round-trip and bad quaternions are refused by line.
#include <hdm/core/error.h>
#include <hdm/haptics/device.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

namespace hdm {
namespace {

using Quat = Eigen::Quaterniond;

// Rotation angle [rad] of @p q about @p axis (unit), signed: q's rotation vector along the axis.
double angle_about(const Quat& q, const Vec3& axis) {
  const Eigen::AngleAxisd aa(q.w() < 0 ? Quat(-q.coeffs()) : q);
  return aa.angle() * aa.axis().dot(axis);
}

// Runs @p ticks with a constant @p torque and returns the states read at the start of each tick
// and the one after the last.
std::vector<DeviceState> run(SimulatedDevice& d, int ticks, const Vec3& torque) {
  std::vector<DeviceState> out;
  for (int k = 0; k <= ticks; ++k) {
    DeviceState s;
    d.begin_frame(s);
    out.push_back(s);
    if (k < ticks) d.end_frame(Vec3::Zero(), torque);
  }
  return out;
}

SimulatedDeviceOptions free_handle() {
  SimulatedDeviceOptions o;
  o.wrist_stiffness = 0, o.wrist_damping = 0;
  o.spec.max_torque_nm = 1;
  return o;
}

const std::vector<Vec3> kStill(1, Vec3::Zero());

// Free handle, τ held from rest: θ(t) = τ·t²/(2I); the backward-difference angular velocity at t is
// (θ(t) − θ(t − T))/T = τ·(t − T/2)/I.
TEST(DeviceRotation, ConstantTorqueFromRestTurnsByTauTSquaredOverTwoI) {
  const SimulatedDeviceOptions o = free_handle();
  SimulatedDevice d(o, kStill, Vec3::Zero());
  const double tau = 1e-3, I = o.inertia_kgm2, T = 1 / o.rate_hz;
  const std::vector<DeviceState> s = run(d, 50, Vec3(0, 0, tau));
  const double t = 50 * T;
  EXPECT_NEAR(angle_about(s.back().orientation, Vec3::UnitZ()), tau * t * t / (2 * I), 0.01 * tau * t * t / (2 * I));
  EXPECT_NEAR(s.back().angular_velocity.z(), tau * (t - T / 2) / I, 0.01 * tau * t / I);
  EXPECT_LT(s.back().angular_velocity.head<2>().norm(), 1e-12) << "about the torque's axis only";
  EXPECT_NEAR(s.back().orientation.norm(), 1, 1e-12);
  EXPECT_EQ(s.back().position, Vec3::Zero()) << "a torque moves no position";
}

// Settled against the wrist's spring, the handle sits τ/k from the target, about the torque's
// axis (device frame), whatever the target; the wrist pushes back with −τ.
TEST(DeviceRotation, SteadyDeflectionIsTorqueOverWristStiffness) {
  SimulatedDeviceOptions o;  // the defaults: k = 1 N·m/rad, b = 0.006 N·m·s/rad
  o.spec.max_torque_nm = 0.2;
  o.orientation = Quat(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()));
  SimulatedDevice d(o, kStill, Vec3::Zero());
  const Vec3 tau(0.03, -0.04, 0);  // 0.05 N·m
  const std::vector<DeviceState> s = run(d, 2000, tau);
  const Eigen::AngleAxisd turned(s.back().orientation * o.orientation.conjugate());
  EXPECT_NEAR(turned.angle(), tau.norm() / o.wrist_stiffness, 1e-4 * tau.norm() / o.wrist_stiffness);
  EXPECT_GT(turned.axis().dot(tau.normalized()), 1 - 1e-9);
  EXPECT_LT((d.wrist_torque() + tau).norm(), 1e-4 * tau.norm());
  EXPECT_LT(s.back().angular_velocity.norm(), 1e-6);

  SimulatedDevice clamped(o, kStill, Vec3::Zero());  // 1 N·m asked, 0.2 N·m rendered
  const std::vector<DeviceState> c = run(clamped, 2000, Vec3(0, 1, 0));
  EXPECT_NEAR(Eigen::AngleAxisd(c.back().orientation * o.orientation.conjugate()).angle(), 0.2 / o.wrist_stiffness,
              1e-4);
}

// Upward zero crossings of the angle about y, linearly interpolated [s].
std::vector<double> crossings(const std::vector<DeviceState>& s) {
  std::vector<double> out;
  for (size_t k = 1; k < s.size(); ++k) {
    const double a = angle_about(s[k - 1].orientation, Vec3::UnitY()), b = angle_about(s[k].orientation, Vec3::UnitY());
    if (a < 0 && b >= 0) out.push_back(s[k - 1].time_s + (s[k].time_s - s[k - 1].time_s) * a / (a - b));
  }
  return out;
}

// Released 0.1 rad from its target, the handle rings at ω = sqrt(k/I) (undamped: period 2π/ω),
// and with the damper at ω·sqrt(1 − ζ²), ζ = b/(2·sqrt(k·I)).
TEST(DeviceRotation, WristRingsWithThePeriodOfItsSpringAndInertia) {
  SimulatedDeviceOptions o;
  o.wrist_damping = 0;
  o.orientation = Quat(Eigen::AngleAxisd(0.1, Vec3::UnitY()));  // the start; the target is the identity
  const std::vector<Quat> target(1, Quat::Identity());
  SimulatedDevice d(o, kStill, Vec3::Zero(), {}, target);
  const double w = std::sqrt(o.wrist_stiffness / o.inertia_kgm2);
  const std::vector<double> up = crossings(run(d, 500, Vec3::Zero()));
  ASSERT_GE(up.size(), 6u);
  EXPECT_NEAR((up.back() - up.front()) / double(up.size() - 1), 2 * std::numbers::pi / w,
              0.005 * 2 * std::numbers::pi / w);

  SimulatedDeviceOptions damped = o;
  damped.wrist_damping = 0.006;
  SimulatedDevice e(damped, kStill, Vec3::Zero(), {}, target);
  const double zeta = damped.wrist_damping / (2 * std::sqrt(o.wrist_stiffness * o.inertia_kgm2));
  const double wd = w * std::sqrt(1 - zeta * zeta);
  const std::vector<double> up_d = crossings(run(e, 200, Vec3::Zero()));
  ASSERT_GE(up_d.size(), 2u);
  EXPECT_NEAR(up_d[1] - up_d[0], 2 * std::numbers::pi / wd, 0.01 * 2 * std::numbers::pi / wd);
}

// A NaN or infinite torque is no torque: the handle does not turn.
TEST(DeviceRotation, NonFiniteTorqueTurnsNothing) {
  SimulatedDevice d(free_handle(), kStill, Vec3::Zero());
  for (const Vec3& t : {Vec3(NAN, 0, 0), Vec3(0, INFINITY, 0), Vec3(0, 0, -INFINITY)}) {
    const std::vector<DeviceState> s = run(d, 10, t);
    EXPECT_EQ(s.back().orientation.coeffs(), Quat::Identity().coeffs());
    EXPECT_EQ(s.back().angular_velocity, Vec3::Zero());
    EXPECT_EQ(d.last_torque(), Vec3::Zero());
  }
}

// Held rigidly (infinite wrist stiffness), the handle reads each tick's target and the target's
// rate, whatever the torque; a compliant wrist following the same turn settles on its rate too
// (the damper acts on the velocity relative to the target's).
TEST(DeviceRotation, FollowsTurningTargets) {
  const double rate = 2.0;  // [rad/s] about z
  std::vector<Quat> targets;
  for (int k = 0; k <= 400; ++k) targets.push_back(Quat(Eigen::AngleAxisd(rate * k * 1e-3, Vec3::UnitZ())));
  SimulatedDeviceOptions o;
  o.wrist_stiffness = INFINITY;
  o.spec.max_torque_nm = 0.2;
  SimulatedDevice rigid(o, kStill, Vec3::Zero(), {}, targets);
  const std::vector<DeviceState> s = run(rigid, 300, Vec3(0.1, 0.1, 0.1));
  EXPECT_NEAR(angle_about(s[300].orientation, Vec3::UnitZ()), rate * 0.3, 1e-12);
  EXPECT_LT((s[300].angular_velocity - Vec3(0, 0, rate)).norm(), 1e-9);
  EXPECT_EQ(rigid.wrist_torque(), Vec3::Zero());

  o.wrist_stiffness = 1.0;
  SimulatedDevice compliant(o, kStill, Vec3::Zero(), {}, targets);
  const std::vector<DeviceState> c = run(compliant, 400, Vec3::Zero());
  EXPECT_LT((c[400].angular_velocity - Vec3(0, 0, rate)).norm(), 1e-3 * rate);
  EXPECT_NEAR(angle_about(c[400].orientation, Vec3::UnitZ()), rate * 0.4, 1e-4) << "no lag left";
}

TEST(DeviceRotation, RefusesBadRotationalSettings) {
  auto refused = [](SimulatedDeviceOptions o, std::vector<Quat> targets, const std::string& reason) {
    try {
      SimulatedDevice d(o, kStill, Vec3::Zero(), {}, targets);
      ADD_FAILURE() << "accepted: " << reason;
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
    }
  };
  SimulatedDeviceOptions o;
  o.inertia_kgm2 = 0;
  refused(o, {}, "inertia_kgm2");
  o = {}, o.wrist_stiffness = -1;
  refused(o, {}, "wrist_stiffness");
  o = {}, o.wrist_damping = NAN;
  refused(o, {}, "wrist_damping");
  refused({}, {Quat::Identity(), Quat(0, 0, 0, 0)}, "orientation target of tick 1");
  refused({}, {Quat(NAN, 0, 0, 1)}, "orientation target of tick 0");
}

// A recording that turns about a fixed axis at a known rate, its quaternions written unnormalised
// and with the sign of q flipped on some rows (the same rotation): read back unit, with the
// recorded orientations and the rate by backward difference.
TEST(ReplayOrientation, RoundTripsOrientationAndAngularVelocity) {
  const std::string path = (std::filesystem::temp_directory_path() / "hdm_replay_orientation.csv").string();
  const Vec3 axis = Vec3(1, -2, 2) / 3;
  const double rate = 3.0, dt = 1e-3;  // [rad/s], [s]
  {
    std::ofstream f(path);
    f << "time_s,device_x_m,device_y_m,device_z_m,tool_on,device_qw,device_qx,device_qy,device_qz\n";
    for (int k = 0; k < 20; ++k) {
      Quat q(Eigen::AngleAxisd(0.4 + rate * k * dt, axis));
      q.coeffs() *= (k % 3 == 1 ? -2.5 : 1.0);
      char line[256];
      std::snprintf(line, sizeof line, "%.17g,0,0,0,0,%.17g,%.17g,%.17g,%.17g\n", k * dt, q.w(), q.x(), q.y(), q.z());
      f << line;
    }
  }
  ReplayDevice d(path);
  std::filesystem::remove(path);
  DeviceState s;
  for (int k = 0; d.begin_frame(s); ++k) {
    const Quat expected(Eigen::AngleAxisd(0.4 + rate * k * dt, axis));
    EXPECT_NEAR(s.orientation.norm(), 1, 1e-15);
    EXPECT_LT(s.orientation.angularDistance(expected), 1e-12) << "row " << k;
    const Vec3 w = k == 0 ? Vec3::Zero() : Vec3(rate * axis);
    EXPECT_LT((s.angular_velocity - w).norm(), 1e-9) << "row " << k;
    d.end_frame(Vec3::Zero());
  }

  ReplayDevice plain = ReplayDevice::from_csv("time_s,device_x_m,device_y_m,device_z_m\n0,0,0,0\n0.001,0,0,0\n", "p");
  for (; plain.begin_frame(s); plain.end_frame(Vec3::Zero())) {
    EXPECT_EQ(s.orientation.coeffs(), Quat::Identity().coeffs());
    EXPECT_EQ(s.angular_velocity, Vec3::Zero());
  }
}

TEST(ReplayOrientation, RefusesBadQuaternionsNamingFileAndLine) {
  const std::string header = "time_s,device_x_m,device_y_m,device_z_m,device_qw,device_qx,device_qy,device_qz\n";
  auto refused = [&](const std::string& text, const std::string& reason) {
    try {
      ReplayDevice::from_csv(text, "q.csv");
      ADD_FAILURE() << "accepted: " << reason;
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
    }
  };
  refused(header + "0,0,0,0,1,0,0,0\n0.001,0,0,0,0,0,0,0\n", "q.csv:3: orientation");
  refused(header + "0,0,0,0,1,0,0,0\n0.001,0,0,0,0,0,0,0\n", "zero quaternion");
  refused(header + "0,0,0,0,nan,0,0,1\n", "q.csv:2: orientation");
  refused(header + "0,0,0,0,1,0,inf,0\n", "not a finite quaternion");
  refused(header + "0,0,0,0,1,0,0,1e999\n", "not a finite quaternion");
  refused("time_s,device_x_m,device_y_m,device_z_m,device_qw,device_qx,device_qy\n0,0,0,0,1,0,0\n",
          "q.csv: header lacks column device_qz");
}

}  // namespace
}  // namespace hdm
