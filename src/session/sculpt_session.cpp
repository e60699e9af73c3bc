// SPDX-License-Identifier: MIT
#include <hdm/core/error.h>
#include <hdm/session/sculpt_session.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>
#include <thread>
#include <vector>

namespace hdm {

namespace {

// Single-producer single-consumer ring of commands (control thread → servo thread): wait-free.
class CommandQueue {
 public:
  explicit CommandQueue(int capacity) : ring_(static_cast<size_t>(std::max(2, capacity))) {}
  bool push(const SessionCommand& c) noexcept {
    const size_t t = tail_.load(std::memory_order_relaxed);
    if (t - head_.load(std::memory_order_acquire) == ring_.size()) return false;
    ring_[t % ring_.size()] = c;
    tail_.store(t + 1, std::memory_order_release);
    return true;
  }
  bool pop(SessionCommand& c) noexcept {
    const size_t h = head_.load(std::memory_order_relaxed);
    if (h == tail_.load(std::memory_order_acquire)) return false;
    c = ring_[h % ring_.size()];
    head_.store(h + 1, std::memory_order_release);
    return true;
  }

 private:
  std::vector<SessionCommand> ring_;
  std::atomic<size_t> head_{0}, tail_{0};
};

// The editor's write gate: the snapshots preserve a slab's committed state before its first write.
bool allow_write(void* snapshots, int32_t slab) noexcept {
  return static_cast<SlabSnapshots*>(snapshots)->before_write(slab);
}

}  // namespace

struct SculptSession::Impl {
  Impl(SlabModel m, const Workspace& w, const SessionOptions& o)
      : options(o), model(std::move(m)), locator(model), ws(w), editor(model, o.editor), commands(o.command_capacity) {
    if (o.publish) {
      snapshots = std::make_unique<SlabSnapshots>(model, o.snapshots);
      editor.scratch().gate = WriteGate{&allow_write, snapshots.get()};
    }
    brush.radius = 0.01 * std::max(model.source_diagonal, 1e-12);
    if (o.mode == RenderMode::RigidTool) {
      if (options.tool.points.empty()) options.tool = burr_shell(brush.radius, o.tool_points);
      tool_state = std::make_unique<RigidToolState>();
      const double head = o.head_radius > 0 ? o.head_radius : brush.radius;
      for (const Vec3& p : options.tool.points) in_head.push_back(p.norm() <= head * (1 + 1e-9));
    }
  }
  SessionOptions options;
  SlabModel model;
  SlabLocator locator;
  Workspace ws;
  StrokeEditor editor;
  std::unique_ptr<SlabSnapshots> snapshots;
  CommandQueue commands;
  ProxyState proxy;
  SphereProxyState ball;                       // RenderMode::Sphere
  std::unique_ptr<RigidToolState> tool_state;  // RenderMode::RigidTool
  ToolWrench wrench;                           // RenderMode::RigidTool: the last tick's
  std::vector<uint8_t> in_head;                // RenderMode::RigidTool: per shell point, 1 on the burr's head
  double head_force_n = 0;                     // the head's contact normal forces [N], the last tick's
  ToolPartContacts head_part, shaft_part;      // the head's and the shaft's contacts, the last tick's
  Contact head_contact;                        // the head's contact on the surface, the last tick's
  QueryCache head_cache;                       // coherence of the head contact's query
  Brush brush;
  bool tool_on = false;
  double last_publish_s = -1e300;
  SessionStats stats;
  std::vector<EditLogEntry>* edit_log = nullptr;
  std::vector<size_t>* epoch_log = nullptr;

  // The renderer's tick: the point proxy (or penalty), or the ball of the brush's radius.
  ProxyOutput render(const DeviceState& d) noexcept {
    if (options.mode == RenderMode::RigidTool) return render_tool(d);
    if (options.mode != RenderMode::Sphere)
      return render_step(options.mode, model, locator, ws, d.position, d.velocity, options.proxy, proxy);
    SphereProxyParams p;
    p.proxy = options.proxy;
    p.radius = options.ball_radius > 0 ? options.ball_radius : brush.radius;
    p.samples = options.ball_samples;
    return sphere_proxy_step(model, locator, ws, d.position, d.velocity, p, ball);
  }

