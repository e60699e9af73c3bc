// SPDX-License-Identifier: MIT
#include <hdm/edit/stroke_editor.h>

#include <hdm/edit/brush_registry.h>
#include <hdm/query/detail/surface_eval.h>
#include "edit_job.h"

#include <algorithm>
#include <cmath>

namespace hdm {

namespace {

struct Event {
  enum Kind : uint8_t { Begin, Sample, End, Undo, Redo, Sweep } kind = Sample;
  Brush brush;                // Begin
  ToolSample sample;          // Sample
  Vec3 axis = Vec3::UnitZ();  // Sample: the tool's axis
  BrushSweep sweep;           // Sweep: a logged sweep to apply as is
  Vec3 point = Vec3::Zero();  // Sample: the tool's position, once computed
  bool has_point = false;
};

}  // namespace

struct StrokeEditor::Impl {
  Impl(SlabModel& m, const StrokeEditorOptions& o)
      : options(o),
        scratch(m),
        memory(m),
        history(o.undo_cap_bytes, o.undo_max_strokes),
        queue(static_cast<size_t>(std::max(16, o.queue_capacity))) {
    memory.history = &history;
  }
  StrokeEditorOptions options;
  EditScratch scratch;
  edit::detail::StrokeMemory memory;
  UndoHistory history;
  edit::detail::EditJob job;
  std::vector<Event> queue;
  size_t head = 0, count = 0;
  bool producer_open = false;  // begin_stroke called and end_stroke not yet
  bool producer_axis = true;   // the stroke being fed orients its tool along the axis
  bool axis_valid = false;     // the producer's low-passed contact normal
  // Strokes begun by the producer and by the processing: the stroke memory holds the producer's
  // stroke only while the two agree and that stroke is open.
  uint64_t producer_strokes = 0, processed_strokes = 0;
  Vec3 axis = Vec3::UnitZ();
  double axis_time = 0;
  // The stroke being processed.
  bool open = false;
  Brush brush;
  bool has_last = false;
  Vec3 last_point = Vec3::Zero();
  double last_time = 0;
  int64_t changed_total = 0;
  std::vector<EditLogEntry>* log = nullptr;
  void write_log(EditLogEntry::Kind kind, const BrushSweep* sweep = nullptr) noexcept {
    if (!log || log->size() >= log->capacity()) return;
    EditLogEntry e;
    e.kind = kind;
    if (sweep) e.sweep = *sweep;
    log->push_back(e);
  }
  bool flush_requested = false;
  double normals_time = 0;  // stroke time of the last normal refresh

  // The pending normals are refreshed on request, before a command (stroke end, undo, a new
  // stroke), when the stroke is over, or during a stroke once normals_interval_s has passed since
  // the last refresh and the samples may have moved by a twentieth of the grid spacing (smooth and
  // flatten move them by micrometres a tick: their normals wait up to 12 intervals).
  double motion = 0;  // upper bound of any sample's motion since the last refresh [model units]
  bool normals_due() const noexcept {
    if (scratch.changed_count == 0) return false;
    if (flush_requested || !open) return true;
    if (count > 0 && queue[head].kind != Event::Sample) return true;
    const double interval = options.normals_interval_s;
    // Stroke time (the servo's), never the wall clock: the normals the proxy stands on steer later
    // sweeps, so a refresh timed by the clock made two replays of one stroke differ.
    const double elapsed = last_time - normals_time;
    return elapsed >= 12 * interval || (elapsed >= interval && motion >= 0.05 * scratch.sample_spacing);
  }

  Event& at(size_t k) noexcept { return queue[(head + k) % queue.size()]; }
  bool push(const Event& e, bool replace_sample_when_full) noexcept {
    if (count == queue.size()) {
      // Full (the sweeps lag far behind): the newest position is replaced, so the next sweep
      // spans both; a stroke command replaces it too (the stroke ends one tick earlier).
      Event& last = at(count - 1);
      if (!replace_sample_when_full || last.kind != Event::Sample) return false;
      last = e;
      return true;
    }
    at(count++) = e;
    return true;
  }
  void pop() noexcept {
    head = (head + 1) % queue.size();
    --count;
  }

