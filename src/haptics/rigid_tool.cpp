// SPDX-License-Identifier: MIT
#include <hdm/haptics/rigid_tool.h>

#include "rotation.h"

#include <algorithm>
#include <cmath>

namespace hdm {
namespace {

using Quat = Eigen::Quaterniond;
using haptics_detail::from_rotation_vector;
using haptics_detail::rotation_vector;

// A shell point may be pushed by a surface whose outward normal is within this cosine of the
// point's inward normal (120°): a surface facing the tool's inside is the far side of a thin part.
constexpr double kFacing = -0.5;

// A row whose surface normal is farther than this cosine (20°) from the tool's normal at its point
// may be at an edge of the surface: see contact_normal.
constexpr double kEdgeGap = 0.9396926207859084;

// The god-object's displacement: v [model units] and ω [rad] about the tip, model frame.
struct Twist {
  Vec3 v = Vec3::Zero(), w = Vec3::Zero();
};

// The inverse of the metric M = diag(k_t/scale²·I, k_r·I).
struct Metric {
  double t, r;
};

// Input the tick refuses (BadInput): the state is then left as it is.
bool bad_input(const Workspace& ws, const ToolShell& shell, const ToolPose& d, const ToolTwist& v,
               const RigidToolParams& p) noexcept {
  if (!d.position.allFinite() || !d.orientation.coeffs().allFinite() || !(d.orientation.norm() > 1e-6)) return true;
  if (!v.linear.allFinite() || !v.angular.allFinite() || !(d.position.norm() <= p.position_limit_m)) return true;
  if (!std::isfinite(ws.scale) || !(ws.scale > 0) || !ws.origin.allFinite()) return true;
  const size_t n = shell.points.size();
  if (n < 1 || n > size_t(kMaxToolPoints) || shell.normals.size() != n) return true;
  if (!(p.stiffness > 0) || !(p.rot_stiffness > 0) || !(p.max_force >= 0) || !(p.max_torque >= 0)) return true;
  return p.sweeps < 1 || p.rounds < 1 || !(p.band >= 0) || !std::isfinite(p.band);
}

double band_of(const SlabModel& model, const RigidToolParams& p) noexcept {
  if (p.band > 0) return p.band;
  return 0.002 * (model.source_diagonal > 0 ? model.source_diagonal : 1.0);
}

// The contact normal of a shell point: @p c its query, @p nt the tool's inward normal there.
// Where the surface turns within a few bands (a convex edge the bake has rounded over a grid cell),
// the true contact lies where the surface's normal meets the tool's, and the shell point in contact
// is up to about its spacing from it, where the surface's normal can be tens of degrees off: the
// normal is then the tool's, with the part along the edge (where the surface does not turn)
// removed. A surface that does not turn so fast (a face, a large curvature radius) gives its own
// normal, as does a sharp part of the tool (a rim) on it.
Vec3 contact_normal(const SlabModel& model, const SlabLocator& locator, const Contact& c, const Vec3& nt, double band,
                    QueryCache cache, AlphaSolver solver) noexcept {
  const Vec3& ns = c.normal;
  const double gap = ns.dot(nt);
  if (gap > kEdgeGap) return ns;
  const Vec3 u = (nt - gap * ns).normalized();
  // One probe where the surface's normal has turned the most (it turns one way along a convex
  // edge); nearer ones only when the farther probes leave the shell.
  for (double e = 8 * band; e >= band; e *= 0.5) {
    const Contact q = query(model, locator, c.surface_point + e * u, cache, solver);
    if (!q.in_shell()) continue;
    const Vec3 turn = q.normal - q.normal.dot(ns) * ns;
    if (!(turn.norm() > 1e-6)) continue;
    const Vec3 d = turn.normalized();  // the way the surface turns: towards the tool's normal at a convex edge
    const double lean = nt.dot(d);
    if (!(lean > 0)) return ns;
    const Vec3 n = (gap * ns + lean * d).normalized();
    return q.normal.dot(d) >= n.dot(d) ? n : ns;
  }
  return ns;
}

// Queries every shell point at the god-object's pose and writes the rows of those near or below the
// surface, warm-started from the multipliers they had. Returns the shell's reach max |r| [model
// units]; @p deepest is the largest depth among the rows (0 for none).
double gather(const SlabModel& model, const SlabLocator& locator, const ToolShell& shell, double band, const Metric& m,
              const RigidToolParams& p, RigidToolState& s, double& deepest) noexcept {
  const Eigen::Matrix3d R = s.orientation.toRotationMatrix();
  const int n = static_cast<int>(shell.points.size());
  double reach = 0;
  deepest = 0;
  s.row_count = 0;
  for (int i = 0; i < n; ++i) {
    const Vec3 r = R * shell.points[i];
    reach = std::max(reach, r.norm());
    const Contact c = query(model, locator, s.position + r, s.caches[i], p.solver);
    const double warm = s.lambda[i];
    s.lambda[i] = 0;
    if (!c.in_shell() || !(c.depth > -band) || c.normal.dot(R * shell.normals[i]) < kFacing) continue;
    ToolConstraint& row = s.rows[s.row_count++];
    // Only a point that pushed last tick or is below the surface can push: the others keep the
    // surface's normal and save contact_normal's probe.
    const bool can_push = warm > 0 || c.depth > 0;
    row.n = can_push ? contact_normal(model, locator, c, R * shell.normals[i], band, s.caches[i], p.solver) : c.normal;
    row.rxn = r.cross(row.n);
    row.b = c.depth;
    row.inv_k = 1.0 / (m.t + m.r * row.rxn.squaredNorm());
    row.lambda = warm;
    row.point = i;
    deepest = std::max(deepest, c.depth);
  }
  return reach;
}

// The displacement nearest @p a in the M metric with every row met: x = a + M⁻¹Jᵀλ, λ >= 0, by
// projected Gauss–Seidel over the multipliers (Hildreth 1957 in the M metric), from the rows' warm
// starts. Returns the rows left pushing.
int solve(const Twist& a, const Metric& m, int sweeps, RigidToolState& s, Twist& x) noexcept {
  x = a;
  for (int k = 0; k < s.row_count; ++k) {
    const ToolConstraint& row = s.rows[k];
    x.v += (m.t * row.lambda) * row.n;
    x.w += (m.r * row.lambda) * row.rxn;
  }
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    double change = 0;
    for (int k = 0; k < s.row_count; ++k) {
      ToolConstraint& row = s.rows[k];
      const double miss = row.b - (row.n.dot(x.v) + row.rxn.dot(x.w));
      const double next = std::max(0.0, row.lambda + miss * row.inv_k);
      const double d = next - row.lambda;
      if (d == 0) continue;
      row.lambda = next;
      x.v += (m.t * d) * row.n;
      x.w += (m.r * d) * row.rxn;
      change = std::max(change, std::abs(d) / row.inv_k);  // the row's motion [model units]
    }
    if (change < 1e-9) break;
  }
  int pushing = 0;
  for (int k = 0; k < s.row_count; ++k) {
    s.lambda[s.rows[k].point] = s.rows[k].lambda;
    pushing += s.rows[k].lambda > 0;
  }
  return pushing;
}

// Moves the god-object by @p x, scaled down so that no shell point (reach @p reach) moves more than
// @p band. Returns true when it was scaled down (the target is not reached).
bool move(Twist x, double reach, double band, RigidToolState& s) noexcept {
  const double travel = x.v.norm() + x.w.norm() * reach;
  const bool limited = travel > band;
  if (limited) {
    x.v *= band / travel;
    x.w *= band / travel;
  }
  s.position += x.v;
  s.orientation = (from_rotation_vector(x.w) * s.orientation).normalized();
  return limited;
}

// A damping term no larger than its spring term.
Vec3 bounded_damping(const Vec3& damping, const Vec3& spring) noexcept {
  const double d = damping.norm(), cap = spring.norm();
  return d > cap ? Vec3(damping * (cap / d)) : damping;
}

// The coupling's wrench from the god-object to the device, damped and clamped.
void coupling_wrench(const Workspace& ws, const Vec3& target, const Quat& target_q, const ToolTwist& velocity,
                     const RigidToolParams& p, const RigidToolState& s, ToolWrench& out) noexcept {
  const Vec3 f = (p.stiffness / ws.scale) * (s.position - target);
  const Vec3 t = p.rot_stiffness * rotation_vector(s.orientation * target_q.conjugate());
  Vec3 force = f + bounded_damping(-p.damping * velocity.linear, f);
  Vec3 torque = t + bounded_damping(-p.rot_damping * velocity.angular, t);
  out.status = ForceStatus::Contact;
  if (force.norm() > p.max_force) force *= p.max_force / force.norm(), out.status = ForceStatus::Clamped;
  if (torque.norm() > p.max_torque) torque *= p.max_torque / torque.norm(), out.status = ForceStatus::Clamped;
  out.force = force.allFinite() ? force : Vec3::Zero();
  out.torque = torque.allFinite() ? torque : Vec3::Zero();
}

}  // namespace

