// SPDX-License-Identifier: MIT
// Rigid tool (6-DOF god-object) tests against analytic geometry: a burr pressed onto the flat top
// of a block (z = 0, normal +z), whose rest pose, force direction and lever arm follow from the
// burr's analytic shape, not from the shell the code queries.
#include "haptics/haptics_fixtures.h"

#include <hdm/core/error.h>
#include <hdm/haptics/rigid_tool.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <numbers>

namespace hdm {
namespace {

using test::angle_deg;

constexpr double kR = 0.1;           // burr head radius [model units]: 1 cm at the device
constexpr double kShaft = 0.4 * kR;  // shaft radius
const double kZ0 = std::sqrt(kR * kR - kShaft * kShaft);
const double kEnd = kZ0 + 8 * kR;  // the shaft's end along the tool's +z

// A block [-1,1]² × [-1,0] from cubes of 0.1, 10 model units per metre (0.2 m wide at the device).
struct Block {
  Block()
      : baked(test::voxel_surface(20, 20, 10, 0.1, Vec3(-1, -1, -1), [](int, int, int) { return true; }), "block", 500,
              8) {
    ws.scale = 10;
  }
  test::BakedMesh baked;
  Workspace ws;
};

const Block& block() {
  static const Block b;
  return b;
}

RigidToolParams params() {
  RigidToolParams p;
  p.damping = 0;
  p.rot_damping = 0;
  return p;
}

// The lowest of the shell's points at the god-object's pose [model units]: how far the points the
// solve constrains went below the face z = 0.
double lowest_point(const ToolShell& shell, const RigidToolState& st) {
  double low = INFINITY;
  for (const Vec3& p : shell.points) low = std::min(low, (st.position + st.orientation * p).z());
  return low;
}

// The shell's point spacing sqrt(area / #P) [model units]: the resolution of a contact's position.
double spacing(const ToolShell& shell) {
  const double area = 2 * std::numbers::pi * kR * (kR + kZ0) + 2 * std::numbers::pi * kShaft * 8 * kR +
                      std::numbers::pi * kShaft * kShaft;
  return std::sqrt(area / double(shell.points.size()));
}

// The torque of @p out is the moment about the device's tip @p tip of its force acting at @p c
// [model units], (c − tip) × F, within 5 %; the contact has a lever arm across the force of at
// least 0.15 (1.5 cm at the device), so the moment is not a vanishing one.
void expect_moment_about(const ToolWrench& out, const Vec3& c, const Vec3& tip, const Workspace& ws) {
  const Vec3 expected = ((c - tip) / ws.scale).cross(out.force);  // [m] × [N]
  ASSERT_GT(expected.norm(), 0.15 / ws.scale * out.force.norm()) << "the contact must have a lever arm";
  EXPECT_LT((out.torque - expected).norm(), 0.05 * expected.norm())
      << "torque " << out.torque.transpose() << " vs r x F " << expected.transpose();
}

// Runs ticks with the device's tip moving from @p from to @p to [model units] over @p ramp ticks,
// then held for @p hold ticks, at orientation @p q; returns the last wrench.
ToolWrench press(const Block& b, const ToolShell& shell, const Eigen::Quaterniond& q, const Vec3& from, const Vec3& to,
                 int ramp, int hold, RigidToolState& st, double* worst_low = nullptr) {
  // worst_low: the lowest shell point over the ticks [model units]
  const RigidToolParams p = params();
  ToolWrench out;
  for (int k = 0; k <= ramp + hold; ++k) {
    ToolPose d;
    d.position = b.ws.to_device(from + (to - from) * std::min(1.0, double(k) / ramp));
    d.orientation = q;
    out = rigid_tool_step(b.baked.model, b.baked.locator, b.ws, shell, d, ToolTwist{}, p, st);
    if (worst_low) *worst_low = std::min(*worst_low, lowest_point(shell, st));
  }
  return out;
}

// Upright burr (shaft up) pressed 0.02 below its rest height onto the top face: no shell point goes
// below the face by more than 1 % of r on any tick, the god-object's head rests on the face (centre
// r above it), the force is k·(r − z_device)/scale along +z, and the torque about the tip is that of
// a contact straight below it, zero, up to the shell's resolution: a force F at a point at most half
// the point spacing h off the axis (h = 0.18 r for 1,000 points).
TEST(RigidTool, HeadPressedOntoAFacePushesAlongItsNormal) {
  const Block& b = block();
  const ToolShell shell = burr_shell(kR);
  auto st = std::make_unique<RigidToolState>();
  const Vec3 over(0.23, -0.17, 0);
  double lowest = INFINITY;
  const ToolWrench out = press(b, shell, Eigen::Quaterniond::Identity(), over + Vec3(0, 0, kR + 0.1),
                               over + Vec3(0, 0, kR - 0.02), 200, 100, *st, &lowest);
  ASSERT_EQ(out.status, ForceStatus::Contact);
  EXPECT_GT(lowest, -0.01 * kR) << "a shell point went below the face";
  EXPECT_NEAR(st->position.z(), kR, 0.02 * kR) << "the head rests on the face";
  EXPECT_NEAR(st->position.x(), over.x(), 1e-3 * kR);
  EXPECT_NEAR(st->position.y(), over.y(), 1e-3 * kR);
  EXPECT_LT(angle_deg(out.force, Vec3::UnitZ()), 1.0);
  const double expected = 1000 * 0.02 / b.ws.scale;  // k·depth [N]
  EXPECT_NEAR(out.force.norm(), expected, 0.03 * expected);
  EXPECT_LT(out.torque.norm(), 0.5 * spacing(shell) / b.ws.scale * out.force.norm()) << "contact below the tip";
}

// The burr upside down (shaft down) and tilted 50° about y: only the rim of the shaft's end touches
// the face, about 0.7 (7 cm) to the side of the tip. Held there, the torque about the device's tip
// is the moment of the force at that contact, (c − tip) × F, within 5 %; the force is normal to the
// face; no shell point goes below it by more than 1 % of r, and the analytic rim by no more than the
// sag of the shell's sampling between two points (5 % of r).
TEST(RigidTool, TorqueIsTheContactForcesMomentAboutTheDevicePoint) {
  const Block& b = block();
  const ToolShell shell = burr_shell(kR);
  const double tilt = 50 * std::numbers::pi / 180;
  const Eigen::Quaterniond q = Eigen::Quaterniond(Eigen::AngleAxisd(tilt, Vec3::UnitY())) *
                               Eigen::Quaterniond(Eigen::AngleAxisd(std::numbers::pi, Vec3::UnitX()));
  // The lowest point of the end's rim for a pose (tip, R): the end's centre plus the shaft radius
  // along the rim's steepest descent (the axis points down, so no other point of the tool is lower).
  auto rim_low = [](const Vec3& tip, const Eigen::Matrix3d& R) {
    const Vec3 centre = tip + kEnd * R.col(2), u = R.col(0), w = R.col(1);
    return Vec3(centre - kShaft * (u.z() * u + w.z() * w).normalized());
  };
  const Eigen::Matrix3d Rd = q.toRotationMatrix();
  const Vec3 tip_at_touch = Vec3(0.3, 0.1, 0) - rim_low(Vec3::Zero(), Rd);  // rim low point at (0.3, 0.1, 0)
  auto st = std::make_unique<RigidToolState>();
  const Vec3 to = tip_at_touch - Vec3(0, 0, 0.02);
  double lowest = INFINITY;
  const ToolWrench out = press(b, shell, q, tip_at_touch + Vec3(0, 0, 0.1), to, 300, 300, *st, &lowest);
  ASSERT_EQ(out.status, ForceStatus::Contact);
  const Vec3 c = rim_low(st->position, st->orientation.toRotationMatrix());
  EXPECT_GT(lowest, -0.01 * kR) << "a shell point went below the face";
  EXPECT_NEAR(c.z(), 0.0, 0.05 * kR) << "the rim rests on the face";
  EXPECT_LT(angle_deg(out.force, Vec3::UnitZ()), 2.0);
  expect_moment_about(out, c, to, b.ws);
}

// The upright burr slid 1.0 across the face, 0.01 below its rest height, while it tilts up to 25°
// about x and turns about its axis: the head is a sphere about the tip, so the god-object's tip
// stays r above the face (within 2 % of r) on every tick, no shell point goes below it by more
// than 1 % of r, and the frictionless force stays within 2° of the face normal.
TEST(RigidTool, SlidesAndTurnsOnAFaceWithTheHeadOnIt) {
  const Block& b = block();
  const ToolShell shell = burr_shell(kR);
  auto st = std::make_unique<RigidToolState>();
  const RigidToolParams p = params();
  const int n = 1500;
  double worst_height = 0, lowest = INFINITY, worst_angle = 0;
  for (int k = 0; k <= n; ++k) {
    const double u = std::max(0.0, (k - 200.0) / (n - 200.0));  // 200 ticks down, then across
    const double z = k < 200 ? kR + 0.05 - 0.06 * k / 200.0 : kR - 0.01;
    ToolPose d;
    d.position = b.ws.to_device(Vec3(-0.5 + u, 0.1, z));
    d.orientation =
        Eigen::Quaterniond(Eigen::AngleAxisd(25 * std::numbers::pi / 180 * std::sin(3 * u), Vec3::UnitX())) *
        Eigen::Quaterniond(Eigen::AngleAxisd(4 * u, Vec3::UnitZ()));
    const ToolWrench out = rigid_tool_step(b.baked.model, b.baked.locator, b.ws, shell, d, ToolTwist{}, p, *st);
    if (k < 200) continue;
    ASSERT_EQ(out.status, ForceStatus::Contact) << "tick " << k;
    worst_height = std::max(worst_height, std::abs(st->position.z() - kR));
    lowest = std::min(lowest, lowest_point(shell, *st));
    worst_angle = std::max(worst_angle, angle_deg(out.force, Vec3::UnitZ()));
  }
  EXPECT_LT(worst_height, 0.02 * kR) << "the tip's height above the face, minus r";
  EXPECT_GT(lowest, -0.01 * kR) << "a shell point went below the face";
  EXPECT_LT(worst_angle, 2.0) << "force direction vs the face normal [deg]";
}

// The shaft lying across the block's edge (x = 1, z = 0, along y), the head hanging beyond it: the
// tool rests on the edge at the point c = (1, y_tip, 0) of the edge in the tool's plane, so the
// torque about the device's tip is (c − tip) × F within 5 %, whatever the direction the rounded
// edge gives the force, and the shaft stays on the edge (its axis 0.4 r from it, within 5 % of r).
TEST(RigidTool, ShaftOnAnEdgeGivesTheMomentAboutTheEdgePoint) {
  const Block& b = block();
  const ToolShell shell = burr_shell(kR);
  const double phi = 30 * std::numbers::pi / 180;  // the shaft's elevation, rising towards -x
  const Vec3 axis(-std::cos(phi), 0, std::sin(phi)), up(std::sin(phi), 0, std::cos(phi));  // up: ⟂ axis
  const Eigen::Quaterniond q = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), axis);
  // The tip 0.3 beyond the edge, at the height that puts the edge (kShaft − press) below the axis.
  auto tip_for = [&](double press) {
    return Vec3(1.3, 0.05, ((kShaft - press) - 0.3 * std::sin(phi)) / std::cos(phi));
  };
  auto st = std::make_unique<RigidToolState>();
  const Vec3 to = tip_for(0.01);
  press(b, shell, q, tip_for(-0.05), to, 300, 300, *st);
  const RigidToolParams p = params();
  const ToolWrench out = rigid_tool_step(b.baked.model, b.baked.locator, b.ws, shell, ToolPose{b.ws.to_device(to), q},
                                         ToolTwist{}, p, *st);
  ASSERT_EQ(out.status, ForceStatus::Contact);
  const Vec3 c(1, to.y(), 0);
  const Vec3 god_axis = st->orientation * Vec3::UnitZ();
  const double edge_to_axis = (c - st->position).cross(god_axis).norm();
  EXPECT_NEAR(edge_to_axis, kShaft, 0.05 * kR) << "the shaft rests on the edge";
  expect_moment_about(out, c, to, b.ws);
}

