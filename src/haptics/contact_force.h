// SPDX-License-Identifier: MIT
#pragma once
// The input guard and the force output shared by the point and sphere proxies (internal).

#include <hdm/haptics/proxy.h>

#include <algorithm>
#include <cmath>

namespace hdm::haptics_detail {

// A HIP or velocity that is not finite, a HIP outside the position limit, or a broken workspace.
inline bool bad_input(const Workspace& ws, const Vec3& hip_device, const Vec3& velocity, const ProxyParams& p) noexcept {
  if (!hip_device.allFinite() || !velocity.allFinite()) return true;
  if (!(hip_device.norm() <= p.position_limit_m)) return true;
  return !std::isfinite(ws.scale) || !(ws.scale > 0) || !ws.origin.allFinite();
}

// Normal damping, "never pull" on the normal part, then the max-force clamp. The damping
// coefficient grows with the spring force k·depth up to the full b at damping_force_n (Hunt &
// Crossley 1975: a damper that scales with the contact force), so a contact starts with the spring
// alone instead of a step of b·v_n (at 5 cm/s and b = 1 N·s/m, 1.5 % of a 3.3 N device in one
// tick). Scaling with force rather than depth keeps the full b in a press-and-hold at any
// stiffness, so the stability limits stay those of b. It is also bounded by the spring along the
// normal (|b·v_n| <= k·depth), so it can never pull.
inline void finish_force(Vec3 f, const Vec3& n, const Vec3& velocity, const ProxyParams& p, ProxyOutput& out) noexcept {
  const ForceParams& fp = p.force;
  const double spring = std::max(f.dot(n), 0.0);
  const double ramp = p.damping_force_n > 0 ? std::min(1.0, spring / p.damping_force_n) : 1.0;
  f += std::clamp(-ramp * fp.damping * velocity.dot(n), -spring, spring) * n;
  const double fn = f.dot(n);
  if (fn < 0) f -= fn * n;
  const double mag = f.norm();
  if (mag > fp.max_force) {
    f *= fp.max_force / mag;
    out.status = ProxyStatus::Clamped;
  }
  out.force = f.allFinite() ? f : Vec3::Zero();
}

}  // namespace hdm::haptics_detail
