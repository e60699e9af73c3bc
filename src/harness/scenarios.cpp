// SPDX-License-Identifier: MIT
#include "angle_deg.h"

#include <hdm/core/error.h>
#include <hdm/core/percentile.h>
#include <hdm/harness/scenario_sites.h>
#include <hdm/harness/scenarios.h>
#include <hdm/haptics/servo_loop.h>
#include <hdm/haptics/sphere_proxy.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <cstdio>

namespace hdm {
namespace {

using harness::detail::angle_deg;

// ---- hand-target paths, device frame [m] -------------------------------------------------------

void line_to(std::vector<Vec3>& out, const Vec3& b, double speed, double rate) {
  const Vec3 a = out.back();
  const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / speed * rate)));
  for (int i = 1; i <= n; ++i) out.push_back(a + (b - a) * (double(i) / n));
}

void hold(std::vector<Vec3>& out, double seconds, double rate) {
  const Vec3 a = out.back();
  for (int i = 0, n = static_cast<int>(seconds * rate); i < n; ++i) out.push_back(a);
}

// Constant-speed resampling of a polyline that starts at out.back().
void polyline(std::vector<Vec3>& out, const std::vector<Vec3>& pts, double speed, double rate) {
  for (const Vec3& p : pts) line_to(out, p, speed, rate);
}

struct Setup {
  Aabb box;
  Vec3 size;
  double diag = 1;
  Workspace ws;
  double ball_m = 0;                         // the ball's radius at the device [m]; 0 for a point
  std::vector<Vec3> targets;                 // hand target per tick [m]
  int64_t steady_begin = 0, steady_end = 0;  // ticks of the steady part (force_cv, stiff hold)
  std::string note;
};

// ---- scoring ----------------------------------------------------------------------------------

struct RunFlags {
  bool score_normals = true;
};

// What score_run accumulates over the ticks, and the previous tick each tick is compared against.
struct RunTally {
  std::vector<double> tick_ns, nerr, nerr_smooth, nfloor, steady_force;
  Vec3 f_prev = Vec3::Zero(), x_prev = Vec3::Zero(), hip_prev = Vec3::Zero(), f_ref_prev = Vec3::Zero();
  Vec3 f_fac_prev = Vec3::Zero();
  bool f_ref_valid = false, f_fac_valid = false;
  double returned = 0, absorbed = 0, force_sum = 0;
  int prev_slab = -1;
};

// The forces a renderer of the exact input would give at this tick (valid flags: defined at all).
struct ReferenceForces {
  Vec3 f_ref = Vec3::Zero(), f_fac = Vec3::Zero();
  bool ref_valid = false, fac_valid = false;
};

// The scenarios score a point renderer (render_step) or the ball: the rigid tool, whose torque
// they do not score, is refused by name, and so is a ball radius that is not a length or is given
// for a point renderer.
void require_scored_mode(const char* what, const ScenarioOptions& o) {
  if (o.mode == RenderMode::RigidTool)
    throw InvalidInput(std::string(what) +
                       ": mode rigid is not scored here (its force and torque are scored by the tool scenarios "
                       "shaft_edge and drill_layers); proxy, penalty or sphere");
  if (!(o.ball_radius >= 0) || !std::isfinite(o.ball_radius))
    throw InvalidInput(std::string(what) + ": ball radius " + std::to_string(o.ball_radius) +
                       " is not a length >= 0 (0: 1 % of the model's diagonal)");
  if (o.mode != RenderMode::Sphere && o.ball_radius != 0)
    throw InvalidInput(std::string(what) + ": ball radius " + std::to_string(o.ball_radius) +
                       " is for the ball (mode sphere) only");
}

// The renderer a run drives, with the state it carries from tick to tick: a point renderer
// (render_step) or the ball (sphere_proxy_step). The ball's state is a few kB: one per run.
struct Renderer {
  RenderMode mode = RenderMode::Proxy;
  ProxyParams point;
  SphereProxyParams ball;
  ProxyState st;
  SphereProxyState ball_state;