// A hand that jumps from 0.2 above the face to 0.3 inside the block in one tick (past the shell's
// inner layer) and stays there: the god-object moves at most `band` per tick, so its head is caught
// on the face, where it rests (tip r above it, within 2 % of r), pushing up.
TEST(RigidTool, CatchesAFastEntry) {
  const Block& b = block();
  const ToolShell shell = burr_shell(kR);
  auto st = std::make_unique<RigidToolState>();
  ToolWrench out =
      press(b, shell, Eigen::Quaterniond::Identity(), Vec3(0.1, 0.2, kR + 0.2), Vec3(0.1, 0.2, kR + 0.2), 1, 0, *st);
  ASSERT_EQ(out.status, ForceStatus::Free);
  double lowest = INFINITY;
  out =
      press(b, shell, Eigen::Quaterniond::Identity(), Vec3(0.1, 0.2, -0.3), Vec3(0.1, 0.2, -0.3), 1, 200, *st, &lowest);
  EXPECT_NE(out.status, ForceStatus::Free);
  EXPECT_NEAR(st->position.z(), kR, 0.02 * kR);
  EXPECT_GT(lowest, -0.01 * kR) << "a shell point went below the face";
  EXPECT_LT(angle_deg(out.force, Vec3::UnitZ()), 1.0);
}

