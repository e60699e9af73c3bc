// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// The servo loop assembled: device → proxy / force → force envelope → device on the servo
/// thread, which also owns the model and edits it with strokes within a work budget per tick,
/// and publishes the changed slabs for renderer and saver threads (hdm::SlabSnapshots).
/// Used by `hdm sculpt` and meant for an interactive studio. Design, guarantees and measured
/// figures: docs/editing.md.

#include <hdm/edit/stroke_editor.h>
#include <hdm/haptics/device.h>
#include <hdm/haptics/proxy.h>
#include <hdm/haptics/rigid_tool.h>
#include <hdm/haptics/servo_loop.h>
#include <hdm/haptics/sphere_proxy.h>
#include <hdm/slab/slab_snapshots.h>

#include <atomic>
#include <cstdint>
#include <memory>

namespace hdm {

/// Settings of a SculptSession.
struct SessionOptions {
  /// Force model: a point (Proxy, Penalty), the tool's ball (Sphere) or a rigid tool with torque
  /// (RigidTool: renders force and torque; with the drill brush its head's contacts drill, other
  /// brushes get no samples from it).
  RenderMode mode = RenderMode::Proxy;
  ProxyParams proxy;  ///< proxy and force parameters (SI at the device)
  /// RenderMode::Sphere: the felt ball's radius [model units]; 0 (default): the brush's radius, so
  /// the ball the user feels is the ball that carves, adds, smooths or paints.
  double ball_radius = 0;
  int ball_samples = 32;  ///< RenderMode::Sphere: points on the ball queried per tick (SphereProxyParams::samples)
  /// RenderMode::RigidTool: the tool's point shell [model units, tool frame, tip point at the
  /// origin], #P in [1, kMaxToolPoints]; empty (default): burr_shell() of head radius 1 % of the
  /// model's source diagonal with `tool_points` points.
  ToolShell tool;
  int tool_points =
      1000;  ///< RenderMode::RigidTool without a `tool`: points of the default burr, in [16, kMaxToolPoints]
  /// RenderMode::RigidTool: the shell points within this distance of the tip are the burr's head,
  /// whose contacts drill [model units]; 0 (default): the default burr's head radius (1 % of the
  /// model's source diagonal), its whole spherical head.
  double head_radius = 0;
  /// RenderMode::RigidTool: couplings, damping, force and torque clamps, contact band (SI at the
  /// device, rigid_tool.h); `proxy` is not used by the rigid tool.
  RigidToolParams rigid;
  /// Time a tick may take with its edit and publication work [s], counted from the tick's start:
  /// after the force is sent, edits run until then (the rest carries over to the next ticks), and for
  /// at least a fifth of it, so a tick lasts about this, or the proxy step plus a fifth of it.
  double edit_budget_s = 25e-6;
  double publish_interval_s = 0.01;  ///< publish changed slabs at most this often [s] (100 Hz)
  bool publish = true;               ///< keep SlabSnapshots for other threads (memory: see SlabSnapshots)
  SnapshotOptions snapshots;         ///< reader slots, spare versions
  StrokeEditorOptions editor;        ///< undo cap, queue
  uint32_t tool_button = 1;          ///< device button mask that holds the tool on (a stroke while held)
  /// Feed a tool position every this many ticks (1: every tick, the default; the paper's 10 Hz
  /// at 1 kHz is 100). The sweep joins consecutive positions either way.
  int64_t edit_every = 1;
  int command_capacity = 256;  ///< commands (post()) waiting for the servo thread
};

/// A command for the servo thread from another thread (post()).
struct SessionCommand {
  /// What the servo thread does: switch to `brush`, undo or redo the last stroke, or render with
  /// `proxy` (stiffness, friction, ...: the studio's live controls).
  /// @{
  enum Kind : uint8_t { SetBrush, Undo, Redo, SetProxy } kind = SetBrush;
  /// @}
  Brush brush;        ///< SetBrush: used from the next stroke on
  ProxyParams proxy;  ///< SetProxy: the force and proxy parameters from this tick on (the proxy's state is kept)
};

/// RenderMode::RigidTool: the contacts of one part of the tool (the head or the shaft) in the
/// tick's solve. The parts split the shell at SessionOptions::head_radius from the tip: the head is
/// within it, the shaft (with its end) beyond.
struct ToolPartContacts {
  int32_t contacts = 0;  ///< the part's shell points pushing the god-object (multiplier > 0)
  /// The sum of their contact forces on the tool [N, device axes = model axes]: scale·λ·n per point,
  /// the solve's forces before damping and the force clamp, times the servo loop's force gain as the
  /// rendered force and torque are (0 while the watchdog fades them out). At the solve's equilibrium
  /// their moments about the tip add up to the torque rendered before damping and the torque clamp
  /// (rigid_tool.h), so the shaft's lever arm sets the torque's sense.
  Vec3 force = Vec3::Zero();
  /// Their force-weighted mean point [model units, model frame] (on the tool's surface where they
  /// press); the god-object's tip without a contact.
  Vec3 point = Vec3::Zero();
};

/// What one tick did (for the caller's records).
struct SessionTick {
  DeviceState device;         ///< the device reading of the tick (device frame)
  Vec3 force = Vec3::Zero();  ///< force sent [N], after the envelope's gain
  ProxyOutput out;            ///< the renderer's output (contact, forces, friction)
  /// RenderMode::Sphere: the ball's centre (god-object); RenderMode::RigidTool: the god-object's tip
  /// point [model units, model frame].
  Vec3 ball_centre = Vec3::Zero();
  Vec3 torque =
      Vec3::Zero();  ///< RenderMode::RigidTool: torque sent [N·m, device frame, about the tip], after the gain
  /// RenderMode::RigidTool: the god-object's orientation (tool frame → model frame, unit).
  Eigen::Quaterniond tool_orientation = Eigen::Quaterniond::Identity();
  int32_t tool_contacts = 0;  ///< RenderMode::RigidTool: shell points pushing the god-object
  /// RenderMode::RigidTool: the sum of the normal forces of the head's contacts [N] (shell points
  /// within SessionOptions::head_radius of the tip), the drill's F_n: the contact forces of the
  /// solve, before damping and the force clamp; 0 without a head contact.
  double head_force_n = 0;
  ToolPartContacts head;      ///< RenderMode::RigidTool: the head's contacts (shell points within head_radius)
  ToolPartContacts shaft;     ///< RenderMode::RigidTool: the shaft's contacts (the other shell points)
  bool ended = false;         ///< the device had nothing more (begin_frame returned false)
  bool tool_on = false;       ///< the tool button is held
  int32_t sweeps = 0;         ///< sweeps finished in this tick
  int32_t changed = 0;        ///< samples / texels changed in this tick
  int32_t published = 0;      ///< slabs committed in this tick
  bool edit_pending = false;  ///< the budget ran out with work left: it carries over to the next tick
};

/// Counters of a session.
struct SessionStats {
  /// @{ Ticks run, ticks in contact, sweeps finished, samples / texels changed.
  int64_t ticks = 0, contact_ticks = 0, sweeps = 0, changed = 0;
  /// @}
  int64_t publications = 0;     ///< epochs committed
  int64_t slabs_published = 0;  ///< slabs committed (written since the commit before)
  /// ticks a due publication waited for readers to let go of the versions the commit before replaced
  int64_t publish_deferred = 0;
  /// ticks whose edit stopped before a slab the snapshots could not grant yet (a reader copying
  /// it, or every spare version held by readers of older epochs); it resumed on a later tick
  int64_t edits_refused = 0;
  int64_t carried_ticks = 0;     ///< ticks whose budget ran out with work left for the next
  double max_edit_ns = 0;        ///< longest edit + publish work in one tick [ns]
};

/// One haptic sculpting session: the live model, its locator, the proxy, a StrokeEditor and
/// (optionally) SlabSnapshots.
///
/// Threading: tick(), set_brush(), undo() and redo() are for the servo thread only (or any one
/// thread while no servo runs); post() for one control thread at a time (lock-free SPSC queue);
/// snapshots() for any reader thread. model(), editor(), stats() and finish() only while no
/// servo loop runs. The tick never allocates, locks or does I/O.
class SculptSession {
 public:
  /// @brief Takes @p model (derived data built), builds its locator, editor and snapshots.
  /// @param model    slab model with derived data (moved in).
  /// @param ws       device ↔ model mapping.
  /// @param options  edit budget, undo memory, snapshots, command queue.
  /// @throws InvalidInput on a model without derived data or bad options (RenderMode::RigidTool: a
  ///         tool shell with #P outside [1, kMaxToolPoints] or normals not matching its points,
  ///         tool_points outside [16, kMaxToolPoints] when no shell is given, or a head_radius
  ///         that is negative or not finite).
  /// @note Allocates everything the ticks need: editor buffers (~60 B per sample, ~30 per texel,
  ///       plus the undo cap), snapshot versions (see SlabSnapshots), the locator and, for
  ///       RenderMode::RigidTool, the tool's shell and state (RigidToolState, about 200 KB).
  SculptSession(SlabModel model, const Workspace& ws, const SessionOptions& options = {});
  ~SculptSession();
  SculptSession(const SculptSession&) = delete;
  SculptSession& operator=(const SculptSession&) = delete;