  ProxyOutput step(const SlabModel& model, const SlabLocator& locator, const Workspace& ws, const DeviceState& ds) {
    if (mode == RenderMode::Sphere)
      return sphere_proxy_step(model, locator, ws, ds.position, ds.velocity, ball, ball_state);
    return render_step(mode, model, locator, ws, ds.position, ds.velocity, point, st);
  }
  // Where the force is judged from: the proxy (the SCP in penalty mode), or the ball's centre [model units].
  const Vec3& proxy() const { return mode == RenderMode::Sphere ? ball_state.center : st.position; }
};

// The ball's radius [model units] a run uses: as sphere_proxy_step() resolves 0.
double ball_radius(const SlabModel& model, const ScenarioOptions& o) {
  if (o.mode != RenderMode::Sphere) return 0;
  return o.ball_radius > 0 ? o.ball_radius : 0.01 * model.source_diagonal;
}

// The report's identification fields, before any tick is run.
ScenarioReport report_header(const ScenarioOptions& o, const Setup& s) {
  ScenarioReport r;
  r.scenario = scenario_name(o.scenario);
  r.mode = o.mode == RenderMode::Proxy ? "proxy" : o.mode == RenderMode::Sphere ? "sphere" : "penalty";
  r.rate_hz = o.rate_hz;
  r.ball_radius = s.ball_m * s.ws.scale;
  r.stable_stiffness_n_per_m = o.proxy.force.stiffness;
  r.note = s.note;
  return r;
}

// Per-tick buffers sized for @p n ticks, so that scoring does not reallocate mid-run.
RunTally make_tally(int64_t n) {
  RunTally t;
  t.tick_ns.resize(n);
  t.nerr.reserve(n);
  t.nerr_smooth.reserve(n);
  t.nfloor.reserve(n);
  t.steady_force.reserve(n);
  return t;
}

// Energy, force steps while still, contact force and depth, and the steady-part force samples.
void score_force(ScenarioReport& r, RunTally& t, const Setup& s, const ProxyOutput& out, const Vec3& x, int64_t k,
                 double max_f) {
  const Vec3& f = out.force;
  // Work of the force held over the last period on the handle's motion in that period.
  const double w = t.f_prev.dot(x - t.x_prev);
  (w > 0 ? t.returned : t.absorbed) += std::abs(w);
  if (k > 0 && (x - t.x_prev).norm() < 1e-4)
    r.max_force_step_pct = std::max(r.max_force_step_pct, 100 * (f - t.f_prev).norm() / max_f);
  const double fm = f.norm();
  if (fm > 0) {
    ++r.contact_ticks;
    t.force_sum += fm;
    r.max_force_n = std::max(r.max_force_n, fm);
    r.max_penetration_mm = std::max(r.max_penetration_mm, 1e3 * out.contact.depth / s.ws.scale);
  }
  if (k >= s.steady_begin && k < s.steady_end) t.steady_force.push_back(fm);
}

// The ball on the exact input, at the HIP's closest input point @p ch: a spring of depth r - |g|
// outside the input, r + |g| inside (g = HIP - c), along the input's interpolated normal at c
// (smooth) and along g (facets: the faceted input's offset surface is smooth, so is this force).
ReferenceForces ball_reference(const ExactMeshQuery& ref, const Setup& s, const ProxyParams& pp, const SurfacePoint& ch,
                               const Vec3& hip, double max_f) {
  ReferenceForces rf;
  const Vec3 g = hip - ch.point;
  const double r = s.ball_m * s.ws.scale, d = g.norm();
  const bool inside = ref.inside(hip);
  const double depth = inside ? r + d : r - d;
  if (depth <= 0) return rf;
  const double spring = std::min(max_f, pp.force.stiffness * depth / s.ws.scale);
  rf.f_ref = spring * ch.normal;
  rf.ref_valid = true;
  if (!inside && d > 0) {
    rf.f_fac = spring * g / d;
    rf.fac_valid = true;
  }
  return rf;
}

