// SPDX-License-Identifier: MIT
// The rigid tool drills: a SculptSession with RenderMode::RigidTool and the drill brush, its burr held
// upright on a flat sheet (z = 0, millimetres) by a device that reports a fixed pose d below the rest
// pose. The coupling's equilibrium gives the head's normal force analytically, F = k_t·d, and the
// removal is checked against Archard's law V = K·F·ω·r·Δt / H computed here (Archard 1953), the
// volume measured from the displaced surface (test::removed_volume), independently of the kernel.
#include <hdm/session/sculpt_session.h>

#include "../support/flat_sheet.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <numbers>
#include <vector>

namespace hdm {
namespace {

constexpr double kBurrRadius = 1.5;  // burr head radius [mm]
constexpr double kStiffness = 1000;  // coupling k_t [N/m]
constexpr double kWear = 0.01, kRpm = 200000;
constexpr int kDescent = 200, kSettle = 100, kDrill = 101;  // ticks at 1 kHz
constexpr double kX = 0.3, kY = -0.2;                       // the tip's x, y [mm]

// A handle held rigidly on a scripted pose: the tip on the path [m], upright, at rest; the tool
// button held on the ticks that say so.
class HeldDevice : public HapticDevice {
 public:
  HeldDevice(std::vector<Vec3> path, std::vector<uint32_t> buttons)
      : path_(std::move(path)), buttons_(std::move(buttons)) {}
  bool begin_frame(DeviceState& s) noexcept override {
    if (k_ >= path_.size()) return false;
    s = DeviceState{};
    s.position = path_[k_];
    s.buttons = buttons_[k_];
    s.time_s = 1e-3 * double(k_++);
    return true;
  }
  using HapticDevice::end_frame;
  void end_frame(const Vec3&) noexcept override {}
  DeviceSpec spec() const noexcept override { return {}; }