  // Where the tool is for this sample (the brush's placement): the sphere's centre behind the HIP
  // (carve), the sphere whose top stands `height` above the stroke's starting surface (add), or
  // the surface contact point.
  Vec3 tool_point(const SlabModel& m, Event& e) const noexcept {
    if (!e.has_point) e.point = compute_tool_point(m, e), e.has_point = true;
    return e.point;
  }
  Vec3 compute_tool_point(const SlabModel& m, const Event& e) const noexcept {
    const ToolSample& t = e.sample;
    const Contact& c = t.contact;
    const BrushInfo* info = find_brush(brush.tool);
    switch (info ? info->placement : ToolPlacement::Contact) {
      case ToolPlacement::BehindHip:
        return t.hip + e.axis * ((t.ball_centre ? 0.0 : brush.radius) + std::max(brush.resilience, 0.0));
      case ToolPlacement::StartSurface: {
        // The starting surface under the contact: the stroke's first-touch displacements,
        // interpolated over the grid cell evaluate_surface uses.
        const slab_query::detail::GridCell cell =
            slab_query::detail::grid_cell(m, c.slab, c.coords.bary[1], c.coords.bary[2]);
        auto base = [&](int32_t id) {
          return memory.sample_mark[id] == memory.id ? double(memory.sample_base[id].delta)
                                                     : double(m.displacement[id]);
        };
        const double delta = cell.wa * base(cell.a) + cell.wb * base(cell.b) + cell.wd * base(cell.d);
        const Vec3 point = c.surface_point + (delta - c.delta) * c.ray;  // same projection line
        return point + e.axis * (brush.height - brush.radius);
      }
      default:
        return c.surface_point;
    }
  }

  // The starting surface's normal at contact c: the normals of the three corners of c's grid cell
  // (each the area-weighted sum of its grid triangles, at the displacements the stroke found
  // there), interpolated with c's weights in the cell, so the axis turns continuously as the
  // contact crosses cells.
  Vec3 base_normal(const SlabModel& m, const Contact& c) const noexcept {
    const SampleLayout& L = m.samples;
    const slab_query::detail::GridCell cell =
        slab_query::detail::grid_cell(m, c.slab, c.coords.bary[1], c.coords.bary[2]);
    // The first-touch values in the stroke memory are this stroke's only once its Begin was
    // processed; before that they are an earlier stroke's (or none), and the model is the start.
    const bool own_memory = open && processed_strokes == producer_strokes;
    // Base positions of the few samples around the cell, each computed once.
    constexpr int kCache = 48;
    int32_t ids[kCache];
    Vec3 at[kCache];
    int cached = 0;
    auto base_point = [&](int32_t id) -> Vec3 {
      for (int k = 0; k < cached; ++k)
        if (ids[k] == id) return at[k];
      const double delta = own_memory && memory.sample_mark[id] == memory.id ? double(memory.sample_base[id].delta)
                                                                             : double(m.displacement[id]);
      const std::array<double, 3>& w = scratch.grid_weights[L.home(id).index];
      const Tri& t = m.slabs[L.home(id).slab];
      const Vec3 p0 = w[0] * m.inner[t[0]] + w[1] * m.inner[t[1]] + w[2] * m.inner[t[2]];
      const Vec3 p1 = w[0] * m.outer[t[0]] + w[1] * m.outer[t[1]] + w[2] * m.outer[t[2]];
      const Vec3 p = p0 + delta * (p1 - p0);
      if (cached < kCache) ids[cached] = id, at[cached++] = p;
      return p;
    };
    Vec3 sum = Vec3::Zero();
    const int32_t corner[3] = {cell.a, cell.b, cell.d};
    const double weight[3] = {cell.wa, cell.wb, cell.wd};
    for (int i = 0; i < 3; ++i) {
      Vec3 n = Vec3::Zero();
      L.for_each_incident_triangle(corner[i], [&](int32_t, const Tri& t) {
        const Vec3 a = base_point(t[0]);
        n += (base_point(t[1]) - a).cross(base_point(t[2]) - a);
      });
      const double len = n.norm();
      if (len > 0) sum += weight[i] * (n / len);
    }
    const double len = sum.norm();
    return len > 0 ? Vec3(sum / len) : c.normal;
  }

  double pressure(const ToolSample& t) const noexcept {
    const double full = brush.pressure_force_n > 0 ? brush.pressure_force_n : 1.0;
    return paint_pressure(t.normal_force_n, 0.1 * full, full);
  }