// Far above the block, moving and turning: no contact, zero wrench on every tick.
TEST(RigidTool, FreeSpaceGivesZeroWrench) {
  const Block& b = block();
  const ToolShell shell = burr_shell(kR);
  auto st = std::make_unique<RigidToolState>();
  for (int k = 0; k < 100; ++k) {
    ToolPose d;
    d.position = b.ws.to_device(Vec3(0.5 * std::sin(0.05 * k), 0.2, 0.5 + 0.002 * k));
    d.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.01 * k, Vec3(1, 1, 0).normalized()));
    const ToolWrench out = rigid_tool_step(b.baked.model, b.baked.locator, b.ws, shell, d, ToolTwist{}, params(), *st);
    ASSERT_EQ(out.status, ForceStatus::Free) << "tick " << k;
    EXPECT_EQ(out.force, Vec3::Zero());
    EXPECT_EQ(out.torque, Vec3::Zero());
  }
}

// Non-finite or out-of-range input in contact: zero wrench, BadInput, god-object unchanged.
TEST(RigidTool, BadInputGivesZeroWrenchAndKeepsState) {
  const Block& b = block();
  const ToolShell shell = burr_shell(kR);
  auto st = std::make_unique<RigidToolState>();
  press(b, shell, Eigen::Quaterniond::Identity(), Vec3(0, 0, kR + 0.05), Vec3(0, 0, kR - 0.02), 100, 10, *st);
  ASSERT_TRUE(st->contact);
  const Vec3 held = st->position;
  const Eigen::Quaterniond held_q = st->orientation;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Vec3 good = b.ws.to_device(Vec3(0, 0, kR - 0.02));
  auto check = [&](const ToolPose& d, const ToolTwist& v, const ToolShell& sh, const char* what) {
    const ToolWrench out = rigid_tool_step(b.baked.model, b.baked.locator, b.ws, sh, d, v, params(), *st);
    EXPECT_EQ(out.status, ForceStatus::BadInput) << what;
    EXPECT_EQ(out.force, Vec3::Zero()) << what;
    EXPECT_EQ(out.torque, Vec3::Zero()) << what;
    EXPECT_EQ(st->position, held) << what;
    EXPECT_EQ(st->orientation.coeffs(), held_q.coeffs()) << what;
  };
  check(ToolPose{Vec3(nan, 0, 0), Eigen::Quaterniond::Identity()}, ToolTwist{}, shell, "NaN position");
  check(ToolPose{good, Eigen::Quaterniond(nan, 0, 0, 0)}, ToolTwist{}, shell, "NaN orientation");
  check(ToolPose{good, Eigen::Quaterniond(0, 0, 0, 0)}, ToolTwist{}, shell, "zero quaternion");
  check(ToolPose{Vec3(10, 0, 0), Eigen::Quaterniond::Identity()}, ToolTwist{}, shell, "beyond the position limit");
  check(ToolPose{good, Eigen::Quaterniond::Identity()}, ToolTwist{Vec3::Zero(), Vec3(0, INFINITY, 0)}, shell,
        "infinite angular velocity");
  check(ToolPose{good, Eigen::Quaterniond::Identity()}, ToolTwist{}, ToolShell{}, "empty shell");
}