// Normal errors of force @p f against the input, and the exact input's reference forces at @p hip.
ReferenceForces score_normals(RunTally& t, const ScenarioSites& sites, const ExactMeshQuery& ref, const Setup& s,
                              const ProxyParams& pp, const Vec3& proxy, const Vec3& f, const Vec3& hip, double max_f) {
  // The input's face and interpolated normals at its closest point to the proxy (to the SCP
  // in penalty mode, to the ball's centre).
  const SurfacePoint cp = sites.project(proxy);
  if (cp.face >= 0) {
    // A ball's exact contact normal is the direction from the input's closest point to its centre
    // (the normal of the input's offset surface): on a surface rough at the ball's scale, the
    // interpolated normal there is not the direction the input pushes the ball.
    const Vec3 smooth =
        s.ball_m > 0 && (proxy - cp.point).norm() > 0 ? Vec3((proxy - cp.point).normalized()) : cp.normal;
    t.nerr.push_back(angle_deg(f, cp.face_normal));
    t.nerr_smooth.push_back(angle_deg(f, smooth));
    t.nfloor.push_back(angle_deg(cp.face_normal, smooth));
  }
  const SurfacePoint ch = sites.project(hip);
  if (ch.face < 0) return {};
  if (s.ball_m > 0) return ball_reference(ref, s, pp, ch, hip, max_f);
  ReferenceForces rf;
  // The same contact rendered on the exact input: spring to the HIP's closest input point along
  // the input's interpolated normal there (what a renderer of the smooth input would give).
  rf.f_ref = std::min(max_f, pp.force.stiffness * (ch.point - hip).norm() / s.ws.scale) * ch.normal;
  rf.ref_valid = true;
  // Its facets: the spring straight to c, while the HIP is under c's face.
  const Vec3 g = ch.point - hip;
  if (g.dot(ch.face_normal) > 0) {
    rf.f_fac = std::min(max_f, pp.force.stiffness * g.norm() / s.ws.scale) * g.normalized();
    rf.fac_valid = true;
  }
  return rf;
}

// The reference renderers' worst force steps while the handle is still (the floor for ours).
void score_reference_steps(ScenarioReport& r, RunTally& t, const ReferenceForces& rf, bool still, double max_f) {
  auto reference_step = [&](const Vec3& f_now, bool valid, Vec3& f_before, bool& valid_before, double& worst) {
    if (valid && valid_before && still) worst = std::max(worst, 100 * (f_now - f_before).norm() / max_f);
    f_before = f_now;
    valid_before = valid;
  };
  reference_step(rf.f_ref, rf.ref_valid, t.f_ref_prev, t.f_ref_valid, r.reference_force_step_pct);
  reference_step(rf.f_fac, rf.fac_valid, t.f_fac_prev, t.f_fac_valid, r.reference_facet_force_step_pct);
}

// Pop-through: a real surface never pulls the handle in, and never lets go of a handle that
// is inside it or has just passed through it.
void score_pop_through(ScenarioReport& r, const RunTally& t, const ExactMeshQuery& ref, const Vec3& f,
                       const Vec3& hip) {
  const double fp = t.f_prev.norm();
  if (fp > 0.2 && f.dot(t.f_prev) <= 0) {
    const bool reversed = f.dot(t.f_prev) < -0.1 * fp * fp;
    bool through = reversed || ref.inside(hip);
    if (!through && (hip - t.hip_prev).dot(t.f_prev) < 0) {
      std::vector<SegmentHit> hits;
      ref.segment_hits(t.hip_prev, hip, hits);
      through = !hits.empty();
    }
    if (through) ++r.pop_throughs;
  }
}

