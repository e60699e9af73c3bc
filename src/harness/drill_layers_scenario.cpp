// SPDX-License-Identifier: MIT
// ToolScenario::DrillLayers: the rigid burr drilling enamel and dentin at equal force in a
// SculptSession, its removal scored against Archard's law (Archard 1953).
#include <hdm/edit/brush_registry.h>
#include <hdm/session/sculpt_session.h>

#include "tool_scenario_detail.h"

#include <cmath>
#include <numbers>
#include <string>

namespace hdm::harness::detail {
namespace {

constexpr double kScale = 100;                 // model units per metre: the 2-unit block is 2 cm wide
constexpr double kHead = 0.1;                  // burr head radius [model units]: 1 mm
constexpr double kEnamel = 300, kDentin = 55;  // [HV]
const Vec3 kAt(0.3, 0.25, 0.0);                // where the burr drills (x, y) on the top z = 0

// The volume the displaced surface encloses [model units³] (divergence theorem over its triangles).
double enclosed_volume(const SlabModel& m) {
  std::vector<Vec3> p;
  std::vector<Tri> f;
  displaced_surface(m, p, f);
  double v = 0;
  for (const Tri& t : f) v += p[t[0]].dot(p[t[1]].cross(p[t[2]]));
  return v / 6;
}

struct Drilled {
  double volume = 0;      // removed [model units³]
  double force_time = 0;  // ∫ F_n dt over the stroke's sweeps [N·s]
};

// Lowers the upright burr onto the top in 0.2 s, pressing with @p force, settles 0.1 s, drills
// 0.5 s with the tool button held, lifts off.
Drilled drill(const SlabModel& model, const ToolScenarioOptions& o, double force) {
  Workspace ws;
  ws.scale = kScale;
  SessionOptions so;
  so.mode = RenderMode::RigidTool;
  so.publish = false;
  so.edit_budget_s = 1.0;  // every sweep finishes in its tick: the result does not depend on the machine
  so.tool = burr_shell(kHead);
  so.head_radius = kHead;
  so.rigid.stiffness = o.proxy.force.stiffness;
  so.rigid.max_force = o.proxy.force.max_force;
  so.rigid.solver = o.proxy.solver;
  SculptSession session(model, ws, so);
  Brush b;  // the drill's defaults: K = 0.01, 200,000 rpm
  b.tool = BrushTool::Drill;
  b.radius = kHead;
  b.falloff = find_brush(BrushTool::Drill)->falloff;
  session.set_brush(b);
  const double before = enclosed_volume(session.model());
  const double offset = force * (1 / o.device.hand_stiffness + 1 / o.proxy.force.stiffness) * kScale;
  const Vec3 above = kAt + Vec3(0, 0, kHead + 0.05), pressed = kAt + Vec3(0, 0, kHead - offset);
  const int down = int(std::lround(0.2 * o.rate_hz)), settle = int(std::lround(0.1 * o.rate_hz)),
            on = int(std::lround(0.5 * o.rate_hz));
  std::vector<Vec3> path;
  std::vector<uint32_t> buttons;
  for (int k = 1; k <= down + settle + on + 2; ++k) {
    path.push_back(ws.to_device(above + (pressed - above) * std::min(1.0, double(k) / down)));
    buttons.push_back(k > down + settle && k <= down + settle + on);
  }
  SimulatedDeviceOptions d = o.device;
  d.rate_hz = o.rate_hz;
  d.spec.max_force_n = o.proxy.force.max_force;
  SimulatedDevice device(d, path, path.front(), buttons);
  Drilled out;
  ServoTick t;
  bool stroke = false;
  for (size_t k = 0; k < path.size(); ++k) {
    t.tick = static_cast<int64_t>(k);
    t.time_s = double(k) / o.rate_hz;
    const SessionTick r = session.tick(device, t);
    if (r.tool_on && stroke) out.force_time += r.head_force_n / o.rate_hz;  // the first sample sweeps nothing
    stroke = r.tool_on && r.head_force_n > 0;
  }
  session.finish();
  out.volume = before - enclosed_volume(session.model());
  return out;
}

// Archard's removal per N·s on hardness @p hv [mm³/(N·s)]: K·v_s/H, v_s = ω·r, for the drill's
// defaults (the brush drill() uses).
double archard_rate(double hv) {
  const Brush drill;
  const double speed = 2 * std::numbers::pi * drill.rpm / 60 * (kHead / kScale);
  return drill.wear_coefficient * speed / vickers_to_pa(hv) * 1e9;
}

}  // namespace

ToolScenarioReport run_drill_layers(const ToolScenarioOptions& o) {
  // n = 32: the top's samples about 0.03 apart, a few dozen under the burr's 0.1 radius.
  const Block b([](int, int, int) { return true; }, 32);
  SlabModel enamel = b.model, dentin = b.model;
  enamel.hardness.assign(enamel.hardness.size(), float(kEnamel));
  dentin.under_layer.hardness_hv = float(kDentin);
  dentin.layer_displacement.assign(dentin.layer_displacement.size(), 1.0f);  // the under-layer is exposed
  const double mm3 = 1e9 / (kScale * kScale * kScale);                       // mm³ per model unit³
  const Drilled e = drill(enamel, o, o.press_force_n), d = drill(dentin, o, o.press_force_n);
  ToolScenarioReport r;
  r.scenario = tool_scenario_name(o.scenario);
  r.rate_hz = o.rate_hz;
  r.radius = kHead;
  r.enamel_rate = e.force_time > 0 ? e.volume * mm3 / e.force_time : 0.0;
  r.dentin_rate = d.force_time > 0 ? d.volume * mm3 / d.force_time : 0.0;
  r.enamel_archard = archard_rate(kEnamel);
  r.dentin_archard = archard_rate(kDentin);
  const double ratio = r.enamel_rate > 0 ? r.dentin_rate / r.enamel_rate : 0.0;
  r.ratio_error_pct = 100 * std::abs(ratio / (kEnamel / kDentin) - 1);
  r.note = "1 mm burr, K = 0.01, 200,000 rpm, 0.5 s at " + std::to_string(o.press_force_n) +
           " N on enamel (300 HV) and on exposed dentin (55 HV); removal " + std::to_string(e.volume * mm3) + " / " +
           std::to_string(d.volume * mm3) + " mm3 for " + std::to_string(e.force_time) + " / " +
           std::to_string(d.force_time) + " N s";
  return r;
}

}  // namespace hdm::harness::detail
