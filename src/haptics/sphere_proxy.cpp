// SPDX-License-Identifier: MIT
#include <hdm/haptics/sphere_proxy.h>

#include "contact_force.h"
#include "nearest_surface_point.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace hdm {
namespace {

using haptics_detail::bad_input;
using haptics_detail::finish_force;
using haptics_detail::nearest_surface_point;
using haptics_detail::shading_turn;
using haptics_detail::SurfacePoint;

// A surface point less than this fraction of r outside the ball still constrains it: contacts
// are held a little before they are reached, so the ball does not bounce on entry.
constexpr double kNearBand = 0.05;
// A sample whose surface contact point is within this many r of the centre seeds a search.
constexpr double kSeedReach = 1.5;
// Samples queried per tick while touches are known: one in this many at most. A direction is then
// queried every `stride` ticks; the stride keeps the ball's motion over them within the seed's
// slack, (kSeedReach − 1)·r, at the speed of its last tick, so a region is found before the ball
// reaches it. The samples are most of the tick's cost (a slab query each).
constexpr int kMaxWarmStride = 8;
// A round moves the centre at most this fraction of r, so the contacts it creates are seen by
// the next round (at 1 kHz and r = 1.6 mm, 0.4 m/s per round).
constexpr double kMaxMove = 0.25;
// Free motion is swept in steps of this fraction of r: a thin part is caught on its entry side.
constexpr double kSweepStep = 0.5;
// A round searches the touches again only once the centre has moved this fraction of r since the
// last search: a nearest point moves no farther than the centre on a convex surface, and the
// planes are linearised at the new centre anyway.
constexpr double kFollow = 0.03;
// Surface points the ball can touch at once.
constexpr int kMaxTouches = 16;

// One constraint on the centre X: a·X >= b, |a| = 1.
struct Plane {
  Vec3 a;
  double b;
};

// The surface points the ball touches, carried over the rounds of one tick: each is searched
// again from where it was at every round, so on a concave spot, where the global nearest point
// jumps between two, both hold the ball at once instead of taking turns.
struct Touches {
  SurfacePoint at[kMaxTouches];
  int count = 0;
  void add(const SurfacePoint& p, double same) noexcept {
    for (int i = 0; i < count; ++i)
      if ((at[i].point - p.point).squaredNorm() <= same * same) return;
    if (count < kMaxTouches) at[count++] = p;
  }
};

double radius_of(const SlabModel& model, const SphereProxyParams& p) noexcept {
  if (p.radius > 0) return p.radius;
  return 0.01 * (model.source_diagonal > 0 ? model.source_diagonal : 1.0);
}

// Fibonacci sphere (González 2010): near-uniform directions without a table in the binary.
void fill_directions(SphereProxyState& s, int n) noexcept {
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int k = 0; k < n; ++k) {
    const double z = 1.0 - (2.0 * k + 1.0) / n;
    const double rho = std::sqrt(std::max(0.0, 1.0 - z * z));
    s.directions[k] = Vec3(rho * std::cos(golden * k), rho * std::sin(golden * k), z);
  }
  s.sample_count = n;
}

// Samples per query while held: the largest stride (at most kMaxWarmStride) over which the ball,
// moving as far per tick as since the last search, stays within the seed's slack.
int warm_stride(const Vec3& c, double r, const SphereProxyState& s) noexcept {
  const double moved = (c - s.searched).norm();  // NaN before the first search
  const double slack = (kSeedReach - 1) * r;
  if (!std::isfinite(moved)) return 1;
  if (moved * kMaxWarmStride <= slack) return kMaxWarmStride;
  return std::max(1, static_cast<int>(slack / moved));
}

