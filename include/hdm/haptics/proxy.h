// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// The proxy (god-object) held on the reconstructed displacement surface: no pop-through, force
/// shading and static/dynamic friction, with the paper's memoryless penalty force kept as a mode
/// (Zilles & Salisbury 1995; Ruspini, Kolarov & Khatib 1997; docs/design.md#force-and-proxy).
///
/// Frames: the device reports the haptic interaction point (HIP) in metres (device frame); the
/// proxy lives in the model frame [model units]; hdm::Workspace maps between them. Forces are
/// returned in newtons in the device frame.

#include <hdm/haptics/force.h>
#include <hdm/slab/slab_model.h>

#include <array>

namespace hdm {

/// Force model of a HapticRenderer.
enum class RenderMode : uint8_t {
  Proxy,    ///< god-object on the displaced surface (default)
  Penalty,  ///< the paper's memoryless SCP = HIP + n·depth (paper §3.4), for comparison
  Sphere,   ///< a ball of the tool's radius held outside the surface (sphere_proxy_step(), sphere_proxy.h)
  /// A rigid 6-DOF tool (a point shell) held outside the surface, force and torque
  /// (rigid_tool_step(), rigid_tool.h); hdm::SculptSession runs it. parse_render_mode() reads it as "rigid".
  RigidTool,
};

/// Parameters of the proxy, SI at the device unless stated. Defaults suit a desktop device
/// (Phantom Omni / Touch class) at 1 kHz.
struct ProxyParams {
  ForceParams force;              ///< stiffness k [N/m], damping b [N·s/m] along the normal, max force [N]
  double damping_force_n = 0.2;   ///< spring force k·depth [N] at which the normal damping reaches force.damping;
                                  ///< it ramps in linearly from 0 at contact (Hunt & Crossley 1975), so a
                                  ///< contact starts without a damping step; 0: full damping at once
  double friction_scale = 1.0;    ///< factor on the per-sample μs, μd of SlabModel (0: frictionless)
  int iterations = 3;             ///< tangent-plane projection + re-projection rounds per tick (>= 1)
  int max_halvings = 6;           ///< step halvings when a candidate leaves the shell or turns too far
  double max_turn_deg = 30.0;     ///< largest change of the proxy's normal accepted per step [deg]
  double position_limit_m = 1.0;  ///< HIP farther than this from the workspace centre [m]: BadInput, zero force
  double tunnel_step = 0.0;       ///< free-space sub-step [model units] to catch a HIP that jumps across a
                                  ///< thin part in one tick; 0: 0.002 × the model's source diagonal
  int max_tunnel_steps = 16;      ///< cap on free-space sub-steps per tick
  AlphaSolver solver = AlphaSolver::Newton;  ///< alpha-plane root finder of every slab lookup (paper: Bisection)
  /// Depth below the under-layer's top over which its stiffness and friction replace the surface's
  /// [model units] (layer_exposure()); 0: 0.0005 × the model's source diagonal (0.08 mm on a 16 cm
  /// workspace), narrow enough to feel the boundary, wide enough that the force never steps.
  double layer_band = 0.0;
};

/// Status of one proxy tick.
enum class ProxyStatus : uint8_t {
  Free,      ///< no contact: proxy = HIP, zero force
  Stuck,     ///< in contact, proxy held by static friction
  Sliding,   ///< in contact, proxy moved (frictionless or dynamic friction)
  Clamped,   ///< in contact, force clamped to max_force
  BadInput,  ///< non-finite or out-of-range HIP / velocity: zero force, proxy state kept
};

/// Proxy state carried from tick to tick. Plain data, no allocation: copyable into a servo
/// thread's storage.
struct ProxyState {
  bool contact = false;          ///< proxy is on the surface
  bool stuck = false;            ///< static friction holds the proxy (only meaningful in contact)
  int32_t slab = -1;             ///< proxy's slab (contact only)
  SlabCoordinates coords;        ///< proxy's (α = δ, barycentrics) in that slab (contact only)
  Vec3 position = Vec3::Zero();  ///< proxy [model units]: on the displaced surface in contact, else the HIP
  Vec3 normal = Vec3::UnitZ();   ///< interpolated unit normal at the proxy (contact only)
  Vec3 last_hip = Vec3::Zero();  ///< previous finite HIP [model units]
  bool has_last_hip = false;     ///< last_hip is valid
  QueryCache hip_cache;          ///< coherence cache of the HIP queries (free motion)
  QueryCache proxy_cache;        ///< coherence cache of the proxy re-projections
  /// Slab of `surface_records` (-1: none). With them, what the proxy's surface point and normal
  /// were evaluated from: a tick whose grid records under the proxy are unchanged (no edit touched
  /// them) reuses the point and normal instead of evaluating them again (the same values).
  int32_t surface_slab = -1;
  std::array<SlabSample, 3> surface_records{};  ///< the grid triangle's three records (SlabSample) as read
};

/// Output of one tick.
struct ProxyOutput {
  Vec3 force = Vec3::Zero();               ///< force on the handle [N], device frame; never NaN
  ProxyStatus status = ProxyStatus::Free;  ///< free, in contact, clamped or bad input
  Contact contact;                         ///< contact at the proxy (slab, coords, surface point, normal) with
                                           ///< depth = (proxy - HIP)·n [model units] > 0; slab -1 when free
  double normal_force = 0;                 ///< k·depth [N] before damping and clamping
  double friction_force = 0;               ///< tangential spring force |F_t| [N]
  /// @{ Static and dynamic friction coefficients interpolated at the proxy.
  double mu_static = 0, mu_dynamic = 0;
  /// @}
};

/// @brief Interpolates a per-sample field at slab coordinates (the grid triangle and weights of
/// evaluate_surface, docs/design.md#query).
/// @param model     slab model with derived data.
/// @param field     #samples values (e.g. SlabModel::friction_static); empty: returns @p fallback.
/// @param slab      slab id in [0, #S).
/// @param c         coordinates in that slab (locate_in_slab()).
/// @param fallback  value returned for an empty @p field.
/// @note noexcept, O(1), real-time safe.
double interpolate_field(const SlabModel& model, const std::vector<float>& field, int slab, const SlabCoordinates& c,
                         double fallback) noexcept;
/// @brief interpolate_field() of a binary16 field (SlabModel::friction_static, friction_dynamic,
/// hardness); a uniform field returns its value without finding the grid cell.
double interpolate_field(const SlabModel& model, const SampleField<Half16>& field, int slab, const SlabCoordinates& c,
                         double fallback) noexcept;
/// @brief interpolate_field() of a unorm16 field (SlabModel::stiffness_scale, layer_displacement);
/// a uniform field returns its value without finding the grid cell.
double interpolate_field(const SlabModel& model, const SampleField<Unorm16>& field, int slab, const SlabCoordinates& c,
                         double fallback) noexcept;

/// @brief One proxy tick: update the god-object from the HIP and compute the force.
///
/// Free: the HIP is queried; while it does not penetrate the proxy follows it. On the first
/// penetration (also found on free-space sub-steps when the HIP jumps) the proxy is set on the
/// surface point of the HIP's projection line. In contact the proxy is moved towards the HIP in
/// its interpolated tangent plane and re-projected onto the displaced surface, params.iterations
/// rounds: within its slab by one Newton step of the slab map from the proxy's coordinates,
/// across slab edges and corners through SlabLocator::find. A step is halved when it leaves the
/// shell, lands on a surface facing away, turns the normal by more than max_turn_deg, or does not
/// reduce the tangential residual. Static friction holds it while |F_t| <= μs·F_n, otherwise it
/// slides so that |F_t| = μd·F_n. Stiffness scale and friction are the per-sample fields
/// interpolated at the proxy, or the under-layer's (SlabModel::under_layer) where the proxy is below the layer's top
/// (blended over ProxyParams::layer_band); they are read on every tick, so painting them is felt
/// on the next. Contact lasts while (HIP - proxy)·n_proxy < 0, whatever the HIP's own query
/// says, so it holds past the inner face and through thin parts. Force
/// F = k·s·(proxy - HIP)/scale - b'·(v·n)·n with b' = b·min(1, k·depth/damping_force_n) (Hunt &
/// Crossley 1975) and |b'·(v·n)| <= k·depth, normal part never pulling, clamped to max_force.
///
/// @param model     slab model (derived data built).
/// @param locator   its search structure.
/// @param ws        device [m] ↔ model transform.
/// @param hip_device  HIP [m], device frame.
/// @param velocity    HIP velocity [m/s], device frame.
/// @param params    see ProxyParams.
/// @param state     carried state, updated.
/// @return force and status; BadInput (zero force, state unchanged) when the HIP or velocity is
///         not finite or farther than params.position_limit_m from the workspace centre.
/// @note noexcept, no allocation, no locks, no I/O. Cost: up to params.iterations surface
///       evaluations, each after a 3 × 3 solve (a locator find when the step leaves the slab);
///       181-184 ns median on the bunny (`hdm bench`, half the ticks in contact).
/// @see Zilles & Salisbury 1995; Ruspini et al. 1997 (proxy, force shading, friction);
///      Melder & Harwin 2005 (friction cone); docs/design.md#force-and-proxy.
ProxyOutput proxy_step(const SlabModel& model, const SlabLocator& locator, const Workspace& ws, const Vec3& hip_device,
                       const Vec3& velocity, const ProxyParams& params, ProxyState& state) noexcept;

/// @brief The same interface for the paper's penalty force (RenderMode::Penalty): query the HIP,
/// SCP = HIP + n·depth, F = k·depth·n - b·(v·n)·n (hdm::penalty_force).
/// @note noexcept, real-time safe; state keeps only the query cache and last HIP. The proxy
///       fields of the output hold the SCP.
ProxyOutput penalty_step(const SlabModel& model, const SlabLocator& locator, const Workspace& ws,
                         const Vec3& hip_device, const Vec3& velocity, const ProxyParams& params,
                         ProxyState& state) noexcept;

/// @brief Dispatches the point renderers: proxy_step() or penalty_step().
/// @return their output; BadInput (zero force, state unchanged) for RenderMode::Sphere and
///         RenderMode::RigidTool, which carry their own state (sphere_proxy_step(),
///         rigid_tool_step(); hdm::SculptSession runs any).
/// @note noexcept, real-time safe.
inline ProxyOutput render_step(RenderMode mode, const SlabModel& model, const SlabLocator& locator, const Workspace& ws,
                               const Vec3& hip_device, const Vec3& velocity, const ProxyParams& params,
                               ProxyState& state) noexcept {
  if (mode == RenderMode::Proxy) return proxy_step(model, locator, ws, hip_device, velocity, params, state);
  if (mode == RenderMode::Penalty) return penalty_step(model, locator, ws, hip_device, velocity, params, state);
  ProxyOutput bad;
  bad.status = ProxyStatus::BadInput;
  return bad;
}

/// @brief Parses "newton" or "bisection" (the alpha-plane root finder, hdm::AlphaSolver).
/// @throws InvalidInput for any other name, naming it.
AlphaSolver parse_alpha_solver(const std::string& name);

/// @brief Parses a render mode's name: "proxy", "penalty", "sphere" or "rigid" (RenderMode::RigidTool).
/// @throws InvalidInput for any other name, naming it.
RenderMode parse_render_mode(const std::string& name);

}  // namespace hdm
