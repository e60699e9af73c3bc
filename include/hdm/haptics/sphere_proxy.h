// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// A spherical god-object: a ball of radius r held outside the displaced surface, so the user
/// feels the tool's size (it rolls around convex edges and cannot enter a gap narrower than 2r),
/// with contacts found from the slab field and the displaced surface's own triangles.
///
/// Frames as in proxy.h: the HIP (the ball's centre on the device) in metres, device frame; the
/// ball in the model frame [model units]; forces in newtons, device frame.

#include <hdm/haptics/proxy.h>

#include <array>

namespace hdm {

/// Most points on the ball's surface that SphereProxyParams::samples may ask for.
inline constexpr int kMaxBallSamples = 128;

/// Parameters of the sphere proxy.
struct SphereProxyParams {
  /// Stiffness [N/m], damping [N·s/m], force limit [N], friction scale, alpha-plane solver,
  /// position limit [m], as for the point proxy. `iterations` is the number of contact-gathering
  /// and constraint-solving rounds per tick (>= 1); `max_tunnel_steps` caps the free-space sweep.
  ProxyParams proxy;
  double radius = 0;  ///< ball radius r [model units]; 0: 0.01 × the model's source diagonal
  int samples = 32;   ///< points on the ball's surface queried to find touched regions, in [6, kMaxBallSamples]
};

/// Where the ball touched the surface: a slab and barycentrics, where the next tick's search starts.
struct BallTouch {
  int32_t slab = -1;    ///< slab id
  /// @{ Barycentrics (wS, wT) in it.
  float wS = 0, wT = 0;
  /// @}
};

/// Ball state carried from tick to tick: plain data, no allocation.
struct SphereProxyState {
  bool contact = false;          ///< the ball is held by the surface
  bool stuck = false;            ///< static friction holds it (contact only)
  Vec3 center = Vec3::Zero();    ///< the ball's centre (god-object) [model units]
  Vec3 normal = Vec3::UnitZ();   ///< unit direction from the HIP to the centre (contact only)
  int planes = 0;                ///< constraint planes active at the last solve (contact only)
  bool has_center = false;       ///< center holds a previous position
  int sample_count = 0;          ///< directions below are for this many samples
  std::array<Vec3, kMaxBallSamples> directions{};  ///< unit sample directions (Fibonacci sphere)
  std::array<QueryCache, kMaxBallSamples> caches{};  ///< one coherence cache per sample point
  std::array<BallTouch, 4> touched{};  ///< where the ball touched last tick (contact only)
  int touched_count = 0;               ///< entries of touched in use
  int sample_phase = 0;                ///< which of every `stride` samples the next held tick queries
  Vec3 searched = Vec3::Constant(NAN);  ///< the centre at the last tick's sample search [model units]
};

/// @brief One tick of the sphere proxy: move the ball towards the HIP as far as the surface lets it.
///
/// Contacts: the slab field is queried (hdm::query) at `samples` points C + r·u_k of the ball's
/// surface (u_k a Fibonacci sphere, those facing the HIP; while the ball is held, one in every m
/// per tick, in turn, with m as large as lets the ball move no more than r/2 in m ticks at its
/// last tick's speed, at most 8); a point in the shell whose surface
/// contact point lies within 1.5 r seeds a search for the point of the displaced surface nearest
/// the centre (a descent over the slabs' grid triangles, the surface the renderer draws, crossing
/// slab edges), as do the places the ball touched last tick. Each such point cp within 1.05 r
/// constrains the centre X: a·X >= a·cp + r, with a the force-shading normal at cp where it is
/// within 5° of C − cp (so the ball rolls over the grid's facets without their steps, as the
/// point proxy slides) and the direction C − cp beyond 15° (sharp edges), blended between. The
/// centre is the point nearest the HIP that meets every constraint (Hildreth's projection; a
/// god-object with several constraint planes as in Ruspini, Kolarov & Khatib 1997). Further
/// rounds (`proxy.iterations`) search again from the points found, so a point stays a constraint
/// while the ball moves (two at once in a groove). A round moves the centre at most r/4. Free
/// motion is swept from the previous centre in steps of r/2 (at most `max_tunnel_steps`), so a
/// fast hand does not pass a thin part. Static friction holds the ball while the tangential
/// spring force is within μs times the normal one; sliding keeps it at μd (coefficients and the
/// stiffness scale interpolated where the ball touches, as the point proxy reads them).
/// Force F = k·s·(C − HIP)/scale, damped along C − HIP as the point proxy (Hunt & Crossley ramp,
/// never pulling), clamped to max_force.
///
/// @param model  slab model (derived data built).
/// @param locator  its search structure.
/// @param ws  device [m] ↔ model transform.
/// @param hip_device  the ball's centre on the device [m], device frame.
/// @param velocity  its velocity [m/s], device frame.
/// @param params  see SphereProxyParams.
/// @param state  carried state, updated.
/// @return force and status; BadInput (zero force, state unchanged) for a non-finite HIP or
///         velocity, a HIP beyond the position limit, samples outside [6, kMaxBallSamples], or a
///         negative or non-finite radius.
/// @note noexcept, no allocation, no locks, no I/O. Cost: about `samples`/2 queries (each one slab
///       test when coherent) and one nearest-point descent per touched region (about 50 triangle
///       tests per 5 × 5-cell window) in the first round, one descent per touch in the others;
///       while free, the same search at each sweep step. `hdm bench` reports the tick.
/// @see Ruspini, Kolarov & Khatib 1997 (god-object with several constraint planes); McNeely,
///      Puterbaugh & Troy 1999 (tool points queried against the model); Hildreth 1957 (the
///      projection); docs/haptics.md.
ProxyOutput sphere_proxy_step(const SlabModel& model, const SlabLocator& locator, const Workspace& ws,
                              const Vec3& hip_device, const Vec3& velocity, const SphereProxyParams& params,
                              SphereProxyState& state) noexcept;

}  // namespace hdm