  /// @brief One servo tick: commands, device reading, force, device command (first, so edits
  /// never delay the force), stroke bookkeeping from the tool button, then edits and publication
  /// within SessionOptions::edit_budget_s. RenderMode::RigidTool reads the handle's pose
  /// (position, orientation, velocities) and commands force and torque
  /// (HapticDevice::end_frame(force, torque)); the other modes command the force alone. With
  /// RenderMode::RigidTool and the drill brush, a held tool button feeds the stroke the head's
  /// contact (the force-weighted mean of its contact points, projected on the surface) with
  /// SessionTick::head_force_n as the drill's normal force, so removal follows the rigid tool's
  /// contacts (docs/haptics.md, "The rigid tool drills").
  /// @param device  the haptic device, read and commanded once.
  /// @param tick    from the servo loop (its force_gain scales the force).
  /// @note noexcept; no allocation, no lock, no I/O; servo thread only.
  SessionTick tick(HapticDevice& device, const ServoTick& tick) noexcept;

  /// @brief The brush used from the next stroke on (servo thread). noexcept.
  void set_brush(const Brush& brush) noexcept;
  /// @brief Queues an undo of the last stroke (servo thread). noexcept.
  void undo() noexcept;
  /// @brief Queues a redo of the last undone stroke (servo thread). noexcept.
  void redo() noexcept;
  /// @brief Renders with @p params from the next tick on (servo thread; SessionCommand::SetProxy from
  /// another thread). The proxy's state is kept, so a contact goes on at the new stiffness. noexcept.
  void set_proxy_params(const ProxyParams& params) noexcept;
  /// The force and proxy parameters in use. Servo thread, or while no servo loop runs.
  const ProxyParams& proxy_params() const noexcept;
  /// The force model (SessionOptions::mode), fixed for the session. Any thread.
  RenderMode render_mode() const noexcept;
  /// The rigid tool's point shell [model units, tool frame, tip at the origin]: SessionOptions::tool
  /// or the default burr built for the model; empty unless RenderMode::RigidTool. Fixed for the
  /// session, any thread (a renderer draws the tool from it).
  const ToolShell& tool_shell() const noexcept;
  /// @brief Sends a command to the servo thread from one other thread; false when the queue is
  /// full. noexcept, wait-free.
  bool post(const SessionCommand& command) noexcept;