 private:
  std::vector<Vec3> path_;
  std::vector<uint32_t> buttons_;
  size_t k_ = 0;
};

// Archard's volume [mm³] for force @p force [N] over @p seconds on hardness @p hv [HV].
double archard(double force, double seconds, double hv) {
  const double speed = 2 * std::numbers::pi * kRpm / 60 * (kBurrRadius / test::kSheetUnits);  // ω·r [m/s]
  const double m3 = kWear * force * speed * seconds / vickers_to_pa(hv);
  return m3 * 1e9;
}

struct DrillRun {
  double removed = 0;     // [mm³]
  double head_force = 0;  // mean SessionTick::head_force_n over the drilling ticks [N]
};

// The burr lowered from 0.3 mm above the sheet to a pose @p depth_mm below its rest pose, settled,
// then drilling for kDrill ticks with the tool button held.
DrillRun drill(double depth_mm, float hardness_hv) {
  SlabModel m = test::flat_sheet();
  m.hardness.assign(m.hardness.size(), hardness_hv);
  std::vector<Vec3> before;
  std::vector<Tri> faces;
  displaced_surface(m, before, faces);
  Workspace ws;
  ws.scale = test::kSheetUnits;
  SessionOptions o;
  o.mode = RenderMode::RigidTool;
  o.publish = false;
  o.tool = burr_shell(kBurrRadius);
  o.head_radius = kBurrRadius;
  o.rigid.stiffness = kStiffness;
  o.rigid.damping = 0;
  o.rigid.rot_damping = 0;
  o.rigid.band = 0.05;  // [mm], well inside the sheet's 1 mm outer shell
  SculptSession session(std::move(m), ws, o);
  Brush b;
  b.tool = BrushTool::Drill;
  b.radius = kBurrRadius;
  b.falloff = Falloff::Smooth;
  b.wear_coefficient = kWear;
  b.rpm = kRpm;
  session.set_brush(b);
  std::vector<Vec3> path;
  std::vector<uint32_t> buttons;
  const double top = kBurrRadius + 0.3, held = kBurrRadius - depth_mm;  // the tip's z [mm]
  for (int k = 1; k <= kDescent; ++k) path.emplace_back(kX, kY, top + (held - top) * k / kDescent);
  for (int k = 0; k < kSettle + kDrill + 5; ++k) path.emplace_back(kX, kY, held);
  for (Vec3& p : path) p /= test::kSheetUnits;
  buttons.assign(path.size(), 0);
  std::fill(buttons.begin() + kDescent + kSettle, buttons.begin() + kDescent + kSettle + kDrill, 1u);
  HeldDevice device(path, buttons);
  DrillRun run;
  ServoTick t;
  for (size_t k = 0; k < path.size(); ++k) {
    t.tick = static_cast<int64_t>(k);
    t.time_s = 1e-3 * double(k);
    const SessionTick r = session.tick(device, t);
    if (r.tool_on) run.head_force += r.head_force_n / kDrill;
  }
  session.finish();
  run.removed = test::removed_volume(session.model(), before);
  return run;
}

// At equal force, the removed volume is Archard's for each hardness, and the ratio of the volumes
// is the inverse ratio of the hardnesses.
TEST(RigidDrill, RemovalScalesWithTheInverseHardness) {
  const double seconds = 1e-3 * (kDrill - 1);  // the stroke's first sample has no elapsed time
  const DrillRun enamel = drill(1.0, 300), dentin = drill(1.0, 55);
  const double force = kStiffness * 1.0e-3;  // k_t·d at equilibrium [N]
  std::printf(
      "rigid drill: 1 N, 100 ms: enamel %.6g mm3 (Archard %.6g), dentin %.6g mm3 (Archard %.6g), "
      "ratio %.4g (hardness ratio %.4g); head force %.4f / %.4f N\n",
      enamel.removed, archard(force, seconds, 300), dentin.removed, archard(force, seconds, 55),
      dentin.removed / enamel.removed, 300.0 / 55, enamel.head_force, dentin.head_force);
  EXPECT_NEAR(enamel.head_force / force, 1.0, 0.02) << "the head's contact force is the coupling's k_t·d";
  EXPECT_NEAR(enamel.removed / archard(force, seconds, 300), 1.0, 0.05);
  EXPECT_NEAR(dentin.removed / archard(force, seconds, 55), 1.0, 0.05);
  EXPECT_NEAR(dentin.removed / enamel.removed / (300.0 / 55), 1.0, 0.05);
}

// Removal grows linearly with the held force: each volume is Archard's within 5 %, and the
// least-squares slope is Archard's volume per newton.
TEST(RigidDrill, RemovalGrowsLinearlyWithForce) {
  const double seconds = 1e-3 * (kDrill - 1);
  std::vector<double> f, v;
  for (double d = 0.5; d <= 2.5 + 1e-9; d += 0.5) {
    const DrillRun run = drill(d, 300);
    const double force = kStiffness * d * 1e-3;
    EXPECT_NEAR(run.head_force / force, 1.0, 0.02) << d;
    EXPECT_NEAR(run.removed / archard(force, seconds, 300), 1.0, 0.05) << d;
    f.push_back(force);
    v.push_back(run.removed);
  }
  const double n = double(f.size());
  double sf = 0, sv = 0, sff = 0, sfv = 0;
  for (size_t k = 0; k < f.size(); ++k) sf += f[k], sv += v[k], sff += f[k] * f[k], sfv += f[k] * v[k];
  const double slope = (n * sfv - sf * sv) / (n * sff - sf * sf), per_newton = archard(1.0, seconds, 300);
  std::printf("rigid drill: 0.5-2.5 N, 100 ms: slope %.6g mm3/N, Archard %.6g mm3/N\n", slope, per_newton);
  EXPECT_NEAR(slope / per_newton, 1.0, 0.05);
}

}  // namespace
}  // namespace hdm