ToolWrench rigid_tool_step(const SlabModel& model, const SlabLocator& locator, const Workspace& ws,
                           const ToolShell& shell, const ToolPose& device, const ToolTwist& velocity,
                           const RigidToolParams& p, RigidToolState& s) noexcept {
  ToolWrench out;
  if (bad_input(ws, shell, device, velocity, p)) {
    out.status = ForceStatus::BadInput;
    return out;
  }
  const Vec3 target = ws.to_model(device.position);
  const Quat target_q = device.orientation.normalized();
  if (!s.has_pose) {
    s.position = target;
    s.orientation = target_q;
    s.lambda.fill(0);
    s.has_pose = true;
  }
  const double band = band_of(model, p);
  const Metric m{ws.scale * ws.scale / p.stiffness, 1.0 / p.rot_stiffness};
  int pushing = 0;
  for (int round = 0; round < p.rounds; ++round) {
    const double reach = gather(model, locator, shell, band, m, p, s, out.max_depth);
    Twist a, x;
    a.v = target - s.position;
    a.w = rotation_vector(target_q * s.orientation.conjugate());
    pushing = solve(a, m, p.sweeps, s, x);
    if (!move(x, reach, band, s)) break;
  }
  s.contact = pushing > 0;
  out.contacts = pushing;
  if (!s.contact) return out;
  coupling_wrench(ws, target, target_q, velocity, p, s, out);
  return out;
}

}  // namespace hdm