// The burr's points lie on its analytic surface (head sphere, shaft side, end disc), their normals
// point into it, and each part holds its share of the area.
TEST(ToolShell, BurrPointsLieOnTheBurrWithInwardNormals) {
  const int n = 1000;
  const ToolShell s = burr_shell(kR, n);
  ASSERT_EQ(s.points.size(), size_t(n));
  ASSERT_EQ(s.normals.size(), size_t(n));
  int head = 0, side = 0, end = 0;
  for (int i = 0; i < n; ++i) {
    const Vec3& p = s.points[i];
    const double rho = std::hypot(p.x(), p.y());
    const bool on_head = std::abs(p.norm() - kR) < 1e-9 && p.z() <= kZ0 + 1e-9;
    const bool on_side = std::abs(rho - kShaft) < 1e-9 && p.z() >= kZ0 - 1e-9 && p.z() <= kEnd + 1e-9;
    const bool on_end = std::abs(p.z() - kEnd) < 1e-9 && rho <= kShaft + 1e-9;
    ASSERT_TRUE(on_head || on_side || on_end) << "point " << i << ": " << p.transpose();
    head += on_head, side += on_side && !on_head, end += on_end && !on_side;
    EXPECT_NEAR(s.normals[i].norm(), 1.0, 1e-12);
    // A step along the inward normal enters the solid burr: in the head ball or the shaft's cylinder.
    const Vec3 in = p + 1e-3 * kR * s.normals[i];
    const bool inside = in.norm() < kR || (std::hypot(in.x(), in.y()) < kShaft && in.z() > 0 && in.z() < kEnd);
    EXPECT_TRUE(inside) << "point " << i;
  }
  const double a_head = 2 * std::numbers::pi * kR * (kR + kZ0), a_side = 2 * std::numbers::pi * kShaft * 8 * kR,
               a_end = std::numbers::pi * kShaft * kShaft, total = a_head + a_side + a_end;
  EXPECT_NEAR(double(head) / n, a_head / total, 0.01);
  EXPECT_NEAR(double(side) / n, a_side / total, 0.01);
  EXPECT_NEAR(double(end) / n, a_end / total, 0.01);
  EXPECT_THROW(burr_shell(0.0), InvalidInput);
  EXPECT_THROW(burr_shell(kR, kMaxToolPoints + 1), InvalidInput);
}