// The run's summary statistics from what was tallied over its @p k ticks.
void finish_report(ScenarioReport& r, RunTally& t, int64_t k) {
  r.ticks = k;
  t.tick_ns.resize(k);
  r.energy_ratio = t.absorbed > 0 ? t.returned / t.absorbed : 0;
  r.mean_contact_force_n = r.contact_ticks > 0 ? t.force_sum / r.contact_ticks : 0;
  r.normal_error_p95_deg = percentile(t.nerr, 0.95);
  r.normal_error_smooth_p95_deg = percentile(t.nerr_smooth, 0.95);
  r.normal_floor_p95_deg = percentile(t.nfloor, 0.95);
  if (!t.steady_force.empty()) {
    double m = 0, v = 0;
    for (double x : t.steady_force) m += x;
    m /= t.steady_force.size();
    for (double x : t.steady_force) v += (x - m) * (x - m);
    r.force_cv = m > 0 ? std::sqrt(v / t.steady_force.size()) / m : 0;
  }
  const LatencyStats ls = latency_stats(std::move(t.tick_ns));
  r.tick_ns_median = ls.median;
  r.tick_ns_p99 = ls.p99;
  r.tick_ns_max = ls.max;
}

// Runs @p n ticks of @p dev against the renderer and scores them. The device is closed-loop
// (simulated hand) or open-loop (replay); either way the force is scored on the motion it gets.
ScenarioReport score_run(const SlabModel& model, const SlabLocator& locator, const ExactMeshQuery& ref,
                         const ScenarioSites* sites, const ScenarioOptions& o, const Setup& s, const RunFlags& flags,
                         HapticDevice& dev, int64_t n) {
  ScenarioReport r = report_header(o, s);
  ProxyParams pp = o.proxy;
  if (!o.friction) pp.friction_scale = 0;
  Renderer rn;
  rn.mode = o.mode;
  rn.point = pp;
  rn.ball.proxy = pp;
  rn.ball.radius = s.ball_m * s.ws.scale;
  RunTally t = make_tally(n);
  if (o.keep_trace) r.trace.reserve(n);
  const double max_f = pp.force.max_force;
  using clock = std::chrono::steady_clock;

  int64_t k = 0;
  for (; k < n; ++k) {
    DeviceState ds;
    if (!dev.begin_frame(ds)) break;
    if (k == 0) t.x_prev = ds.position, t.hip_prev = s.ws.to_model(ds.position);
    const auto t0 = clock::now();
    const ProxyOutput out = rn.step(model, locator, s.ws, ds);
    const auto t1 = clock::now();
    dev.end_frame(out.force);
    t.tick_ns[k] = std::chrono::duration<double, std::nano>(t1 - t0).count();

    const Vec3& x = ds.position;
    const Vec3& f = out.force;
    const Vec3 hip = s.ws.to_model(x);
    if (out.status == ProxyStatus::BadInput) ++r.bad_input_ticks;
    score_force(r, t, s, out, x, k, max_f);
    const double fm = f.norm();
    ReferenceForces rf;
    if (sites && flags.score_normals && fm > 0.05) rf = score_normals(t, *sites, ref, s, pp, rn.proxy(), f, hip, max_f);
    const bool still = k > 0 && (x - t.x_prev).norm() < 1e-4;
    score_reference_steps(r, t, rf, still, max_f);
    if (o.mode == RenderMode::Proxy && rn.st.contact) {
      Contact e;
      evaluate_surface(model, rn.st.slab, rn.st.coords, e);
      r.proxy_surface_error_max =
          std::max(r.proxy_surface_error_max, (e.surface_point - rn.st.position).norm() / s.diag);
    }
    score_pop_through(r, t, ref, f, hip);
    const int slab = fm > 0 ? out.contact.slab : -1;
    if (slab >= 0 && t.prev_slab >= 0 && slab != t.prev_slab) ++r.slab_crossings;
    t.prev_slab = slab;
    if (o.keep_trace)
      r.trace.push_back({k / o.rate_hz, x, f, fm > 0 ? 1e3 * out.contact.depth / s.ws.scale : 0.0,
                         static_cast<int>(out.status), slab, s.ws.to_device(rn.proxy()), out.contact.normal});
    t.f_prev = f;
    t.x_prev = x;
    t.hip_prev = hip;
  }
  finish_report(r, t, k);
  return r;
}