// Finds the surface regions near the ball at centre @p c: each sample facing @p towards (a unit
// vector, or all for zero) in the shell, on a surface facing the centre, whose surface contact
// point is within kSeedReach·r seeds nearest_surface_point(); so do the places the ball touched
// last tick. The samples only find regions: the nearest point of the grid triangles is exact,
// where the samples' own points would let a sharp edge poke in between them.
void find_touches(const SlabModel& model, const SlabLocator& locator, const Vec3& c, double r, const Vec3& towards,
                  const SphereProxyParams& p, SphereProxyState& s, Touches& t) noexcept {
  const double same = 1e-6 * r;
  auto keep = [&](const SurfacePoint& sp) {
    if ((sp.point - c).norm() < (1 + kNearBand) * r) t.add(sp, same);
  };
  for (int i = 0; i < s.touched_count; ++i) {
    const BallTouch& b = s.touched[i];
    if (b.slab >= 0 && b.slab < model.slab_count()) keep(nearest_surface_point(model, b.slab, b.wS, b.wT, c));
  }
  // The sample nearest the centre of each slab and region (samples of one slab closer than r/2
  // are one region: two walls of a groove in one slab are two) starts a search.
  Contact seed[kMaxTouches];
  double seed_distance[kMaxTouches];
  int seeds = 0;
  // Held by known touches, one sample in `stride` per tick (in turn) looks for new regions.
  const int stride = t.count > 0 ? warm_stride(c, r, s) : 1;
  s.searched = c;
  s.sample_phase = (s.sample_phase + 1) % stride;
  for (int k = stride > 1 ? s.sample_phase : 0; k < s.sample_count; k += stride) {
    const Vec3& u = s.directions[k];
    if (u.dot(towards) < -0.3) continue;  // the far side of the ball cannot touch first
    const Contact q = query(model, locator, c + r * u, s.caches[k], p.proxy.solver);
    if (!q.in_shell() || q.normal.dot(u) >= 0) continue;  // outside, or a surface facing away
    const double near = (q.surface_point - c).norm();
    if (!(near < kSeedReach * r)) continue;
    int at = 0;
    while (at < seeds && !(seed[at].slab == q.slab && (seed[at].surface_point - q.surface_point).norm() < 0.5 * r))
      ++at;
    if (at < seeds && near < seed_distance[at]) seed[at] = q, seed_distance[at] = near;
    if (at == seeds && seeds < kMaxTouches) seed[seeds] = q, seed_distance[seeds++] = near;
  }
  // A seed within r of a known touch on a surface facing the same way (within 30°) lies on that
  // touch's own surface and would find it again; two walls of a groove face apart.
  const int known = t.count;
  const double cos_same = std::cos(30 * std::numbers::pi / 180);
  for (int i = 0; i < seeds; ++i) {
    bool found = false;
    for (int j = 0; j < known && !found; ++j)
      found = (t.at[j].point - seed[i].surface_point).norm() < r && t.at[j].normal.dot(seed[i].normal) > cos_same;
    if (!found) keep(nearest_surface_point(model, seed[i].slab, seed[i].coords.bary[1], seed[i].coords.bary[2], c));
  }
}

// The touches searched again from where they were, for the ball at centre @p c.
void follow_touches(const SlabModel& model, const Vec3& c, double r, Touches& t) noexcept {
  Touches next;
  for (int i = 0; i < t.count; ++i) {
    const SurfacePoint sp = nearest_surface_point(model, t.at[i].slab, t.at[i].wS, t.at[i].wT, c);
    if ((sp.point - c).norm() < (1 + kNearBand) * r) next.add(sp, 1e-6 * r);
  }
  t = next;
}

// The ball at centre @p c stays outside each touched point cp: a·X >= a·cp + r for a unit a, which
// keeps cp outside the ball for any a (conservative). a is cp's force-shading normal where that is
// within 5° of both the direction c − cp and its grid triangle's normal (a smooth spot), so the
// ball rolls over the grid's facets as the point proxy slides over them, without their steps; at a
// sharp edge, whose shading blends its faces (and may lean along it), beyond 15° of either, a is
// (c − cp)/|c − cp|, the exclusion sphere of cp linearised at c; blended in between, so the force
// does not switch. Shading also needs the field to turn slowly at the ball's scale: full while r
// times the field's turn rate at cp (shading_turn()) is below 1/4, none from 1/2. A ball rounds a
// feature smaller than itself, so the geometric direction is what it feels there; and beside a
// convex edge, where the shading blends the two faces within a grid spacing, the shaded plane's
// fixed point folded: the ball slid along the flat top, sank into it and snapped back. Measured
// alternatives: the spring as the lever (the point proxy's condition) left the weight partial
// there; a rate per grid triangle jumped between triangles; r plus the spring switched shading on
// and off as a hand pressed deep (a spring of several r) moved the ball over a curved spot, which
// then jumped between two centres on alternate ticks (`hdm feel` on the bunny, press, sphere: 5.4 %
// force steps against 0.67 % with r alone). Returns the number of planes; @p nearest is the touch
// nearest c.
int planes_at(const SlabModel& model, const Touches& t, const Vec3& c, double r, Plane* planes,
              int& nearest) noexcept {
  const double cos_full = std::cos(5 * std::numbers::pi / 180), cos_none = std::cos(15 * std::numbers::pi / 180);
  int count = 0;
  double best = INFINITY;
  nearest = -1;
  for (int i = 0; i < t.count; ++i) {
    const Vec3 away = c - t.at[i].point;
    const double dist = away.norm();
    if (!(dist > 1e-9 * r && dist < (1 + kNearBand) * r)) continue;
    const Vec3 g = away / dist;
    auto ramp = [&](double cos) { return std::clamp((cos - cos_none) / (cos_full - cos_none), 0.0, 1.0); };
    double shade = std::min(ramp(t.at[i].normal.dot(g)), ramp(t.at[i].normal.dot(t.at[i].facet)));
    if (shade > 0) shade *= std::clamp(2 - 4 * r * shading_turn(model, t.at[i]), 0.0, 1.0);
    const Vec3 a = (g + shade * (t.at[i].normal - g)).normalized();
    planes[count++] = Plane{a, a.dot(t.at[i].point) + r};
    if (dist < best) best = dist, nearest = i;
  }
  return count;
}

