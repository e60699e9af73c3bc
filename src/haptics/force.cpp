// SPDX-License-Identifier: MIT
#include <hdm/haptics/force.h>

#include <algorithm>
#include <cmath>

namespace hdm {

Workspace fit_workspace(const Aabb& box, double workspace_m) {
  Workspace ws;
  ws.origin = 0.5 * (box.min + box.max);
  ws.scale = std::max(box.diagonal(), 1e-300) / workspace_m;
  return ws;
}

ForceSample penalty_force(const Contact& c, const Vec3& velocity, const ForceParams& p, const Workspace& ws) noexcept {
  ForceSample out;
  if (!velocity.allFinite() || !std::isfinite(c.depth) || !c.normal.allFinite()) {
    out.status = ForceStatus::BadInput;
    return out;
  }
  if (!c.penetrating()) return out;
  const double depth_m = c.ray_depth() / ws.scale;  // the paper's force: depth along the ray (§3.3)
  const double vn = velocity.dot(c.normal);
  Vec3 f = (p.stiffness * depth_m - p.damping * vn) * c.normal;
  if (f.dot(c.normal) < 0) f.setZero();  // a surface never pulls the handle in
  out.status = ForceStatus::Contact;
  const double mag = f.norm();
  if (mag > p.max_force) {
    f *= p.max_force / mag;
    out.status = ForceStatus::Clamped;
  }
  out.force = f;
  return out;
}

}  // namespace hdm