// The closed loop: a simulated hand follows the setup's targets.
ScenarioReport simulate(const SlabModel& model, const SlabLocator& locator, const ExactMeshQuery& ref,
                        const ScenarioSites* sites, const ScenarioOptions& o, const Setup& s, const RunFlags& flags) {
  SimulatedDeviceOptions dopt = o.device;
  dopt.rate_hz = o.rate_hz;
  dopt.spec.max_force_n = o.proxy.force.max_force;
  SimulatedDevice dev(dopt, s.targets, s.targets.front());
  return score_run(model, locator, ref, sites, o, s, flags, dev, static_cast<int64_t>(s.targets.size()));
}

// ---- scenario geometry ----------------------------------------------------------------------

Setup base_setup(const SlabModel& model, const ExactMeshQuery& ref, const ScenarioOptions& o) {
  Setup s;
  s.box = bounds(ref.mesh());
  s.size = s.box.max - s.box.min;
  s.diag = s.box.diagonal();
  s.ws = fit_workspace(s.box, o.workspace_m);
  s.ball_m = ball_radius(model, o) / s.ws.scale;
  return s;
}

// Hand offset below the surface that makes the hand push with force F through the rendered spring.
double press_offset(const ScenarioOptions& o, double force) {
  return force / o.device.hand_stiffness + force / o.proxy.force.stiffness;
}

// Approach the first point along its normal, follow the points at @p speed, lift off along the
// last normal. The steady part is the stroke minus its first 0.1 s.
void stroke(const ScenarioOptions& o, Setup& s, const std::vector<Vec3>& pts, const std::vector<Vec3>& lifted,
            double speed) {
  s.targets.push_back(lifted.front());
  line_to(s.targets, pts.front(), 0.05, o.rate_hz);
  hold(s.targets, 0.1, o.rate_hz);
  s.steady_begin = static_cast<int64_t>(s.targets.size() + 0.1 * o.rate_hz);
  polyline(s.targets, pts, speed, o.rate_hz);
  s.steady_end = static_cast<int64_t>(s.targets.size());
  line_to(s.targets, lifted.back(), 0.05, o.rate_hz);
  hold(s.targets, 0.05, o.rate_hz);
}

double length(const std::vector<Vec3>& pts) {
  double len = 0;
  for (size_t i = 1; i < pts.size(); ++i) len += (pts[i] - pts[i - 1]).norm();
  return len;
}

// Hand targets [m] under surface points: pressed in along the interpolated normal by @p depth [m]
// (negative: lifted off), measured from the ball's surface (its centre one radius above).
std::vector<Vec3> targets_under(const Setup& s, const std::vector<SurfacePoint>& pts, double depth) {
  std::vector<Vec3> out;
  out.reserve(pts.size());
  for (const SurfacePoint& p : pts) out.push_back(s.ws.to_device(p.point) - (depth - s.ball_m) * p.normal);
  return out;
}

// Stroke over the smoothest exposed stretch of the input, there and back.
void slide_path(const ScenarioSites& sites, const ScenarioOptions& o, Setup& s) {
  const SurfaceStroke st = sites.slide_stroke();
  std::vector<Vec3> pts = targets_under(s, st.points, press_offset(o, o.press_force_n));
  std::vector<Vec3> lifted = targets_under(s, st.points, -0.01);
  const double one_way = length(pts);
  pts.insert(pts.end(), pts.rbegin(), pts.rend());  // there and back
  std::reverse(lifted.begin(), lifted.end());
  stroke(o, s, pts, lifted, o.speed_m_s);
  const Vec3& a = st.points.front().point;
  char buf[240];
  std::snprintf(
      buf, sizeof buf,
      "stroke from (%.4g, %.4g, %.4g) and back, %.1f cm each way at %.0f mm/s, hand pressing %.2f N along -n; "
      "input roughness p95 %.1f deg, bend %.1f deg",
      a.x(), a.y(), a.z(), 100 * one_way, 1e3 * o.speed_m_s, o.press_force_n, st.roughness_deg, st.bend_deg);
  s.note = buf;
}