  // The rigid tool's tick, its force as the proxy's output (no single contact point: slab -1).
  ProxyOutput render_tool(const DeviceState& d) noexcept {
    wrench = rigid_tool_step(model, locator, ws, options.tool, ToolPose{d.position, d.orientation},
                             ToolTwist{d.velocity, d.angular_velocity}, options.rigid, *tool_state);
    head_contact_of_tool();
    ProxyOutput out;
    out.force = wrench.force;
    out.normal_force = wrench.force.norm();
    out.status = wrench.status == ForceStatus::Free       ? ProxyStatus::Free
                 : wrench.status == ForceStatus::Clamped  ? ProxyStatus::Clamped
                 : wrench.status == ForceStatus::BadInput ? ProxyStatus::BadInput
                                                          : ProxyStatus::Sliding;
    return out;
  }

  // The head's contacts after the solve: a row's multiplier λ is its contact force over the
  // workspace's scale (the coupling's force is scale·Σλ·n, rigid_tool.h), so F_n = scale·Σλ over
  // the head's rows. The contact is their force-weighted mean point, projected on the surface. The
  // shaft's rows give its part of the wrench the same way (for the caller's records).
  void head_contact_of_tool() noexcept {
    const RigidToolState& st = *tool_state;
    const Eigen::Matrix3d R = st.orientation.toRotationMatrix();
    double lambda[2] = {0, 0};  // head, shaft
    ToolPartContacts part[2];
    for (int k = 0; k < st.row_count && st.contact; ++k) {
      const ToolConstraint& row = st.rows[k];
      if (!(row.lambda > 0)) continue;
      const int j = in_head[row.point] ? 0 : 1;
      lambda[j] += row.lambda;
      ++part[j].contacts;
      part[j].force += (ws.scale * row.lambda) * row.n;
      part[j].point += row.lambda * (st.position + R * options.tool.points[row.point]);
    }
    for (int j = 0; j < 2; ++j) part[j].point = lambda[j] > 0 ? Vec3(part[j].point / lambda[j]) : st.position;
    head_part = part[0], shaft_part = part[1];
    head_force_n = ws.scale * lambda[0];
    head_contact =
        head_force_n > 0 ? query(model, locator, head_part.point, head_cache, options.rigid.solver) : Contact{};
  }

  // The stroke's sample of this tick: the point renderers' contact, or the rigid tool's head
  // contact while the drill is the brush (other brushes get none from the rigid tool).
  void feed_stroke(const SessionTick& r, const ServoTick& t, bool contact) noexcept {
    const bool tool = options.mode == RenderMode::RigidTool;
    if (!r.tool_on || t.tick % options.edit_every != 0) return;
    if (tool ? !(brush.tool == BrushTool::Drill && head_contact.in_shell()) : !contact) return;
    ToolSample ts;
    ts.contact = tool ? head_contact : r.out.contact;
    ts.hip = tool ? head_contact.surface_point : ws.to_model(r.device.position);
    ts.normal_force_n = tool ? head_force_n : r.out.normal_force;
    ts.units_per_metre = ws.scale;
    ts.time_s = t.time_s;
    ts.ball_centre = options.mode == RenderMode::Sphere;
    editor.add_sample(model, ts);
  }

