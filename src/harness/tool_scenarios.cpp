// SPDX-License-Identifier: MIT
#include <hdm/core/error.h>
#include <hdm/core/percentile.h>
#include <hdm/haptics/sphere_proxy.h>

#include "angle_deg.h"
#include "tool_scenario_detail.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace hdm {
namespace {

constexpr double kR = 0.3;  // the ball's radius [model units]
constexpr double kScale = harness::detail::kToolScale;
constexpr double kSlotHalf = 0.2;  // the slot's half width [model units]
constexpr double kEdgeX = 1.0;     // the block's edge rolled over: x = 1, z = 0

using harness::detail::Block;

// The block's cells: all, or all but a slot |x| < 0.2 of depth 0.4 along y.
std::function<bool(int, int, int)> block_cells(bool slot) {
  return [slot](int i, int, int k) { return !(slot && k >= 6 && i >= 8 && i < 12); };
}

void check_options(const ToolScenarioOptions& o) {
  if (!(o.rate_hz >= 100 && o.rate_hz <= 1e6)) throw InvalidInput("tool scenario: rate_hz must be in [100, 1e6] Hz");
  if (!(o.press_force_n > 0) || !std::isfinite(o.press_force_n))
    throw InvalidInput("tool scenario: press_force_n must be positive and finite");
  if (!(o.speed_m_s > 0) || !std::isfinite(o.speed_m_s))
    throw InvalidInput("tool scenario: speed_m_s must be positive and finite");
  if (!(o.proxy.force.max_force > 0)) throw InvalidInput("tool scenario: the maximum force must be positive");
}

// How far [model units] the hand target lies beyond the ball's rest pose for the hand to push
// with @p force: the hand's spring and the rendered stiffness in series.
double press_offset(const ToolScenarioOptions& o, double force) {
  return force * (1 / o.device.hand_stiffness + 1 / o.proxy.force.stiffness) * kScale;
}

// Slot: down from 0.3 above the ball's rest over the slot's middle to the pressing pose in 0.3 s,
// then held for 0.3 s. @p hold_from is the first tick of the hold.
std::vector<Vec3> slot_path(const ToolScenarioOptions& o, size_t& hold_from) {
  const double rest = std::sqrt(kR * kR - kSlotHalf * kSlotHalf);
  const double low = rest - press_offset(o, o.press_force_n), high = rest + 0.3;
  const int down = int(std::lround(0.3 * o.rate_hz)), hold = int(std::lround(0.3 * o.rate_hz));
  std::vector<Vec3> path;
  for (int k = 0; k <= down + hold; ++k)
    path.emplace_back(0.0, 0.05, high + (low - high) * std::min(1.0, double(k) / down));
  hold_from = size_t(down) + 1;
  return path;
}

// RollEdge: the hand target runs pressed (offset d) along the top from x = 0.4 to the edge, round
// it on a quarter circle of radius r − d about the edge, down the side face to z = −0.6; first it
// comes down onto the top in 0.2 s and stays 0.2 s. @p roll_from is the first tick of the roll.
std::vector<Vec3> roll_path(const ToolScenarioOptions& o, size_t& roll_from) {
  const double d = press_offset(o, o.press_force_n), a = kR - d;
  const double step = o.speed_m_s * kScale / o.rate_hz;  // [model units per tick]
  std::vector<Vec3> path;
  const Vec3 start(0.4, 0.05, a), above(0.4, 0.05, kR + 0.2);
  const int down = int(std::lround(0.2 * o.rate_hz));
  for (int k = 1; k <= 2 * down; ++k) path.push_back(above + (start - above) * std::min(1.0, double(k) / down));
  roll_from = path.size();
  for (double x = start.x(); x < kEdgeX; x += step) path.emplace_back(x, 0.05, a);
  const double arc = 0.5 * std::numbers::pi * a;
  for (double s = 0; s < arc; s += step) {
    const double t = s / a;  // from straight up (t = 0) to straight out (t = π/2)
    path.emplace_back(kEdgeX + a * std::sin(t), 0.05, a * std::cos(t));
  }
  for (double z = 0; z > -0.6; z -= step) path.emplace_back(kEdgeX + a, 0.05, z);
  return path;
}

// The per-tick scores of a run, accumulated.
struct Scores {
  std::vector<double> normal_error;
  Vec3 f_prev = Vec3::Zero();
  bool prev_contact = false;
  double force_sum = 0;
  double max_force = 1;   // the device's limit [N], the step's scale
  size_t steps_from = 0;  // force steps are scored from this tick on (the hold, or the roll)
};

// Penetration on every tick in contact; force steps from Scores::steps_from on; the normal error
// where one plane holds the ball (the direction to the closest point is then the contact normal).
void score_tick(const Block& b, const SphereProxyState& st, const Vec3& force, Scores& s, ToolScenarioReport& r) {
  if (!st.contact) {
    s.prev_contact = false;
    return;
  }
  ++r.contact_ticks;
  const double f = force.norm();
  s.force_sum += f;
  r.max_force_n = std::max(r.max_force_n, f);
  const ClosestPoint cp = b.reference.closest_point(st.center);
  const bool inside = b.reference.inside(st.center);
  const double depth = inside ? kR + cp.distance : kR - cp.distance;
  r.max_penetration_pct_r = std::max(r.max_penetration_pct_r, 100 * std::max(0.0, depth) / kR);
  if (s.prev_contact && size_t(r.ticks) > s.steps_from) {
    r.max_force_step_pct = std::max(r.max_force_step_pct, 100 * (force - s.f_prev).norm() / s.max_force);
    if (f > 0.05 && s.f_prev.norm() > 0.05)
      r.max_direction_step_deg = std::max(r.max_direction_step_deg, harness::detail::angle_deg(force, s.f_prev));
  }
  if (f > 0.05 && cp.distance > 0 && st.planes == 1)
    s.normal_error.push_back(harness::detail::angle_deg(force, st.center - cp.point));
  s.f_prev = force;
  s.prev_contact = true;
}

}  // namespace

