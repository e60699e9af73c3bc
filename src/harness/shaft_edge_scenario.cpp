// SPDX-License-Identifier: MIT
// ToolScenario::ShaftEdge: a rigid burr whose head rests on a floor while its shaft leans on an
// edge, scored against the lever-arm reference of the two contacts.
#include <hdm/haptics/rigid_tool.h>

#include "tool_scenario_detail.h"

#include <cmath>
#include <numbers>
#include <string>

namespace hdm::harness::detail {
namespace {

constexpr double kHead = 0.1;                         // burr head radius [model units]
constexpr double kShaft = 0.4 * kHead;                // shaft radius
constexpr double kFloor = -0.4;                       // the pit's floor, x > 0
constexpr double kLean = std::numbers::pi / 4;        // the tool's lean from +z towards -x at rest [rad]
constexpr double kPush = 5 * std::numbers::pi / 180;  // the hand leans it 5° further
constexpr double kY = 0.05;                           // the tool's plane y = 0.05

// The rotation of the tool's +z to lean @p a from +z towards -x.
Eigen::Quaterniond lean(double a) { return Eigen::Quaterniond(Eigen::AngleAxisd(-a, Vec3::UnitY())); }

// The hand's path: the tip from 0.3 above its rest pose (head on the floor, shaft on the edge at
// kLean) down to 0.05 below it and 0.03 towards the edge in 0.3 s, then held for 0.4 s.
std::vector<Vec3> shaft_path(double rate_hz) {
  const double h = kFloor + kHead;  // the tip's height on the floor
  // The axis through the tip (x, h) along (-sin, cos) passes kShaft above the edge (0, 0).
  const double x = (-h * std::sin(kLean) + kShaft) / std::cos(kLean);
  const Vec3 rest(x, kY, h), from = rest + Vec3(0, 0, 0.3), to = rest + Vec3(-0.03, 0, -0.05);
  const int down = int(std::lround(0.3 * rate_hz)), hold = int(std::lround(0.4 * rate_hz));
  std::vector<Vec3> path;
  for (int k = 0; k <= down + hold; ++k) path.push_back(from + (to - from) * std::min(1.0, double(k) / down));
  return path;
}

// Shell points pushing the god-object, on the head and on the shaft.
void count_contacts(const ToolShell& shell, const RigidToolState& st, ToolScenarioReport& r) {
  r.head_contacts = r.shaft_contacts = 0;
  for (int k = 0; k < st.row_count; ++k) {
    if (!(st.rows[k].lambda > 0)) continue;
    const bool head = shell.points[st.rows[k].point].norm() <= kHead * (1 + 1e-9);
    (head ? r.head_contacts : r.shaft_contacts) += 1;
  }
}

// The lever-arm reference: the edge point c in the tool's plane, the shaft's normal there (from c
// to the axis), the edge's share of the force along it (the floor's contact takes the rest along
// +z, frictionless), and its moment (c − tip) × F_edge about the tip [N·m].
Vec3 reference_torque(const ToolScenarioReport& r) {
  const Vec3 c(0, r.tool_tip.y(), 0);
  const Vec3 on_axis = r.tool_tip + (c - r.tool_tip).dot(r.tool_axis) * r.tool_axis;
  const Vec3 n = (on_axis - c).normalized();
  const Vec3 edge_force = (r.tool_force.x() / n.x()) * n;
  return ((c - r.tool_tip) / kToolScale).cross(edge_force);
}

}  // namespace

ToolScenarioReport run_shaft_edge(const ToolScenarioOptions& o) {
  const Block b([](int i, int, int k) { return !(i >= 10 && k >= 6); });  // the pit x > 0, z > -0.4
  Workspace ws;
  ws.scale = kToolScale;
  const ToolShell shell = burr_shell(kHead);
  RigidToolParams p;
  p.stiffness = o.proxy.force.stiffness;
  p.max_force = o.proxy.force.max_force;
  p.solver = o.proxy.solver;
  std::vector<Vec3> path = shaft_path(o.rate_hz);
  for (Vec3& x : path) x = ws.to_device(x);
  SimulatedDeviceOptions d = o.device;
  d.rate_hz = o.rate_hz;
  d.spec.max_force_n = p.max_force;
  d.spec.max_torque_nm = p.max_torque;
  d.orientation = lean(kLean + kPush);  // the wrist's target: the handle yields to the torque by τ/k_wrist
  SimulatedDevice device(d, path, path.front());
  auto state = std::make_unique<RigidToolState>();
  ToolScenarioReport r;
  r.scenario = tool_scenario_name(o.scenario);
  r.rate_hz = o.rate_hz;
  r.radius = kHead;
  const size_t held_from = path.size() - size_t(std::lround(0.1 * o.rate_hz));
  Vec3 tip = Vec3::Zero(), axis = Vec3::Zero(), force = Vec3::Zero(), torque = Vec3::Zero();
  EnergyTally energy;
  Eigen::Quaterniond turned_from = Eigen::Quaterniond::Identity();
  for (size_t k = 0; k < path.size(); ++k) {
    DeviceState ds;
    device.begin_frame(ds);
    const ToolWrench w = rigid_tool_step(b.model, b.locator, ws, shell, ToolPose{ds.position, ds.orientation},
                                         ToolTwist{ds.velocity, ds.angular_velocity}, p, *state);
    device.end_frame(w.force, w.torque);
    // The handle's turn since the last tick, as a rotation vector in the device frame.
    const Eigen::AngleAxisd turn(ds.orientation * (k ? turned_from.conjugate() : ds.orientation.conjugate()));
    turned_from = ds.orientation;
    energy.add(ds.position, turn.angle() * turn.axis(), w.force, w.torque);
    ++r.ticks;
    r.contact_ticks += w.contacts > 0;
    r.max_force_n = std::max(r.max_force_n, w.force.norm());
    if (k < held_from) continue;
    tip += state->position, axis += state->orientation * Vec3::UnitZ(), force += w.force, torque += w.torque;
  }
  r.energy_ratio = energy.ratio();
  const double held = double(path.size() - held_from);
  r.tool_tip = tip / held, r.tool_axis = axis.normalized(), r.tool_force = force / held, r.tool_torque = torque / held;
  count_contacts(shell, *state, r);
  const Vec3 ref = reference_torque(r);
  r.torque_error_pct = 100 * (r.tool_torque - ref).norm() / ref.norm();
  r.torque_sense_ok = r.tool_torque.dot(ref) > 0;
  r.rest_height_error_pct_r = 100 * std::abs(r.tool_tip.z() - (kFloor + kHead)) / kHead;
  r.note =
      "burr (head r = 0.1, shaft 0.04) held 50 deg from vertical: head on the pit's floor z = -0.4, shaft on "
      "its edge x = 0, z = 0; torque about the tip against (c - tip) x F_edge";
  return r;
}

}  // namespace hdm::harness::detail
