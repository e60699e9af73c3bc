// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Scripted haptic scenarios ("does it feel right?"): a simulated device and hand drive the proxy
/// or penalty renderer on a slab model, and the run is scored against an independent reference,
/// the exact input mesh (docs/design.md#how-we-measure).

#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/haptics/device.h>
#include <hdm/haptics/proxy.h>

#include <string>
#include <vector>

namespace hdm {

/// The scenarios of `hdm feel`.
enum class Scenario : uint8_t {
  Slide,  ///< there and back along the smoothest exposed stroke (ScenarioSites::slide_stroke) at `speed_m_s`,
          ///< the hand pressing with `press_force_n`
  Press,  ///< push along -n into the thickest smooth spot (ScenarioSites::press_spot) until the hand pushes
          ///< with 1.2 × max force, hold, release
  Thin,   ///< push through the thinnest sheet reachable from outside (ScenarioSites::thin_site) with max force
  Edges,  ///< two-turn spiral round a slab corner (ScenarioSites::edges_spiral), crossing its slab edges and
          ///< passing the neighbouring corners at constant force
  Stiff,  ///< the highest stiffness [N/m] whose press-and-hold (at the press spot) stays stable at the rate
};

/// @brief Parses slide, press, thin, edges or stiff. @throws InvalidInput otherwise.
Scenario parse_scenario(const std::string& name);
/// Name of @p s.
const char* scenario_name(Scenario s) noexcept;

/// Settings of a scenario run. Paths are found on the exact input (model frame, any orientation);
/// with the ball (RenderMode::Sphere) the hand targets are lifted by its radius along the input's
/// normal, so the hand presses the ball's surface, not its centre, onto the input with the set force.
struct ScenarioOptions {
  Scenario scenario = Scenario::Slide;  ///< which scripted motion to run
  RenderMode mode = RenderMode::Proxy;  ///< proxy (god-object), the paper's penalty force or the sphere proxy
                                        ///< (a ball of `ball_radius`); not RigidTool
  double ball_radius = 0;     ///< RenderMode::Sphere: ball radius [model units]; 0: 0.01 × the model's source
                              ///< diagonal (and 0 for the other modes)
  double rate_hz = 1000;      ///< servo rate [Hz]
  ProxyParams proxy;          ///< force parameters (stiffness, damping, max force, friction)
  bool friction = false;      ///< use the model's μs/μd fields (off: frictionless, so force
                              ///< direction = surface normal and normal_error is meaningful)
  double workspace_m = 0.16;  ///< device workspace the model's diagonal maps to [m]
  double speed_m_s = 0.1;     ///< slide / edges speed of the hand target [m/s]
  double press_force_n = 1.0;     ///< slide / edges: hand force pressing into the surface [N]
  SimulatedDeviceOptions device;  ///< handle mass, hand spring/damper (rate and max force are set from above)
  bool keep_trace = false;        ///< fill ScenarioReport::trace
};

/// One traced tick (for plots).
struct ScenarioTraceRow {
  double t;         ///< time [s]
  Vec3 device;      ///< handle [m]
  Vec3 force;       ///< rendered force [N]
  double depth_mm;  ///< (proxy - HIP)·n [mm at the device], 0 when free
  int status;       ///< ProxyStatus
  int slab;         ///< proxy / contact slab, -1 free
  Vec3 proxy;       ///< proxy (SCP in penalty mode) [m, device frame]
  Vec3 normal;      ///< contact normal (model frame = device axes)
};

/// Scores of one run. Angles in degrees, forces in N, lengths in mm at the device.
struct ScenarioReport {
  /// @{ Scenario and render mode names (as `hdm feel` takes them).
  std::string scenario, mode;
  /// @}
  double rate_hz = 0;      ///< servo rate simulated [Hz]
  double ball_radius = 0;  ///< the ball's radius [model units] (RenderMode::Sphere); 0 for a point
  /// @{ Ticks run, ticks in contact, ticks with a non-finite device reading.
  int64_t ticks = 0, contact_ticks = 0, bad_input_ticks = 0;
  /// @}
  int pop_throughs = 0;  ///< force reversed, or vanished with the HIP inside / passing through the input
  double max_force_step_pct =
      0;  ///< largest tick-to-tick |ΔF| as % of max force over ticks where the handle moved < 0.1 mm
  /// The same step for a reference renderer of the exact input on the same handle motion: the
  /// spring k·|HIP - c|·n(c) to the HIP's closest input point c along the input's interpolated
  /// normal there (Embree closest point; the same ticks as max_force_step_pct, while the rendered
  /// force exceeds 0.05 N). What the input's own shape asks for: on a convex part of radius R pressed to depth d,
  /// any renderer's force turns by about v·dt/(R - d) per tick.
  double reference_force_step_pct = 0;
  /// The same step for the exact input's facets: the spring k·(c - HIP) to the HIP's closest input
  /// point c (not scored while the HIP is above c's face), so the force follows the face normal inside a
  /// face and turns about edges and vertices. What a god-object on the faceted input, or on any
  /// rendered mesh as rough, gives without force shading: at an edge of dihedral angle θ it steps
  /// by about |F|·θ at any servo rate (the closest point jumps across the edge's bisector).
  double reference_facet_force_step_pct = 0;
  double normal_error_p95_deg =
      0;  ///< force direction vs the exact input face normal at the closest point to the proxy (SCP in penalty mode)
  double normal_error_smooth_p95_deg = 0;  ///< same against the input's interpolated (area-weighted vertex) normal
  /// The input's own facet noise at the same points: its face normal against its interpolated
  /// vertex normal (p95) [deg]. A force that follows any continuous normal field cannot get far
  /// below this against the face normal.
  double normal_floor_p95_deg = 0;
  double energy_ratio = 0;  ///< work the rendered force returned to the handle / work it absorbed
  double stable_stiffness_n_per_m =
      0;  ///< stiff: highest stiffness whose press-and-hold settles (hand coupled); others: the stiffness used
  double passive_stiffness_n_per_m = 0;  ///< stiff: highest stiffness at which the rendered contact is also passive
                                         ///< (returned/absorbed work <= 1; theory: K < 2b/T, Colgate & Brown 1994)
  /// @{ Largest force and mean force over the contact ticks [N].
  double max_force_n = 0, mean_contact_force_n = 0;
  /// @}
  double force_cv = 0;                 ///< std/mean of |F| over the steady part (slide, edges)
  double max_penetration_mm = 0;       ///< largest (proxy - HIP)·n [mm]
  double proxy_surface_error_max = 0;  ///< max |proxy - evaluate_surface(proxy coords)| / diagonal (proxy mode)
  int64_t slab_crossings = 0;          ///< ticks on which the contact slab changed
  /// @{ render_step compute time: median, p99, max [ns].
  double tick_ns_median = 0, tick_ns_p99 = 0, tick_ns_max = 0;
  /// @}
  std::string note;                     ///< scenario details (e.g. where the ear is)
  std::vector<ScenarioTraceRow> trace;  ///< per tick, when keep_trace
};

/// @brief Runs one scenario on @p model, scored against @p reference (the input mesh the model was
/// baked from).
/// With the ball, the HIP is the ball's centre on the device and its proxy the god-object ball's
/// centre; the exact input's references are the same ball on the input: a spring of depth
/// r − |HIP − c| (r + |HIP − c| with the centre inside) along the input's interpolated normal at
/// the centre's closest input point c (smooth), and along HIP − c (facets: a ball on the faceted
/// input, whose offset surface has no edges), and the normals are judged at c of the proxy's centre.
/// @throws InvalidInput when the scenario's geometry cannot be found on the model (e.g. no ray hits),
///         for RenderMode::RigidTool (a rigid tool's scores are its own: hdm::run_tool_scenario), naming
///         the mode, or for a ball_radius that is negative, not finite, or not 0 with a point renderer.
/// @note Runs in simulated time, ticks back to back on the calling thread; allocates only before the
///       tick loop (and in the Stiff search, between runs). Each tick is hdm::render_step (hdm::sphere_proxy_step with
///       the ball), timed.
ScenarioReport run_scenario(const SlabModel& model, const SlabLocator& locator, const ExactMeshQuery& reference,
                            const ScenarioOptions& options);

/// @brief Plays a recorded trajectory (open loop) through the renderer and scores it like a
/// scenario: pop-throughs, force steps, normal error against @p reference, energy.
/// @param model      slab model baked from @p reference (derived data built).
/// @param locator    search structure of @p model.
/// @param reference  exact queries on the input mesh.
/// @param device   the recording, positions in the device frame of hdm::fit_workspace(bounds of
///                 @p reference, options.workspace_m) (what `hdm feel --trace` writes; a CSV of
///                 `hdm sculpt --forces` uses the slab model's box, a few per cent larger).
/// @param options  mode, proxy parameters, friction and workspace; the rate is the recording's.
/// @return the report, scenario "replay"; ticks = rows played.
/// @throws InvalidInput when the recording has fewer than two rows or no duration, for
///         RenderMode::RigidTool, naming the mode, or for a ball_radius that is negative, not finite, or not 0
///         with a point renderer.
/// @note Allocates only before the tick loop; each tick is hdm::render_step (hdm::sphere_proxy_step with the ball),
/// timed.
ScenarioReport run_replay(const SlabModel& model, const SlabLocator& locator, const ExactMeshQuery& reference,
                          ReplayDevice& device, const ScenarioOptions& options);

}  // namespace hdm