  // Starts the sweep from the last point to the furthest queued sample that keeps every sample in
  // between within the merge tolerance of the segment; pops the samples used.
  void start_sweep(const SlabModel& m) noexcept {
    const double tol = options.merge_tolerance * brush.radius;
    const Vec3 first = tool_point(m, at(0));
    const Vec3 from = has_last ? last_point : first;
    size_t use = 1;
    Vec3 to = first;
    constexpr size_t kMaxMerge = 16;  // the check below is quadratic in it
    for (size_t k = 1; k < count && k < kMaxMerge && at(k).kind == Event::Sample; ++k) {
      const Vec3 cand = tool_point(m, at(k));
      const Vec3 u = cand - from;
      const double uu = u.squaredNorm();
      bool ok = true;
      for (size_t j = 0; j < k && ok; ++j) {
        const Vec3 p = j == 0 ? first : tool_point(m, at(j));
        const double s = uu > 0 ? std::clamp((p - from).dot(u) / uu, 0.0, 1.0) : 0.0;
        ok = (p - from - s * u).norm() <= tol;
      }
      if (!ok) break;
      use = k + 1;
      to = cand;
    }
    const ToolSample& end = at(use - 1).sample;
    BrushSweep sw;
    sw.brush = brush;
    sw.from = from;
    sw.to = to;
    sw.plane_point = end.contact.surface_point;
    sw.plane_normal = at(use - 1).axis;
    sw.seed_slab = end.contact.slab;
    sw.seed_bary = end.contact.coords.bary;
    sw.pressure = pressure(end);
    sw.dt = has_last ? std::max(0.0, end.time_s - last_time) : 0.0;
    sw.normal_force_n = std::max(0.0, end.normal_force_n);
    sw.units_per_metre = end.units_per_metre;
    has_last = true;
    last_point = to;
    last_time = end.time_s;
    for (size_t k = 0; k < use; ++k) pop();
    write_log(EditLogEntry::Sweep, &sw);
    job.start_sweep(m, scratch, sw, &memory);
  }