  // Commits the slabs written since the last publication as one epoch, between sweeps (no half
  // edit, normals refreshed): every publish_interval_s, or sooner once the batch holds half the
  // spare versions, and only once readers have let go of the versions the commit before replaced
  // (a reader pinned at an old epoch then holds one batch, and the rest of the pool serves new
  // slabs). A sweep that runs out of versions while its own batch holds half of them is committed
  // in parts: only readers moving past a commit return versions.
  int32_t publish(double now_s) noexcept {
    if (!snapshots || snapshots->pending() == 0) return 0;
    const bool full = 2 * snapshots->pending() >= snapshots->version_count();
    const bool due = full || now_s - last_publish_s >= options.publish_interval_s;
    if (!due) return 0;
    const bool in_parts = full && snapshots->starved();
    if (!editor.between_sweeps() && !in_parts) {
      editor.flush();  // have the editor finish its normals first
      return 0;
    }
    if (!in_parts && !snapshots->readers_caught_up()) {
      ++stats.publish_deferred;
      return 0;
    }
    const int32_t slabs = snapshots->pending();
    snapshots->publish_commit();
    clear_dirty(editor.scratch());  // the next write of any slab asks the snapshots again
    if (epoch_log && edit_log && epoch_log->size() < epoch_log->capacity()) epoch_log->push_back(edit_log->size());
    ++stats.publications;
    stats.slabs_published += slabs;
    last_publish_s = now_s;
    return slabs;
  }
};

SculptSession::SculptSession(SlabModel model, const Workspace& ws, const SessionOptions& options) {
  if (model.slab_samples.size() != model.samples.slot_count() || model.slab_count() == 0)
    throw InvalidInput("sculpt session: the model's derived data are missing (call rebuild_derived first)");
  if (!(options.edit_budget_s > 0) || !(options.publish_interval_s >= 0) || options.edit_every < 1)
    throw InvalidInput("sculpt session: edit_budget_s must be > 0, publish_interval_s >= 0 and edit_every >= 1");
  if (!(ws.scale > 0) || !ws.origin.allFinite()) throw InvalidInput("sculpt session: invalid workspace");
  if (!(options.ball_radius >= 0) || !std::isfinite(options.ball_radius) || options.ball_samples < 6 ||
      options.ball_samples > kMaxBallSamples)
    throw InvalidInput("sculpt session: ball_radius must be finite and >= 0 and ball_samples in [6, " +
                       std::to_string(kMaxBallSamples) + "]");
  const ToolShell& t = options.tool;
  if (options.mode == RenderMode::RigidTool &&
      (t.points.size() > size_t(kMaxToolPoints) || t.normals.size() != t.points.size() ||
       (t.points.empty() && (options.tool_points < 16 || options.tool_points > kMaxToolPoints))))
    throw InvalidInput("sculpt session: the rigid tool needs a shell of 1 to " + std::to_string(kMaxToolPoints) +
                       " points with one normal each, or tool_points in [16, " + std::to_string(kMaxToolPoints) +
                       "] for the default burr");
  if (!(options.head_radius >= 0) || !std::isfinite(options.head_radius))
    throw InvalidInput("sculpt session: head_radius must be finite and >= 0 (0: the default burr's head)");
  impl_ = std::make_unique<Impl>(std::move(model), ws, options);
}

SculptSession::~SculptSession() = default;

SessionTick SculptSession::tick(HapticDevice& device, const ServoTick& t) noexcept {
  Impl& s = *impl_;
  const int64_t start_ns = StrokeEditor::now_ns();
  SessionTick r;
  SessionCommand c;
  while (s.commands.pop(c)) {
    if (c.kind == SessionCommand::SetBrush)
      s.brush = c.brush;
    else if (c.kind == SessionCommand::Undo)
      s.editor.undo();
    else if (c.kind == SessionCommand::Redo)
      s.editor.redo();
    else
      s.options.proxy = c.proxy;
  }
  if (!device.begin_frame(r.device)) {
    r.ended = true;
    device.end_frame(Vec3::Zero());
    return r;
  }
  r.out = s.render(r.device);
  r.force = r.out.force * t.force_gain;
  const bool tool = s.options.mode == RenderMode::RigidTool;
  if (tool) {
    r.ball_centre = s.tool_state->position;
    r.tool_orientation = s.tool_state->orientation;
    r.tool_contacts = s.wrench.contacts;
    r.head_force_n = s.head_force_n;
    r.head = s.head_part;
    r.shaft = s.shaft_part;
    r.torque = s.wrench.torque * t.force_gain;
    device.end_frame(r.force, r.torque);                          // the wrench first: edits never delay it
    r.head.force *= t.force_gain, r.shaft.force *= t.force_gain;  // as rendered, like the wrench
  } else {
    r.ball_centre = s.ball.center;
    device.end_frame(r.force);  // the force first: edits never delay it
  }
  ++s.stats.ticks;
  const bool contact =
      tool ? s.wrench.contacts > 0
           : r.out.contact.in_shell() && r.out.status != ProxyStatus::Free && r.out.status != ProxyStatus::BadInput;
  s.stats.contact_ticks += contact;

  // The tool button makes strokes.
  r.tool_on = (r.device.buttons & s.options.tool_button) != 0;
  if (r.tool_on && !s.tool_on) s.editor.begin_stroke(s.brush);
  if (!r.tool_on && s.tool_on) s.editor.end_stroke();
  s.tool_on = r.tool_on;
  s.feed_stroke(r, t, contact);

  // Edits and publication until the budget, counted from the tick's start: a slow proxy step
  // leaves less time for edits, so the whole tick stays within about the budget; but a fifth of the
  // budget is always left for them, so that edits progress whatever the proxy costs.
  const int64_t budget_ns = static_cast<int64_t>(s.options.edit_budget_s * 1e9);
  const int64_t deadline = std::max(start_ns + budget_ns, StrokeEditor::now_ns() + budget_ns / 5);
  const EditWork w = s.editor.work(s.model, deadline);
  r.sweeps = w.sweeps;
  r.changed = w.changed;
  s.stats.sweeps += w.sweeps;
  s.stats.changed += w.changed;
  s.stats.edits_refused += w.refused;
  r.published = s.publish(t.time_s);
  r.edit_pending = w.deadline;
  s.stats.carried_ticks += r.edit_pending;
  s.stats.max_edit_ns = std::max(s.stats.max_edit_ns, double(StrokeEditor::now_ns() - start_ns));
  return r;
}

void SculptSession::set_brush(const Brush& brush) noexcept { impl_->brush = brush; }
void SculptSession::undo() noexcept { impl_->editor.undo(); }
void SculptSession::redo() noexcept { impl_->editor.redo(); }
void SculptSession::set_proxy_params(const ProxyParams& params) noexcept { impl_->options.proxy = params; }
const ProxyParams& SculptSession::proxy_params() const noexcept { return impl_->options.proxy; }
RenderMode SculptSession::render_mode() const noexcept { return impl_->options.mode; }
const ToolShell& SculptSession::tool_shell() const noexcept { return impl_->options.tool; }
bool SculptSession::post(const SessionCommand& command) noexcept { return impl_->commands.push(command); }
const SlabSnapshots* SculptSession::snapshots() const noexcept { return impl_->snapshots.get(); }
const Workspace& SculptSession::workspace() const noexcept { return impl_->ws; }
SlabModel& SculptSession::model() noexcept { return impl_->model; }
StrokeEditor& SculptSession::editor() noexcept { return impl_->editor; }
const SessionStats& SculptSession::stats() const noexcept { return impl_->stats; }

void SculptSession::record_log(std::vector<EditLogEntry>* edits, std::vector<size_t>* epochs) noexcept {
  impl_->editor.record_log(edits);
  impl_->edit_log = edits;
  impl_->epoch_log = epochs;
}

void SculptSession::finish() noexcept {
  Impl& s = *impl_;
  if (s.tool_on) s.editor.end_stroke();
  s.tool_on = false;
  for (;;) {
    const EditWork w = s.editor.work(s.model, INT64_MAX);
    s.stats.sweeps += w.sweeps;
    s.stats.changed += w.changed;
    s.stats.edits_refused += w.refused;
    s.last_publish_s = -1e300;
    s.publish(0.0);
    if (s.editor.idle() && (!s.snapshots || s.snapshots->pending() == 0)) break;
    std::this_thread::yield();  // a reader copies a slab, or holds versions the edit or commit needs
  }
}

namespace {

struct Runner {
  SculptSession* session;
  HapticDevice* device;
  SessionHooks hooks;
  std::atomic<bool>* stop;
};

void run_tick(void* user, const ServoTick& t) noexcept {
  Runner& r = *static_cast<Runner*>(user);
  if (r.hooks.before) r.hooks.before(r.hooks.user, *r.session, t);
  const SessionTick out = r.session->tick(*r.device, t);
  if (r.hooks.after) r.hooks.after(r.hooks.user, t, out);
  if (out.ended) r.stop->store(true, std::memory_order_relaxed);
}

}  // namespace

ServoStats run_session(SculptSession& session, HapticDevice& device, const ServoOptions& options,
                       const SessionHooks& hooks, const char** realtime_note) {
  std::atomic<bool> own_stop{false};
  ServoOptions o = options;
  Runner r{&session, &device, hooks, options.stop ? options.stop : &own_stop};
  o.stop = r.stop;
  return run_servo_loop(o, run_tick, &r, realtime_note);
}

}  // namespace hdm
