// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// A 6-DOF god-object for a rigid tool given as a point shell (tool_shell.h): the tool's pose is
/// held outside the displaced surface while a translational and a rotational virtual coupling pull
/// it towards the device's pose; the coupling's force and torque go to the device.
///
/// Frames: the device reports the pose of the tool's tip point (the tool frame's origin): its
/// position in metres and its orientation (tool frame to device frame), device frame. hdm::Workspace
/// maps positions to the model frame [model units]; it does not rotate, so orientations are the same
/// in both frames. The shell's points are in model units, tool frame. Force [N] and torque [N·m,
/// about the device's tip point] are returned in the device frame.

#include <hdm/haptics/force.h>
#include <hdm/haptics/tool_shell.h>

#include <array>

namespace hdm {

/// Pose of the tool's tip point as the device reports it.
struct ToolPose {
  Vec3 position = Vec3::Zero();                                     ///< tip point [m], device frame
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  ///< tool frame → device frame (need not be unit)
};

/// Velocity of the tool's tip point as the device reports it, device frame.
struct ToolTwist {
  Vec3 linear = Vec3::Zero();   ///< [m/s]
  Vec3 angular = Vec3::Zero();  ///< [rad/s]
};

/// Parameters of the rigid tool, SI at the device unless stated. Defaults suit a desktop 6-DOF
/// device at 1 kHz with a tool a few centimetres long.
struct RigidToolParams {
  double stiffness = 1000.0;      ///< translational coupling k_t [N/m]
  double damping = 1.0;           ///< translational damping b_t [N·s/m], in contact only
  double rot_stiffness = 0.2;     ///< rotational coupling k_r [N·m/rad]
  double rot_damping = 0.001;     ///< rotational damping b_r [N·m·s/rad], in contact only
  double max_force = 3.3;         ///< force clamp [N]
  double max_torque = 0.2;        ///< torque clamp [N·m]
  double position_limit_m = 1.0;  ///< tip farther than this from the workspace centre [m]: BadInput
  /// Contact band and step bound [model units]: shell points within this distance of the surface
  /// (in the shell, above it) constrain the god-object, and no shell point moves farther than this
  /// in one round, so a point that is not yet constrained cannot pass the surface; 0: 0.002 × the
  /// model's source diagonal (0.32 mm on a 16 cm workspace). Keep it below the shell's outer thickness.
  double band = 0.0;
  int rounds = 1;   ///< query + solve rounds per tick while the step bound stops the god-object (>= 1)
  int sweeps = 16;  ///< projected Gauss–Seidel sweeps per solve (>= 1)
  AlphaSolver solver = AlphaSolver::Newton;  ///< alpha-plane root finder of every shell-point query
};

/// One linearised non-penetration constraint of the solve: n·(v + ω×r) >= b.
struct ToolConstraint {
  Vec3 n = Vec3::UnitZ();   ///< outward unit surface normal at the shell point [model frame]
  Vec3 rxn = Vec3::Zero();  ///< r × n, r the point's offset from the god-object's tip [model units]
  double b = 0;             ///< required normal motion: the point's depth (> 0 inside) [model units]
  double inv_k = 0;         ///< 1 / (J·M⁻¹·Jᵀ) of the row
  double lambda = 0;        ///< its multiplier (>= 0; > 0: the point pushes)
  int32_t point = -1;       ///< shell point index
};

/// God-object state carried from tick to tick: plain data, fixed size (about 200 KB; allocate it
/// once, off the servo thread's stack), no allocation afterwards.
struct RigidToolState {
  bool has_pose = false;                                            ///< position and orientation are set
  bool contact = false;                                             ///< the last tick's god-object was pushed
  Vec3 position = Vec3::Zero();                                     ///< god-object tip [model units, model frame]
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  ///< god-object tool → model rotation (unit)
  std::array<QueryCache, kMaxToolPoints> caches{};                  ///< coherence cache per shell point
  std::array<double, kMaxToolPoints> lambda{};                      ///< last multiplier per shell point (warm start)
  std::array<ToolConstraint, kMaxToolPoints> rows{};                ///< constraints of the last solve
  int row_count = 0;                                                ///< entries of rows in use
};

/// Output of one rigid-tool tick.
struct ToolWrench {
  Vec3 force = Vec3::Zero();               ///< force on the handle [N], device frame; never NaN
  Vec3 torque = Vec3::Zero();              ///< torque on the handle about its tip point [N·m], device frame; never NaN
  ForceStatus status = ForceStatus::Free;  ///< Free, Contact, Clamped or BadInput
  int contacts = 0;                        ///< shell points pushing the god-object (multiplier > 0)
  double max_depth = 0;                    ///< deepest shell point at the last query round [model units], 0 if none
};

/// @brief One tick of the 6-DOF god-object: move the tool's pose towards the device's as far as the
/// surface lets it, and render the coupling's force and torque.
///
/// Each round queries every shell point at the god-object's pose (hdm::query, one coherence cache per
/// point). A point in the shell on a surface it can touch (normal within 120° of the point's inward
/// normal) and within `band` of it or below it gives a row n·(v + ω×r) >= depth, the non-penetration
/// constraint linearised in the god-object's displacement (v [model units], ω [rad], about the tip).
/// n is the surface's normal there, except at an edge the shell does not resolve: a row whose
/// normal is more than 20° from the tool's normal at its point, and whose point pushed on the last
/// tick or is below the surface, probes the surface 8·`band` away along the tool's normal's lean;
/// if the surface's normal has turned that far towards it there, the row takes the tool's normal projected on
/// the plane in which the surface turns (the normal the tool and the edge share, which the shell
/// point nearest it, up to about the shell's spacing off, does not see in the surface's normal).
/// The displacement is the one nearest the unconstrained motion a = (device − god-object position,
/// rotation vector of device·god⁻¹) in the metric M = diag(k_t/scale²·I, k_r·I) that meets every
/// row: Gauss's principle of least constraint (Redon, Kheddar & Coquillart 2002), solved by
/// projected Gauss–Seidel over the rows' multipliers (Hildreth's method in the M metric), warm
/// started from the last tick's. With the coupling's stiffness as the metric the step lands on the
/// coupling's quasi-static equilibrium with the contacts, so force and torque balance the contact
/// wrench (Ortega, Redon & Coquillart 2007 use the god-object's inertia and integrate; this is the
/// limit of that for a massless god-object). The displacement is scaled down so that no shell point
/// moves more than `band`; the next round (up to `rounds`) goes on from there. A god-object that no
/// row pushes is free: zero wrench.
///
/// Force F = k_t·(god − device position)/scale − b_t·v, torque τ = k_r·θ − b_r·ω, θ the rotation
/// vector of god·device⁻¹ (each damping term only in contact, and no larger than its spring term),
/// then clamped to max_force and max_torque (status Clamped). Since F is parallel to the
/// god−device offset, τ is the contact wrench's moment about the device's tip point as well as the
/// god-object's.
///
/// @param model    slab model (derived data built).
/// @param locator  its search structure.
/// @param ws       device [m] ↔ model transform.
/// @param shell    the tool's points and inward normals [model units, tool frame], #P in [1, kMaxToolPoints].
/// @param device   tip position [m] and orientation (tool → device), device frame.
/// @param velocity tip velocity [m/s] and angular velocity [rad/s], device frame.
/// @param params   see RigidToolParams.
/// @param state    carried state, updated; a new state starts the god-object at the device's pose.
/// @return wrench and status; BadInput (zero wrench, state unchanged) for a non-finite or
///         out-of-limit position, a non-finite or zero quaternion, non-finite velocities, a shell
///         with #P outside [1, kMaxToolPoints] or normals not matching points, non-positive
///         stiffnesses, sweeps or rounds, negative or NaN limits, or a negative or non-finite band.
/// @pre @p shell does not change between ticks of one @p state (its per-point caches and
///      multipliers are indexed by point). The first tick of a state puts the tool in free space:
///      only shell points in the shell of slabs are seen, so a god-object started deeper inside
///      the model than the shell is not pushed out.
/// @throws none; noexcept.
/// @note No allocation, no locks, no I/O. Cost per round: #P queries (one slab test each when
///       coherent, less for points in no slab's cell), one to four more per row at an edge, plus
///       `sweeps` × rows constraint updates (about 20 flops each). `hdm bench` reports the tick
///       with a 1,000-point burr (docs/haptics.md).
/// @see McNeely, Puterbaugh & Troy 1999 (point shell, virtual coupling); Redon, Kheddar &
///      Coquillart 2002 (Gauss's principle of least constraint); Ortega, Redon & Coquillart 2007
///      (a 6-DOF god-object with it); Hildreth 1957 (the projection); docs/haptics.md.
ToolWrench rigid_tool_step(const SlabModel& model, const SlabLocator& locator, const Workspace& ws,
                           const ToolShell& shell, const ToolPose& device, const ToolTwist& velocity,
                           const RigidToolParams& params, RigidToolState& state) noexcept;

}  // namespace hdm