  void close_stroke() noexcept {
    if (!open) return;
    history.end_stroke();
    open = false;
    write_log(EditLogEntry::End);
  }
};

StrokeEditor::StrokeEditor(SlabModel& model, const StrokeEditorOptions& options)
    : impl_(std::make_unique<Impl>(model, options)) {}
StrokeEditor::~StrokeEditor() = default;

void StrokeEditor::begin_stroke(const Brush& brush) noexcept {
  Event e;
  e.kind = Event::Begin;
  e.brush = brush;
  const bool pushed = impl_->push(e, true);
  impl_->producer_strokes += pushed;
  impl_->producer_open = pushed || impl_->producer_open;
  const BrushInfo* info = find_brush(brush.tool);
  impl_->producer_axis = info && info->along_axis;
  impl_->axis_valid = false;
}

void StrokeEditor::add_sample(const SlabModel& model, const ToolSample& sample) noexcept {
  if (!impl_->producer_open || !sample.contact.in_shell() || !sample.hip.allFinite() ||
      !sample.contact.surface_point.allFinite() || !sample.contact.normal.allFinite())
    return;
  Impl& s = *impl_;
  // Only the brushes placed or oriented along the axis (carve, add, flatten) need the starting surface's normal.
  const Vec3 n = s.producer_axis ? s.base_normal(model, sample.contact) : sample.contact.normal;
  if (!s.axis_valid) {
    s.axis = n;
    s.axis_valid = true;
  } else {
    const double dt = std::max(0.0, sample.time_s - s.axis_time);
    const double a = s.options.axis_time_s > 0 ? 1 - std::exp(-dt / s.options.axis_time_s) : 1.0;
    const Vec3 next = s.axis + a * (n - s.axis);
    if (next.squaredNorm() > 1e-24) s.axis = next.normalized();
  }
  s.axis_time = sample.time_s;
  Event e;
  e.kind = Event::Sample;
  e.sample = sample;
  e.axis = s.axis;
  s.push(e, true);
}

void StrokeEditor::end_stroke() noexcept {
  if (!impl_->producer_open) return;
  Event e;
  e.kind = Event::End;
  if (impl_->push(e, true)) impl_->producer_open = false;
}

bool StrokeEditor::undo() noexcept {
  Event e;
  e.kind = Event::Undo;
  return impl_->push(e, false);
}

bool StrokeEditor::redo() noexcept {
  Event e;
  e.kind = Event::Redo;
  return impl_->push(e, false);
}

EditWork StrokeEditor::work(SlabModel& m, int64_t deadline_ns) noexcept {
  Impl& s = *impl_;
  EditWork w;
  edit::detail::Deadline d(deadline_ns);
  for (;;) {
    if (s.job.active()) {
      if (!s.job.run(m, s.scratch, d)) {
        w.idle = false;
        w.deadline = true;
        w.refused = s.scratch.write_refused;
        return w;
      }
      ++w.sweeps;
      s.motion += std::sqrt(std::min(s.job.motion2(), 1e300));
      w.visited += s.job.result.visited;
      w.changed += s.job.result.changed;
      s.changed_total += s.job.result.changed;
      continue;
    }
    // Normals: in batches, and before anything but the next sweep of the stroke.
    if (s.normals_due()) {
      if (now_ns() >= deadline_ns) {
        w.idle = false;
        w.deadline = true;
        return w;
      }
      s.job.start_normals(s.scratch);
      s.normals_time = s.last_time;
      s.motion = 0;
      s.flush_requested = false;
      continue;
    }
    if (s.count == 0) break;
    if (now_ns() >= deadline_ns) {  // no new sweep past the deadline
      w.idle = false;
      w.deadline = true;
      return w;
    }
    Event& e = s.at(0);
    switch (e.kind) {
      case Event::Begin: {
        s.close_stroke();
        s.brush = e.brush;
        s.memory.next_stroke();
        ++s.processed_strokes;
        s.history.begin_stroke();
        s.open = true;
        s.has_last = false;
        BrushSweep b;
        b.brush = s.brush;
        s.write_log(EditLogEntry::Begin, &b);
        s.pop();
        break;
      }
      case Event::End:
        s.close_stroke();
        s.pop();
        break;
      case Event::Undo:
      case Event::Redo: {
        const bool redo = e.kind == Event::Redo;
        s.close_stroke();  // an undo while the button is held ends that stroke first
        s.pop();
        s.write_log(redo ? EditLogEntry::Redo : EditLogEntry::Undo);
        s.job.start_history(s.scratch, s.history, redo);
        break;
      }
      case Event::Sweep: {  // a logged sweep, applied as recorded
        const BrushSweep sw = e.sweep;
        s.pop();
        if (!s.open) break;
        s.has_last = true;
        s.last_point = sw.to;
        s.write_log(EditLogEntry::Sweep, &sw);
        s.job.start_sweep(m, s.scratch, sw, &s.memory);
        break;
      }
      case Event::Sample:
        if (!s.open) {
          s.pop();
          break;
        }
        s.start_sweep(m);
        break;
    }
  }
  w.idle = !s.job.active() && s.count == 0 && s.scratch.changed_count == 0;
  return w;
}

void StrokeEditor::record_log(std::vector<EditLogEntry>* log) noexcept { impl_->log = log; }

bool StrokeEditor::replay(const EditLogEntry& entry) noexcept {
  switch (entry.kind) {
    case EditLogEntry::Begin:
      begin_stroke(entry.sweep.brush);
      return true;
    case EditLogEntry::End:
      end_stroke();
      return true;
    case EditLogEntry::Undo:
      return undo();
    case EditLogEntry::Redo:
      return redo();
    default: {
      Event e;
      e.kind = Event::Sweep;
      e.sweep = entry.sweep;
      return impl_->push(e, false);
    }
  }
}
bool StrokeEditor::between_sweeps() const noexcept { return !impl_->job.active() && impl_->scratch.changed_count == 0; }
bool StrokeEditor::idle() const noexcept {
  return !impl_->job.active() && impl_->count == 0 && impl_->scratch.changed_count == 0;
}
void StrokeEditor::flush() noexcept { impl_->flush_requested = true; }
bool StrokeEditor::in_stroke() const noexcept { return impl_->open || impl_->producer_open; }
EditScratch& StrokeEditor::scratch() noexcept { return impl_->scratch; }
const UndoHistory& StrokeEditor::history() const noexcept { return impl_->history; }
int64_t StrokeEditor::total_changed() const noexcept { return impl_->changed_total; }
int64_t StrokeEditor::now_ns() noexcept { return edit::detail::Deadline::now_ns(); }

}  // namespace hdm
