// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Workspace mapping and the penalty force of the paper (§3.4), in SI units at the device.

#include <hdm/query/slab_query.h>

namespace hdm {

/// Maps device space [m] to model space [model units]: x_model = origin + scale·x_device.
struct Workspace {
  Vec3 origin = Vec3::Zero();  ///< model point at the device's workspace centre [model units]
  double scale = 1.0;          ///< model units per metre of device motion
  /// Device point [m] to model point [model units].
  Vec3 to_model(const Vec3& device) const noexcept { return origin + scale * device; }
  /// Model point [model units] to device point [m].
  Vec3 to_device(const Vec3& model) const noexcept { return (model - origin) / scale; }
};

/// @brief Workspace that fits the model's bounding box diagonal into a device workspace of
/// @p workspace_m metres (default 0.16 m, a desktop device), centred on the box.
Workspace fit_workspace(const Aabb& model_box, double workspace_m = 0.16);

/// Force-rendering parameters, SI at the device.
struct ForceParams {
  double stiffness = 1000.0;  ///< k_s [N/m], as felt at the device
  double damping = 1.0;       ///< b [N·s/m], along the normal while in contact
  double max_force = 3.3;     ///< clamp [N] (device limit)
};

/// Status of one force evaluation.
enum class ForceStatus : uint8_t {
  Free,      ///< no penetration: zero force
  Contact,   ///< in contact: force rendered
  Clamped,   ///< in contact, force clamped to max_force
  BadInput,  ///< non-finite position or velocity: zero force
};

/// Rendered force.
struct ForceSample {
  Vec3 force = Vec3::Zero();               ///< force on the device handle [N], device frame
  ForceStatus status = ForceStatus::Free;  ///< what the force evaluation found
};

/// @brief Penalty force F = k_s·depth·n - b·(v·n)·n with the paper's depth along the ray
/// (Contact::ray_depth), clamped to max_force (paper §3.3-3.4; design
/// notes §4.5). depth is converted to metres through @p ws.
/// @param contact   query answer at the HIP.
/// @param velocity  device velocity [m/s].
/// @param params    stiffness [N/m], damping [N·s/m] and force limit [N].
/// @param ws        device ↔ model mapping (converts depth to metres).
/// @return zero force and BadInput for a non-finite velocity or contact, never NaN.
/// @note noexcept, O(1), real-time safe. The surface contact point of the paper is
///       SCP = HIP + n·depth; this force is the spring towards it.
ForceSample penalty_force(const Contact& contact, const Vec3& velocity, const ForceParams& params,
                          const Workspace& ws) noexcept;

}  // namespace hdm