namespace {

// Each tool scenario with the name hdm feel's --scenario and Python spell it.
struct NamedScenario {
  ToolScenario scenario;
  const char* name;
};
constexpr NamedScenario kToolScenarios[] = {{ToolScenario::Slot, "slot"},
                                            {ToolScenario::RollEdge, "roll_edge"},
                                            {ToolScenario::ShaftEdge, "shaft_edge"},
                                            {ToolScenario::DrillLayers, "drill_layers"}};

}  // namespace

ToolScenario parse_tool_scenario(const std::string& name) {
  for (const NamedScenario& s : kToolScenarios)
    if (name == s.name) return s.scenario;
  throw InvalidInput("tool scenario '" + name + "': expected slot, roll_edge, shaft_edge or drill_layers");
}

bool is_tool_scenario(const std::string& name) noexcept {
  for (const NamedScenario& s : kToolScenarios)
    if (name == s.name) return true;
  return false;
}

const char* tool_scenario_name(ToolScenario scenario) noexcept {
  for (const NamedScenario& s : kToolScenarios)
    if (s.scenario == scenario) return s.name;
  return "?";
}

ToolScenarioReport run_tool_scenario(const ToolScenarioOptions& options) {
  check_options(options);
  ToolScenarioOptions o = options;
  if (o.scenario == ToolScenario::ShaftEdge) return harness::detail::run_shaft_edge(o);
  if (o.scenario == ToolScenario::DrillLayers) return harness::detail::run_drill_layers(o);
  const bool slot = o.scenario == ToolScenario::Slot;
  const Block b(block_cells(slot));
  Workspace ws;
  ws.scale = kScale;
  SphereProxyParams p;
  p.proxy = o.proxy;
  p.proxy.friction_scale = 0;
  p.radius = kR;
  Scores s;
  std::vector<Vec3> path = slot ? slot_path(o, s.steps_from) : roll_path(o, s.steps_from);
  for (Vec3& x : path) x = ws.to_device(x);
  o.device.rate_hz = o.rate_hz;
  o.device.spec.max_force_n = o.proxy.force.max_force;
  SimulatedDevice device(o.device, path, path.front());
  SphereProxyState st;
  ToolScenarioReport r;
  r.scenario = tool_scenario_name(o.scenario);
  r.rate_hz = o.rate_hz;
  r.radius = kR;
  s.max_force = o.proxy.force.max_force;
  harness::detail::EnergyTally energy;
  for (size_t k = 0; k < path.size(); ++k) {
    DeviceState ds;
    device.begin_frame(ds);
    const ProxyOutput out = sphere_proxy_step(b.model, b.locator, ws, ds.position, ds.velocity, p, st);
    device.end_frame(out.force);
    energy.add(ds.position, Vec3::Zero(), out.force, Vec3::Zero());
    ++r.ticks;
    score_tick(b, st, out.force, s, r);
    r.entered = r.entered || (slot && st.center.z() < 0);
    if (o.keep_trace) r.centre.push_back(st.center), r.force.push_back(out.force);
  }
  r.mean_contact_force_n = r.contact_ticks > 0 ? s.force_sum / double(r.contact_ticks) : 0.0;
  r.energy_ratio = energy.ratio();
  r.normal_error_p95_deg = percentile(s.normal_error, 0.95);
  for (double e : s.normal_error) r.normal_error_max_deg = std::max(r.normal_error_max_deg, e);
  const double rest = std::sqrt(kR * kR - kSlotHalf * kSlotHalf);
  r.rest_height_error_pct_r = slot ? 100 * std::abs(st.center.z() - rest) / kR : 0.0;
  r.note = slot ? "ball r = 0.3 pressed over a slot 0.4 wide (2r = 0.6) with the hand's force, then held; rest "
                  "height sqrt(r^2 - 0.2^2) = " +
                      std::to_string(rest)
                : "ball r = 0.3 rolled over the block's convex edge (x = 1, z = 0): top, round the edge, side face";
  return r;
}

}  // namespace hdm