void press_path(const SurfacePoint& spot, const ScenarioOptions& o, Setup& s, double hand_force, double hold_s) {
  const Vec3 p = s.ws.to_device(spot.point);
  const Vec3 in = p - (press_offset(o, hand_force) - s.ball_m) * spot.normal, out = p + (0.01 + s.ball_m) * spot.normal;
  s.targets.push_back(out);
  line_to(s.targets, in, 0.02, o.rate_hz);
  s.steady_begin = static_cast<int64_t>(s.targets.size() + 0.5 * hold_s * o.rate_hz);
  hold(s.targets, hold_s, o.rate_hz);
  s.steady_end = static_cast<int64_t>(s.targets.size());
  line_to(s.targets, out, 0.02, o.rate_hz);
  hold(s.targets, 0.05, o.rate_hz);
  char buf[200];
  std::snprintf(buf, sizeof buf, "press at (%.4g, %.4g, %.4g) along -n, hand up to %.2f N, hold %.2f s", spot.point.x(),
                spot.point.y(), spot.point.z(), hand_force, hold_s);
  s.note = buf;
}

void edges_path(const SurfaceStroke& st, const ScenarioOptions& o, Setup& s) {
  const std::vector<Vec3> pts = targets_under(s, st.points, press_offset(o, o.press_force_n));
  const std::vector<Vec3> lifted = targets_under(s, st.points, -0.01);
  stroke(o, s, pts, lifted, o.speed_m_s);
  const Vec3& a = st.points.front().point;
  char buf[240];
  std::snprintf(buf, sizeof buf,
                "two-turn spiral round the slab corner near (%.4g, %.4g, %.4g), %.1f cm at %.0f mm/s, hand pressing "
                "%.2f N along -n; %d slab crossings on the input, roughness p95 %.1f deg",
                a.x(), a.y(), a.z(), 100 * length(pts), 1e3 * o.speed_m_s, o.press_force_n, st.slab_crossings,
                st.roughness_deg);
  s.note = buf;
}

// Push through the thinnest sheet along its entry normal, so that a frictionless surface does not
// deflect the hand sideways, until the hand alone would apply max force with the handle at the far side.
void thin_path(const ThinSite& site, const ScenarioOptions& o, Setup& s) {
  const Vec3 in_d = s.ws.to_device(site.entry.point), out_d = s.ws.to_device(site.exit), u = -site.entry.normal;
  s.targets.push_back(in_d - u * (0.01 + s.ball_m));
  line_to(s.targets, out_d + u * (o.proxy.force.max_force / o.device.hand_stiffness + s.ball_m), 0.02, o.rate_hz);
  s.steady_begin = static_cast<int64_t>(s.targets.size());
  hold(s.targets, 0.3, o.rate_hz);
  s.steady_end = static_cast<int64_t>(s.targets.size());
  line_to(s.targets, in_d - u * (0.01 + s.ball_m), 0.02, o.rate_hz);
  hold(s.targets, 0.05, o.rate_hz);
  const Vec3& in = site.entry.point;
  char buf[200];
  std::snprintf(buf, sizeof buf,
                "thinnest sheet at (%.4g, %.4g, %.4g), %.2f mm thick at the device, pushed along (%.2f, %.2f, %.2f)",
                in.x(), in.y(), in.z(), 1e3 * (out_d - in_d).norm(), u.x(), u.y(), u.z());
  s.note = buf;
}

}  // namespace

Scenario parse_scenario(const std::string& name) {
  for (Scenario s : {Scenario::Slide, Scenario::Press, Scenario::Thin, Scenario::Edges, Scenario::Stiff})
    if (name == scenario_name(s)) return s;
  throw InvalidInput("scenario '" + name + "': expected slide, press, thin, edges or stiff");
}