// The point nearest @p target with a·X >= b for every plane, by Hildreth's dual coordinate ascent
// (Hildreth 1957; exact in the limit, indifferent to parallel or redundant planes):
// X = target + Σ λ_i a_i, λ_i >= 0. @p active counts the planes left pushing (λ_i > 0).
Vec3 project(const Vec3& target, const Plane* planes, int count, double tol, int& active) noexcept {
  double lambda[kMaxTouches] = {};
  Vec3 x = target;
  for (int sweep = 0; sweep < 200; ++sweep) {
    double change = 0;
    for (int i = 0; i < count; ++i) {
      const double next = std::max(0.0, lambda[i] + (planes[i].b - planes[i].a.dot(x)));
      const double d = next - lambda[i];
      if (d != 0) x += d * planes[i].a, lambda[i] = next, change = std::max(change, std::abs(d));
    }
    if (change <= tol) break;
  }
  active = 0;
  for (int i = 0; i < count; ++i) active += lambda[i] > 0;
  return x;
}

// Stiffness and friction at the touch nearest the centre.
struct Material {
  double k, mu_s, mu_d;
};

Material material_at(const SlabModel& model, const SphereProxyParams& p, const SurfacePoint* at) noexcept {
  const ProxyParams& pp = p.proxy;
  if (!at) return {pp.force.stiffness, 0, 0};
  SlabCoordinates c;
  c.bary = Vec3(1 - at->wS - at->wT, at->wS, at->wT);
  const double k = pp.force.stiffness * interpolate_field(model, model.stiffness_scale, at->slab, c, 1.0);
  const double mu_s = pp.friction_scale * interpolate_field(model, model.friction_static, at->slab, c, 0.0);
  const double mu_d =
      std::min(mu_s, pp.friction_scale * interpolate_field(model, model.friction_dynamic, at->slab, c, 0.0));
  return {k, mu_s, mu_d};
}

// Free motion from the previous centre to @p hip in steps of r/2: the first centre whose ball
// meets the surface (then the last free one is the centre, and @p t holds what it meets), or
// false when the ball at the HIP is free.
bool sweep_to_contact(const SlabModel& model, const SlabLocator& locator, const Vec3& hip, double r,
                      const SphereProxyParams& p, SphereProxyState& s, Touches& t) noexcept {
  const Vec3 from = s.has_center ? s.center : hip;
  const double len = (hip - from).norm();
  const int most = std::max(1, p.proxy.max_tunnel_steps);
  const int steps = std::clamp(static_cast<int>(std::ceil(len / (kSweepStep * r))), 1, most);
  const Vec3 dir = len > 0 ? Vec3((hip - from) / len) : Vec3::Zero();
  Vec3 prev = from;
  for (int k = 1; k <= steps; ++k) {
    const Vec3 c = from + (hip - from) * (double(k) / steps);
    t = Touches{};
    find_touches(model, locator, c, r, dir, p, s, t);
    for (int i = 0; i < t.count; ++i)
      if ((t.at[i].point - c).norm() < r) {
        s.center = prev;
        return true;
      }
    prev = c;
  }
  return false;
}

// No contact: the ball follows the hand, from where it is (the next tick sweeps on from there
// when a round's move limit left it short of the hand).
void release(SphereProxyState& s, const Vec3& centre) noexcept {
  s.contact = false;
  s.stuck = false;
  s.planes = 0;
  s.touched_count = 0;
  s.center = centre;
  s.has_center = true;
}

// Rounds of search and solve from the current centre towards @p target (samples in the first
// round only; later rounds follow the touches found). Returns the planes left pushing; @p nearest
// is the touch nearest the centre (-1 for none).
int solve_rounds(const SlabModel& model, const SlabLocator& locator, const Vec3& target, double r,
                 const SphereProxyParams& p, SphereProxyState& s, Touches& t, int& nearest) noexcept {
  int active = 0;
  Plane planes[kMaxTouches];
  Vec3 searched = s.center;
  for (int it = 0; it < std::max(1, p.proxy.iterations); ++it) {
    if (it == 0) {
      const Vec3 d = target - s.center;
      find_touches(model, locator, s.center, r, d.norm() > 0 ? Vec3(d.normalized()) : Vec3::Zero(), p, s, t);
    } else if ((s.center - searched).norm() > kFollow * r) {
      follow_touches(model, s.center, r, t);
      searched = s.center;
    }
    const int n = planes_at(model, t, s.center, r, planes, nearest);
    const Vec3 x = project(target, planes, n, 1e-9 * r, active);
    Vec3 step = x - s.center;
    const double len = step.norm();
    if (len > kMaxMove * r) step *= kMaxMove * r / len;
    s.center += step;
    if (len <= 1e-9 * r) break;
  }
  return active;
}

