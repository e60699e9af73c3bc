// SPDX-License-Identifier: MIT
#include <hdm/core/error.h>
#include <hdm/haptics/proxy.h>

#include <hdm/query/detail/surface_eval.h>

#include "contact_force.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>

namespace hdm {
namespace {

using haptics_detail::bad_input;
using haptics_detail::finish_force;

// A re-projected candidate is accepted only if its surface faces the same way as the proxy's:
// this keeps the proxy on its own side of a thin part even when the locator's grid fallback finds
// a slab of the opposite side (docs/design.md#force-and-proxy).
constexpr double kMinNormalAgreement = 0.0;

// A sliding proxy sticks again once the tangential offset is back within μd·depth (plus this
// relative margin, so that the curvature left over from re-projection does not keep it creeping:
// below about 1e-3·μd·depth of hand motion per tick, i.e. 0.3 mm/s at 1 kHz and 1 mm depth, the
// contact shows stick-slip, as real dry friction does).
constexpr double kRestick = 1e-3;

double model_diagonal(const SlabModel& m) noexcept { return m.source_diagonal > 0 ? m.source_diagonal : 1.0; }

// Surface sample under slab coordinates: (slab, bary) -> surface point at δ on the projection line,
// with the force-shading normal (SlabSample::h) interpolated over the same grid triangle with the
// same weights as evaluate_surface. The grid normals of a scanned surface turn by more than 1 rad per penetration depth
// (armadillo: 5 % of grid edges at 1 mm), so the force-shading fixed point folds there: the proxy
// stalls with a growing tangential force, then snaps across (force steps of 8 % at 10 kHz). The
// one-ring sum turns about half as fast.
// @p cell is the grid triangle under c (local_cell()).
bool surface_at(const SlabModel& model, int slab, const SlabCoordinates& c, const slab_query::detail::LocalCell& cell,
                Contact& out) noexcept {
  const double wS = c.bary[1], wT = c.bary[2];
  double delta;
  Vec3 ray;
  out.surface_point = slab_query::detail::surface_point(model, slab, wS, wT, cell, delta, ray);
  const Vec3f nf = slab_query::detail::interpolated_shading(model, slab, cell);
  out.slab = slab;
  out.coords = c;
  out.delta = delta;
  out.ray = ray;
  const Vec3 nd = nf.cast<double>();
  const double len = nd.norm();  // in double: the normal is unit to rounding, as the force bounds assume
  out.normal = len > 0 ? Vec3(nd * (1.0 / len)) : Vec3(ray.normalized());
  // No depth: every caller sets the proxy's own (0 on the surface, the HIP's in contact_output).
  return out.surface_point.allFinite() && out.normal.allFinite();
}

// The three grid records under a surface point, as surface_at() read them: while they are
// unchanged, so is the surface point and its force-shading normal.
void keep_records(const SlabModel& model, int slab, const slab_query::detail::LocalCell& cell, ProxyState& s) noexcept {
  const SlabSample* v = slab_query::detail::slab_block(model, slab);
  s.surface_slab = slab;
  s.surface_records = {v[cell.la], v[cell.lb], v[cell.ld]};
}

bool records_unchanged(const SlabModel& model, int slab, const slab_query::detail::LocalCell& cell,
                       const ProxyState& s) noexcept {
  if (s.surface_slab != slab) return false;
  const SlabSample* v = slab_query::detail::slab_block(model, slab);
  return std::memcmp(&v[cell.la], &s.surface_records[0], sizeof(SlabSample)) == 0 &&
         std::memcmp(&v[cell.lb], &s.surface_records[1], sizeof(SlabSample)) == 0 &&
         std::memcmp(&v[cell.ld], &s.surface_records[2], sizeof(SlabSample)) == 0;
}

// The proxy's candidate at coordinates @p c of @p slab: the surface point there, refused when its
// normal turns away from @p n_ref by more than allowed (the far side of a thin part, a fold).
// @p cell receives the grid triangle under it.
bool surface_candidate(const SlabModel& model, int slab, const SlabCoordinates& c, const Vec3& n_ref, double min_cos,
                       QueryCache& cache, Contact& out, slab_query::detail::LocalCell& cell) noexcept {
  cell = slab_query::detail::local_cell(model.grid_n, c.bary[1], c.bary[2]);
  if (!surface_at(model, slab, c, cell, out)) return false;
  if (out.normal.dot(n_ref) < std::max(kMinNormalAgreement, min_cos)) return false;
  cache.last_slab = slab;
  out.coords.alpha = out.delta;  // the proxy sits at δ on its line: depth 0 there
  out.depth = 0;
  return true;
}

// Re-projects point @p x onto the displaced surface: locate it, then take the surface point on its
// projection line. Returns false when x is in no slab, or in a slab that faces away. @p alpha_guess
// (the proxy's α, x being a short step along its tangent plane) starts the α solve close to the root.
bool reproject(const SlabModel& model, const SlabLocator& locator, const Vec3& x, const Vec3& n_ref, double min_cos,
               AlphaSolver solver, double alpha_guess, QueryCache& cache, Contact& out,
               slab_query::detail::LocalCell& cell) noexcept {
  SlabCoordinates c;
  const int slab = locator.find(x, cache.last_slab, solver, alpha_guess, c);
  return slab >= 0 && surface_candidate(model, slab, c, n_ref, min_cos, cache, out, cell);
}

Vec3 tangential(const Vec3& v, const Vec3& n) noexcept { return v - v.dot(n) * n; }

// The rows of the inverse Jacobian of the slab map x(wS, wT, α) = R0 + wS·e1 + wT·e2 +
// α·(dR + wS·d1 + wT·d2) at coordinates (wS, wT, α) of one slab that give the barycentric part of a
// step: ΔwS = step·rS, ΔwT = step·rT (the Jacobian [e1 + α·d1, e2 + α·d2, ray], Cramer's rule).
struct SlabStep {
  int32_t slab = -1;  // -1: not computed yet
  Vec3 rS = Vec3::Zero(), rT = Vec3::Zero();
};

// Computes @p j at the proxy's coordinates; false when the Jacobian is singular there.
bool slab_step(const SlabModel& model, int slab, const SlabCoordinates& c, SlabStep& j) noexcept {
  const SlabGeometry& g = model.geometry[slab];
  const double a = c.alpha, wS = c.bary[1], wT = c.bary[2];
  const Vec3 jS = g.e1 + a * g.d1, jT = g.e2 + a * g.d2, ray = slab_query::detail::ray_at(g, wS, wT);
  const Vec3 nS = jT.cross(ray);
  const double det = jS.dot(nS);
  if (!(std::abs(det) > 0)) return false;
  const double inv = 1.0 / det;
  j.slab = slab;
  j.rS = nS * inv;
  j.rT = ray.cross(jS) * inv;
  return true;
}

// The coordinates of x = (proxy's point) + step by a Newton step of the slab map from the proxy's
// own (wS, wT, α = δ), with the Jacobian of the tick's first step in that slab (a chord step: the
// proxy moves micrometres within a tick). The error is second order in the step (the map is bilinear
// in the barycentrics and α), a step of a few µm against a slab millimetres wide, and the candidate
// is a surface point either way: slide_towards accepts it only if the residual decreases. Returns
// false when the step leaves the slab (a barycentric below 0) or the Jacobian is singular; the
// locator's search then takes over (reproject).
bool step_in_slab(const SlabModel& model, int slab, const SlabCoordinates& c, const Vec3& step, SlabStep& j,
                  SlabCoordinates& out) noexcept {
  if (j.slab != slab && !slab_step(model, slab, c, j)) return false;
  const double s = c.bary[1] + step.dot(j.rS), t = c.bary[2] + step.dot(j.rT);
  if (!(s >= 0 && t >= 0 && s + t <= 1)) return false;  // also false for a NaN
  out.bary = Vec3(1 - s - t, s, t);
  out.alpha = c.alpha;
  return true;
}

// A candidate proxy position for a tangential step: in the proxy's slab by step_in_slab when the
// step stays in it (no search), else by the locator (reproject, which crosses slab edges).
bool candidate(const SlabModel& model, const SlabLocator& locator, const ProxyState& s, const Vec3& step,
               double min_cos, AlphaSolver solver, SlabStep& j, QueryCache& cache, Contact& out,
               slab_query::detail::LocalCell& cell) noexcept {
  SlabCoordinates c;
  if (!step_in_slab(model, s.slab, s.coords, step, j, c))
    return reproject(model, locator, s.position + step, s.normal, min_cos, solver, s.coords.alpha, cache, out, cell);
  return surface_candidate(model, s.slab, c, s.normal, min_cos, cache, out, cell);
}

// Moves the proxy towards target T: project T onto the proxy's tangent plane, re-project onto the
// surface, repeat. Converges to the point whose interpolated normal points at T (force shading).
void slide_towards(const SlabModel& model, const SlabLocator& locator, const Vec3& target, const ProxyParams& p,
                   ProxyState& s, Contact& at) noexcept {
  // Converged when the tangential residual is below 1e-7 of the diagonal (0.016 µm on a 16 cm
  // workspace): the force direction is then within ~0.001° of the fixed point at 1 mm depth, and a
  // still or slowly moving hand costs one round instead of params.iterations.
  const double tiny = 1e-7 * model_diagonal(model);
  const double min_cos = std::cos(p.max_turn_deg * std::numbers::pi / 180);
  SlabStep j;
  for (int it = 0; it < std::max(1, p.iterations); ++it) {
    Vec3 step = tangential(target - s.position, s.normal);
    // Squared lengths: the comparisons need no square root (two per candidate on the tick's path).
    const double residual2 = step.squaredNorm();
    if (residual2 <= tiny * tiny) break;
    bool moved = false;
    for (int h = 0; h <= p.max_halvings; ++h, step *= 0.5) {
      Contact c;
      slab_query::detail::LocalCell cell;
      // A move is accepted when the normal turns by less than max_turn_deg and the tangential
      // residual |P_n(target - proxy)| (zero at the force-shading fixed point) decreases. Where the
      // penetration depth times the curvature of the normal field exceeds about 1 (fine relief,
      // concave creases), the plain fixed-point iteration overshoots and the proxy hops between
      // two positions every tick (seen on the armadillo: force flips of 3 N); the residual test
      // with halving turns it into a damped iteration. A strict descent on |target - proxy| was
      // tried and rejected: it made the proxy lag on curved parts, acting as friction.
      if (candidate(model, locator, s, step, min_cos, p.solver, j, s.proxy_cache, c, cell) &&
          tangential(target - c.surface_point, c.normal).squaredNorm() < residual2) {
        keep_records(model, c.slab, cell, s);
        s.slab = c.slab;
        s.coords = c.coords;
        s.position = c.surface_point;
        s.normal = c.normal;
        at = c;
        moved = true;
        break;
      }
    }
    if (!moved) break;
  }
}

void release(ProxyState& s, const Vec3& hip) noexcept {
  s.contact = false;
  s.stuck = false;
  s.slab = -1;
  s.position = hip;
}

// The proxy's material at its coordinates: stiffness and friction coefficients.
struct Material {
  double k, mu_s, mu_d;
};

// The query of a free HIP: the full contact only where it penetrates (δ > α). Above the surface
// the proxy just follows the HIP, so the interpolated normal (its square root and division) is not
// computed: such a contact has its slab, coordinates and δ, and depth 0.
Contact free_query(const SlabModel& model, const SlabLocator& locator, const Vec3& x, QueryCache& cache,
                   AlphaSolver solver) noexcept {
  Contact out;
  SlabCoordinates c;
  const int slab = slab_query::detail::find_cached(locator, x, cache, solver, c);
  if (slab < 0) return out;
  // The same interpolation as evaluate_surface's δ, so the two agree on which points penetrate.
  const double delta = slab_query::detail::interpolated_delta(
      model, slab, slab_query::detail::local_cell(model.grid_n, c.bary[1], c.bary[2]));
  if (delta > c.alpha) {
    evaluate_surface(model, slab, c, out);
    return out;
  }
  out.slab = slab;
  out.coords = c;
  out.delta = delta;
  return out;
}

// Free: the HIP's contact, sub-stepping a long free move (from the last HIP) so that a jump across
// a thin part in one tick is still caught on the entry side.
static inline Contact first_penetration(const SlabModel& model, const SlabLocator& locator, const Vec3& hip,
                                        const ProxyParams& p, ProxyState& s) noexcept {
  Contact c = free_query(model, locator, hip, s.hip_cache, p.solver);
  if (!c.penetrating() && s.has_last_hip) {
    const double step = p.tunnel_step > 0 ? p.tunnel_step : 0.002 * model_diagonal(model);
    const double len = (hip - s.last_hip).norm();
    const int subs = std::min(p.max_tunnel_steps, static_cast<int>(std::ceil(len / step)));
    QueryCache sub_cache = s.hip_cache;
    for (int k = 1; k < subs; ++k) {
      const Contact ck =
          free_query(model, locator, s.last_hip + (hip - s.last_hip) * (double(k) / subs), sub_cache, p.solver);
      if (ck.penetrating()) {
        c = ck;
        break;
      }
    }
  }
  return c;
}

// Entry: the surface point on the penetrating point's projection line (same barycentrics, α = δ).
static inline void enter_contact(ProxyState& s, const Contact& c) noexcept {
  s.contact = true;
  s.stuck = false;
  s.slab = c.slab;
  s.coords = c.coords;
  s.coords.alpha = c.delta;
  s.position = c.surface_point;
  s.normal = c.normal;
  s.proxy_cache.last_slab = c.slab;
  s.surface_slab = -1;  // the entry point carries the surface normal, not the force-shading one
}

// Follow edits under the proxy: re-evaluate the surface at its coordinates (grid triangle @p cell),
// unless the grid records it reads are the ones its point and normal came from (no edit since):
// the evaluation would then give them again, bit for bit.
static inline void follow_surface(const SlabModel& model, const slab_query::detail::LocalCell& cell, ProxyState& s,
                                  Contact& at) noexcept {
  if (records_unchanged(model, s.slab, cell, s)) {
    at.slab = s.slab;
    at.coords = s.coords;
    at.delta = s.coords.alpha;
    at.surface_point = s.position;
    at.normal = s.normal;
    at.ray = slab_query::detail::ray_at(model.geometry[s.slab], s.coords.bary[1], s.coords.bary[2]);
    return;
  }
  if (surface_at(model, s.slab, s.coords, cell, at)) {
    s.position = at.surface_point;
    s.normal = at.normal;
    s.coords.alpha = at.delta;
    keep_records(model, s.slab, cell, s);
  }
}

// Stiffness and friction under the proxy, blended towards the under-layer's where it is exposed.
// @p cell: the grid triangle under the proxy (the same one interpolate_field would find).
static inline Material material_at_proxy(const SlabModel& model, const ProxyParams& p, const ProxyState& s,
                                         const slab_query::detail::GridCell& cell) noexcept {
  auto field = [&](const auto& f, double fallback) {
    if (f.empty()) return fallback;
    const double v = f.uniform() ? double(float(f.uniform_value()))
                                 : cell.wa * float(f[cell.a]) + cell.wb * float(f[cell.b]) + cell.wd * float(f[cell.d]);
    return std::isfinite(v) ? v : fallback;
  };
  // Where carving went below the under-layer's top, its material is felt (paper §2).
  double exposure = 0;
  if (!model.layer_displacement.empty()) {
    const SlabGeometry& g = model.geometry[s.slab];
    const double ray = slab_query::detail::ray_at(g, s.coords.bary[1], s.coords.bary[2]).norm();
    const double band = p.layer_band > 0 ? p.layer_band : 5e-4 * model_diagonal(model);
    exposure = layer_exposure((field(model.layer_displacement, 0.0) - s.coords.alpha) * ray, band);
  }
  const UnderLayer& under = model.under_layer;
  auto blend = [exposure](double top, double below) { return top + exposure * (below - top); };
  const double k = p.force.stiffness * blend(field(model.stiffness_scale, 1.0), under.stiffness_scale);
  const double mu_s = p.friction_scale * blend(field(model.friction_static, 0.0), under.friction_static);
  const double mu_d =
      std::min(mu_s, p.friction_scale * blend(field(model.friction_dynamic, 0.0), under.friction_dynamic));
  return {k, mu_s, mu_d};
}

// Friction cone on the proxy (Ruspini et al. 1997; Melder & Harwin 2005): depths in model units,
// so the cone test k·|t| <= μ·k·d needs no unit conversion. Returns false when the HIP is above
// the tangent plane (contact ends).
static inline bool friction_cone(const SlabModel& model, const SlabLocator& locator, const Vec3& hip,
                                 const ProxyParams& p, const Material& m, ProxyState& s, Contact& at) noexcept {
  const Vec3 d = hip - s.position;
  const double depth = -d.dot(s.normal);
  if (depth <= 0) return false;
  const Vec3 t = d + depth * s.normal;  // tangential offset of the HIP from the proxy
  const double tl = t.norm();
  if (s.stuck && tl <= m.mu_s * depth) {
    // stuck: proxy stays
  } else if (tl <= m.mu_d * depth * (1 + kRestick)) {
    s.stuck = true;  // the HIP stopped pulling the proxy along: stick again
  } else {
    s.stuck = false;
    const Vec3 target = hip - (tl > 0 ? Vec3(t * (m.mu_d * depth / tl)) : Vec3::Zero());
    slide_towards(model, locator, target, p, s, at);
  }
  return true;
}

// The spring from the HIP to the proxy, its normal and friction parts, and the reported contact.
static inline void contact_output(const Workspace& ws, const Vec3& hip, const Vec3& velocity, const ProxyParams& p,
                                  double k, double depth, const ProxyState& s, const Contact& at,
                                  ProxyOutput& out) noexcept {
  out.status = s.stuck ? ProxyStatus::Stuck : ProxyStatus::Sliding;
  const Vec3 spring_model = s.position - hip;  // [model units]
  const Vec3 f = (k / ws.scale) * spring_model;
  out.normal_force = f.dot(s.normal);
  out.friction_force = (f - out.normal_force * s.normal).norm();
  finish_force(f, s.normal, velocity, p, out);

  out.contact = at;
  out.contact.slab = s.slab;
  out.contact.coords = s.coords;
  out.contact.surface_point = s.position;
  out.contact.normal = s.normal;
  out.contact.depth = depth;
}

}  // namespace

namespace {

template <class Field>
double interpolate(const SlabModel& model, const Field& field, int slab, const SlabCoordinates& c,
                   double fallback) noexcept {
  if (field.empty() || slab < 0 || slab >= model.slab_count()) return fallback;
  if constexpr (requires { field.uniform(); })
    if (field.uniform()) {  // one value everywhere: no grid cell to find
      const double v = float(field.uniform_value());
      return std::isfinite(v) ? v : fallback;
    }
  // Same grid triangle and weights as evaluate_surface (docs/design.md#query).
  const slab_query::detail::GridCell cell = slab_query::detail::grid_cell(model, slab, c.bary[1], c.bary[2]);
  const double v = cell.wa * float(field[cell.a]) + cell.wb * float(field[cell.b]) + cell.wd * float(field[cell.d]);
  return std::isfinite(v) ? v : fallback;
}

}  // namespace

double interpolate_field(const SlabModel& model, const std::vector<float>& field, int slab, const SlabCoordinates& c,
                         double fallback) noexcept {
  return interpolate(model, field, slab, c, fallback);
}

double interpolate_field(const SlabModel& model, const SampleField<Half16>& field, int slab, const SlabCoordinates& c,
                         double fallback) noexcept {
  return interpolate(model, field, slab, c, fallback);
}

double interpolate_field(const SlabModel& model, const SampleField<Unorm16>& field, int slab, const SlabCoordinates& c,
                         double fallback) noexcept {
  return interpolate(model, field, slab, c, fallback);
}

ProxyOutput proxy_step(const SlabModel& model, const SlabLocator& locator, const Workspace& ws, const Vec3& hip_device,
                       const Vec3& velocity, const ProxyParams& p, ProxyState& s) noexcept {
  ProxyOutput out;
  if (bad_input(ws, hip_device, velocity, p)) {
    out.status = ProxyStatus::BadInput;
    return out;
  }
  const Vec3 hip = ws.to_model(hip_device);

  if (!s.contact) {
    // Free: follow the HIP; look for the first penetration.
    const Contact c = first_penetration(model, locator, hip, p, s);
    s.last_hip = hip;
    s.has_last_hip = true;
    if (!c.penetrating()) {
      release(s, hip);
      return out;
    }
    enter_contact(s, c);
  }
  s.last_hip = hip;
  s.has_last_hip = true;

  Contact at;
  // One grid triangle for following edits and for the material: both read it at the proxy's coordinates.
  const slab_query::detail::GridCell cell =
      slab_query::detail::grid_cell(model, s.slab, s.coords.bary[1], s.coords.bary[2]);
  follow_surface(model, cell, s, at);
  const Material m = material_at_proxy(model, p, s, cell);
  out.mu_static = m.mu_s;
  out.mu_dynamic = m.mu_d;

  if (!friction_cone(model, locator, hip, p, m, s, at)) {  // HIP above the tangent plane: contact ends
    release(s, hip);
    return out;
  }
  const Vec3 d2 = hip - s.position;
  const double depth2 = -d2.dot(s.normal);
  if (depth2 <= 0) {
    release(s, hip);
    return out;
  }
  contact_output(ws, hip, velocity, p, m.k, depth2, s, at, out);
  return out;
}

ProxyOutput penalty_step(const SlabModel& model, const SlabLocator& locator, const Workspace& ws,
                         const Vec3& hip_device, const Vec3& velocity, const ProxyParams& p, ProxyState& s) noexcept {
  ProxyOutput out;
  if (bad_input(ws, hip_device, velocity, p)) {
    out.status = ProxyStatus::BadInput;
    return out;
  }
  const Vec3 hip = ws.to_model(hip_device);
  s.last_hip = hip;
  s.has_last_hip = true;
  const Contact c = query(model, locator, hip, s.hip_cache, p.solver);
  const ForceSample f = penalty_force(c, velocity, p.force, ws);
  s.contact = c.penetrating();
  s.stuck = false;
  s.slab = c.slab;
  s.coords = c.coords;
  s.normal = c.normal;
  s.position = s.contact ? Vec3(hip + c.normal * c.ray_depth()) : hip;  // the paper's SCP (§3.3)
  out.force = f.force;
  out.status = f.status == ForceStatus::BadInput  ? ProxyStatus::BadInput
               : f.status == ForceStatus::Clamped ? ProxyStatus::Clamped
               : s.contact                        ? ProxyStatus::Sliding
                                                  : ProxyStatus::Free;
  if (s.contact) {
    out.contact = c;  // the HIP's own query: surface point on its projection line, as edits expect
    out.normal_force = p.force.stiffness * c.ray_depth() / ws.scale;
  }
  return out;
}

AlphaSolver parse_alpha_solver(const std::string& name) {
  if (name == "newton") return AlphaSolver::Newton;
  if (name == "bisection") return AlphaSolver::Bisection;
  throw InvalidInput("alpha-plane solver '" + name + "': expected newton or bisection");
}

RenderMode parse_render_mode(const std::string& name) {
  if (name == "proxy") return RenderMode::Proxy;
  if (name == "penalty") return RenderMode::Penalty;
  if (name == "sphere") return RenderMode::Sphere;
  if (name == "rigid") return RenderMode::RigidTool;
  throw InvalidInput("render mode '" + name + "': expected proxy, penalty, sphere or rigid");
}

}  // namespace hdm