  /// Snapshots for reader threads (null when SessionOptions::publish is false).
  const SlabSnapshots* snapshots() const noexcept;
  /// The device ↔ model mapping.
  const Workspace& workspace() const noexcept;
  /// The live model. Only while no servo loop runs.
  SlabModel& model() noexcept;
  /// The editor (undo history, dirty slabs). Only while no servo loop runs.
  StrokeEditor& editor() noexcept;
  /// Counters. Only while no servo loop runs.
  const SessionStats& stats() const noexcept;
  /// @brief Records what the editor applies (StrokeEditor::record_log) into @p edits and, at each
  /// publication, the number of entries of @p edits it contains into @p epochs (entry k for epoch
  /// k + 1), both up to their capacity (reserve them first). Replaying the first epochs[k] entries
  /// on the model as it was reproduces what readers see at epoch k + 1 (tests). Before the loop.
  void record_log(std::vector<EditLogEntry>* edits, std::vector<size_t>* epochs) noexcept;
  /// @brief Ends an open stroke, finishes every queued edit and publishes: call after the loop.
  /// @note Not real-time (no budget): yields while a reader holds a slab or versions the edits or
  ///       the commit need, so it returns once readers let go of their snapshots.
  void finish() noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Calls around each tick of run_session(), on the servo thread (same real-time rules).
struct SessionHooks {
  /// Before the tick (e.g. a script switching brushes or pressing undo at a given time).
  void (*before)(void* user, SculptSession& session, const ServoTick& tick) noexcept = nullptr;
  /// After the tick, with what it did (e.g. recording into preallocated storage).
  void (*after)(void* user, const ServoTick& tick, const SessionTick& result) noexcept = nullptr;
  void* user = nullptr;  ///< passed to both hooks unchanged
};

/// @brief Runs the servo loop (run_servo_loop: rate, envelope, watchdog, SCHED_FIFO when
/// permitted) with @p session's tick on @p device until options.ticks, options.stop, or the
/// device's end (a replay), then waits for it.
/// @param session  the session whose tick runs.
/// @param device   the haptic device (real, simulated or a replay).
/// @param options  rate, ticks, stop flag, watchdog and envelope (as run_servo_loop).
/// @param hooks    optional calls before and after each tick.
/// @param[out] realtime_note  as run_servo_loop.
/// @note Allocates only before the loop starts.
ServoStats run_session(SculptSession& session, HapticDevice& device, const ServoOptions& options,
                       const SessionHooks& hooks = {}, const char** realtime_note = nullptr);

}  // namespace hdm