// Where the ball touches, kept for the next tick's search.
void remember(const Touches& t, SphereProxyState& s) noexcept {
  s.touched_count = 0;
  for (int i = 0; i < t.count && s.touched_count < static_cast<int>(s.touched.size()); ++i)
    s.touched[s.touched_count++] =
        BallTouch{t.at[i].slab, static_cast<float>(t.at[i].wS), static_cast<float>(t.at[i].wT)};
}

// Static friction holds the ball where it was while the tangential offset of the held centre is
// within μs times the normal one (a friction cone on the frictionless centre; Melder & Harwin
// 2005); sliding, the centre trails the frictionless one by μd times the spring. On the tick the
// ball enters contact, `held` is the sweep's last free centre, clear of the surface: friction
// cannot hold it there (a push straight along the normal would keep the ball floating), so it
// starts from the solved centre.
void apply_friction(const Vec3& held, const Vec3& hip, const Vec3& n, double spring, const Material& m, bool entering,
                    SphereProxyState& s) noexcept {
  if (entering) {
    s.stuck = false;
    return;
  }
  const Vec3 hold = held - hip;
  const double hold_n = hold.dot(n);
  const double hold_t = (hold - hold_n * n).norm();
  s.stuck = hold_n > 0 && hold_t <= m.mu_s * hold_n;
  if (s.stuck) {
    s.center = held;
  } else if (m.mu_d > 0 && hold_n > 0 && hold_t > 0) {
    const Vec3 t = (hold - hold_n * n) / hold_t;  // the way the hand pulled from
    s.center += t * std::min(hold_t, m.mu_d * spring);
  }
}

}  // namespace

ProxyOutput sphere_proxy_step(const SlabModel& model, const SlabLocator& locator, const Workspace& ws,
                              const Vec3& hip_device, const Vec3& velocity, const SphereProxyParams& p,
                              SphereProxyState& s) noexcept {
  ProxyOutput out;
  if (bad_input(ws, hip_device, velocity, p.proxy) || p.samples < 6 || p.samples > kMaxBallSamples ||
      !(p.radius >= 0) || !std::isfinite(p.radius)) {
    out.status = ProxyStatus::BadInput;
    return out;
  }
  if (s.sample_count != p.samples) fill_directions(s, p.samples);
  const double r = radius_of(model, p);
  const Vec3 hip = ws.to_model(hip_device);
  Touches touches;  // a sweep's touches seed the solve
  const bool entering = !s.contact;
  if (entering && !sweep_to_contact(model, locator, hip, r, p, s, touches)) {
    release(s, hip);
    return out;
  }
  s.contact = true;
  s.has_center = true;
  const Vec3 held = s.center;
  int nearest = -1;
  s.planes = solve_rounds(model, locator, hip, r, p, s, touches, nearest);
  const Vec3 spring = s.center - hip;  // [model units]
  if (s.planes == 0 || !(spring.norm() > 0)) {
    release(s, s.planes == 0 && spring.norm() > 1e-9 * r ? s.center : hip);
    return out;
  }
  remember(touches, s);
  const Vec3 n = spring.normalized();
  const SurfacePoint* at = nearest >= 0 ? &touches.at[nearest] : nullptr;
  const Material m = material_at(model, p, at);
  apply_friction(held, hip, n, spring.norm(), m, entering, s);
  const Vec3 f = (m.k / ws.scale) * (s.center - hip);
  out.status = s.stuck ? ProxyStatus::Stuck : ProxyStatus::Sliding;
  out.normal_force = f.dot(n);
  out.friction_force = (f - out.normal_force * n).norm();
  out.mu_static = m.mu_s;
  out.mu_dynamic = m.mu_d;
  s.normal = n;
  finish_force(f, n, velocity, p.proxy, out);
  // The contact is the touched point nearest the ball's centre, as the surface there (its slab,
  // barycentrics, displacement and projection line: what a stroke of the brush starts from).
  if (at) {
    SlabCoordinates c;
    c.bary = Vec3(1 - at->wS - at->wT, at->wS, at->wT);
    evaluate_surface(model, at->slab, c, out.contact);
    out.contact.coords.alpha = out.contact.delta;
    out.contact.surface_point = at->point;
  } else {
    out.contact.surface_point = s.center - r * n;
  }
  out.contact.normal = n;
  out.contact.depth = spring.norm();
  return out;
}

}  // namespace hdm