// Sampling a 2 × 1 × 1 box: every point on a face with the face's inward normal, each face holding
// its share of the area, the same shell on every call.
TEST(ToolShell, MeshSamplingIsAreaUniformAndDeterministic) {
  const TriangleMesh box = test::voxel_surface(2, 1, 1, 1.0, Vec3::Zero(), [](int, int, int) { return true; });
  const int n = 1000;
  const ToolShell s = sample_tool_shell(box, n);
  ASSERT_EQ(s.points.size(), size_t(n));
  int on_x_faces = 0;
  for (int i = 0; i < n; ++i) {
    const Vec3& p = s.points[i];
    const Vec3 c = p - Vec3(1, 0.5, 0.5);  // from the box's centre
    // The face the point is on: the coordinate at its bound (|c| = half the extent).
    const Vec3 half(1, 0.5, 0.5);
    int axis = -1;
    for (int a = 0; a < 3; ++a)
      if (std::abs(std::abs(c[a]) - half[a]) < 1e-12) axis = a;
    ASSERT_GE(axis, 0) << "point " << i << " is not on the box: " << p.transpose();
    Vec3 inward = Vec3::Zero();
    inward[axis] = c[axis] > 0 ? -1 : 1;
    EXPECT_LT((s.normals[i] - inward).norm(), 1e-12) << "point " << i;
    on_x_faces += axis == 0;
  }
  EXPECT_NEAR(double(on_x_faces) / n, 2.0 / 10.0, 0.01) << "the x faces hold 2 of the box's 10 units of area";
  const ToolShell again = sample_tool_shell(box, n);
  EXPECT_EQ(again.points, s.points);
  EXPECT_THROW(sample_tool_shell(TriangleMesh{}, n), InvalidInput);
  EXPECT_THROW(sample_tool_shell(box, 0), InvalidInput);
}

}  // namespace
}  // namespace hdm