const char* scenario_name(Scenario s) noexcept {
  switch (s) {
    case Scenario::Slide:
      return "slide";
    case Scenario::Press:
      return "press";
    case Scenario::Thin:
      return "thin";
    case Scenario::Edges:
      return "edges";
    case Scenario::Stiff:
      return "stiff";
  }
  return "?";
}

ScenarioReport run_scenario(const SlabModel& model, const SlabLocator& locator, const ExactMeshQuery& ref,
                            const ScenarioOptions& o) {
  if (!(o.rate_hz > 0)) throw InvalidInput("scenario: rate_hz must be > 0");
  require_scored_mode("scenario", o);
  Setup s = base_setup(model, ref, o);
  RunFlags flags;
  const ScenarioSites sites(ref);
  switch (o.scenario) {
    case Scenario::Slide:
      slide_path(sites, o, s);
      break;
    case Scenario::Press:
      press_path(sites.press_spot(), o, s, 1.2 * o.proxy.force.max_force, 0.3);
      break;
    case Scenario::Thin:
      thin_path(sites.thin_site(model, locator), o, s);
      break;
    case Scenario::Edges:
      edges_path(sites.edges_spiral(model, locator), o, s);
      break;
    case Scenario::Stiff: {
      // Sweep stiffness in 1 dB-like steps (×10^0.1); stable = the held force settles (std/mean < 5 %)
      // and the contact returns no more energy than it absorbed (Colgate & Schenkel's passivity).
      flags.score_normals = false;
      double best = 0, passive = 0;
      ScenarioReport best_report;
      const SurfacePoint spot = sites.press_spot();
      for (int i = 0; i < 80; ++i) {
        ScenarioOptions oi = o;
        oi.proxy.force.stiffness = 200 * std::pow(10.0, 0.1 * i);
        Setup si = base_setup(model, ref, oi);
        press_path(spot, oi, si, 1.5, 0.3);
        const ScenarioReport ri = simulate(model, locator, ref, nullptr, oi, si, flags);

        const bool stable = ri.force_cv < 0.05 && ri.pop_throughs == 0 && ri.energy_ratio < 2;
        if (stable && ri.energy_ratio <= 1.0 && best == passive) passive = oi.proxy.force.stiffness;
        if (stable) {
          best = oi.proxy.force.stiffness;
          best_report = ri;
        } else if (best > 0) {
          break;  // the first failure above a stable stiffness ends the sweep
        }
      }
      best_report.scenario = "stiff";
      best_report.stable_stiffness_n_per_m = best;
      best_report.passive_stiffness_n_per_m = passive;
      best_report.note =
          "press-and-hold at 1.5 N, stiffness swept x10^0.1 from 200 N/m; stable: no pop-through and "
          "the held force settles (std/mean < 5 %); passive: also returned/absorbed work <= 1";
      return best_report;
    }
  }
  return simulate(model, locator, ref, &sites, o, s, flags);
}

ScenarioReport run_replay(const SlabModel& model, const SlabLocator& locator, const ExactMeshQuery& ref,
                          ReplayDevice& device, const ScenarioOptions& options) {
  ScenarioOptions o = options;
  o.rate_hz = device.rate_hz();
  if (!(o.rate_hz > 0)) throw InvalidInput("replay: the trajectory needs at least two rows with increasing time");
  require_scored_mode("replay", o);
  Setup s = base_setup(model, ref, o);
  s.steady_begin = 0;
  s.steady_end = static_cast<int64_t>(device.size());
  s.note = "replay of a recorded trajectory (open loop: the handle does not respond to the force)";
  const ScenarioSites sites(ref);
  ScenarioReport r =
      score_run(model, locator, ref, &sites, o, s, RunFlags{}, device, static_cast<int64_t>(device.size()));
  r.scenario = "replay";
  return r;
}

}  // namespace hdm
