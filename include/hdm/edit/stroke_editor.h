// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Strokes at haptic rate: the thread that owns a model (the servo thread) feeds it one tool
/// position per tick while a button is held; the editor sweeps the brush between consecutive
/// positions and does at most a given amount of work per tick, carrying the rest to later ticks.
/// Undo / redo per stroke. Design and measured figures: docs/editing.md.

#include <hdm/edit/edit_tools.h>
#include <hdm/edit/undo_history.h>

#include <cstdint>
#include <memory>

namespace hdm {

/// Settings of a StrokeEditor.
struct StrokeEditorOptions {
  size_t undo_cap_bytes = size_t(64) << 20;  ///< undo record memory [bytes] (UndoHistory)
  int undo_max_strokes = 4096;               ///< strokes remembered for undo
  int queue_capacity = 4096;                 ///< tool positions and commands waiting for work
  /// Consecutive tool positions are merged into one sweep while none of them is farther than
  /// this fraction of the brush radius from the straight segment between the ends.
  double merge_tolerance = 0.02;
  /// Time constant of an optional first-order low-pass on the tool's axis [s] (0: none).
  double axis_time_s = 0.0;
  /// Normals are refreshed once per this much stroke time [s] when the samples may have moved by a
  /// twentieth of the grid spacing since, at the latest after 12 of it, and before any other
  /// command and on flush(), not after every sweep: a sample under the moving tool changes on many
  /// consecutive ticks, and its normals are the larger part of an edit's cost. Displacements (what
  /// the proxy stands on) change at once; normals (the force direction) follow.
  double normals_interval_s = 0.004;
};

/// One tool position, given by the servo thread on each tick of a stroke in contact.
struct ToolSample {
  Contact contact;            ///< the proxy's contact (slab, coordinates, surface point, unit normal)
  Vec3 hip = Vec3::Zero();    ///< haptic interaction point [model units]
  double normal_force_n = 0;  ///< rendered normal force [N]: pressure for Smooth, Flatten, Paint; Drill's F_n
  /// Model units per metre of device motion (hdm::Workspace::scale): Drill's unit conversion
  /// (BrushSweep::units_per_metre).
  double units_per_metre = 1000;
  double time_s = 0;  ///< servo time [s]
  /// The HIP is the centre of the ball the user feels (RenderMode::Sphere, a ball of the brush's
  /// radius held outside the surface), not a point on its rim: Carve centres its sphere at
  /// hip + axis·resilience, so the ball that cuts is the felt ball pushed in by the hand, less the
  /// resilient band. false: hip + axis·(radius + resilience) (paper §4.1).
  bool ball_centre = false;
};

/// One entry of an edit log: what a StrokeEditor applied, in order (StrokeEditor::record_log()).
/// Replaying a log on a copy of the model as it was (StrokeEditor::replay()) reproduces every
/// stored value bit for bit.
struct EditLogEntry {
  /// What the entry records: a stroke's start (Begin), one applied sweep (Sweep), its end (End),
  /// an undo or a redo of the last stroke.
  /// @{
  enum Kind : uint8_t { Begin, Sweep, End, Undo, Redo } kind = Sweep;
  /// @}
  BrushSweep sweep;  ///< Sweep: the sweep applied; Begin: sweep.brush is the stroke's brush
};

/// What StrokeEditor::work() did in one call.
struct EditWork {
  int32_t sweeps = 0;     ///< sweeps (and undo / redo steps) finished
  int32_t visited = 0;    ///< samples or texels visited
  int32_t changed = 0;    ///< samples or texels changed
  bool idle = true;       ///< nothing queued and no sweep in progress after the call
  bool deadline = false;  ///< stopped at the deadline with work left (it carries over to the next call)
  /// stopped before a slab the write gate refused (EditScratch::gate): the work carries over, and
  /// `deadline` is set too
  bool refused = false;
};

/// Applies strokes to one model, from the thread that owns the model, within a time budget.
///
/// A stroke is begin_stroke(brush) … add_sample() per tick … end_stroke() (button down to button
/// up). Normals of the changed samples are refreshed in batches (StrokeEditorOptions::normals_interval_s).
/// The tool's axis (where Carve puts its sphere above the HIP, Add its sphere on the surface, Flatten
/// its plane) is the normal of the stroke's starting surface around the contact: the area-weighted
/// normal of the grid triangles around the contact's cell, at the displacements the stroke found
/// there. The contact normal itself turns as soon as the proxy rides a wall the stroke cut, and a
/// sphere placed along it digs sideways and deeper on every tick (the groove wandered and sank 3 mm
/// over a 40 mm stroke in closed loop). Each sweep covers the path from the last position swept to the newest one
/// (positions that arrived while the previous sweep was running are merged into one segment while they stay within
/// StrokeEditorOptions::merge_tolerance of it, so the swept volume follows the hand). The tool's
/// axis is the contact normal low-passed over StrokeEditorOptions::axis_time_s. Carve and
/// Add are booleans with the swept sphere, so a stroke's result does not depend on the servo rate;
/// Paint keeps per stroke the largest intensity reached at each texel; Smooth and Flatten act at a
/// rate per second of contact.
///
/// work() runs queued sweeps until its deadline: a sweep too large for one call continues in the
/// next (the model then holds part of it: the proxy feels it at once; between_sweeps() tells when
/// no sweep is half done, the moment hdm::SlabSnapshots may copy the model for other threads).
///
/// Memory: everything is allocated by the constructor (about 60 bytes per sample and 30 per texel
/// plus the undo cap); no member function allocates, locks or does I/O.
/// Threading: one thread calls everything (the servo thread in hdm::SculptSession).
class StrokeEditor {
 public:
  /// @brief Allocates the editor's buffers for @p model (its topology must not change later) and
  /// gives the model's per-sample and per-texel fields of one value their arrays (materialise_fields()).
  StrokeEditor(SlabModel& model, const StrokeEditorOptions& options = {});
  ~StrokeEditor();
  StrokeEditor(const StrokeEditor&) = delete;
  StrokeEditor& operator=(const StrokeEditor&) = delete;

  /// @brief Starts a stroke with @p brush (closing an open one). Queued; noexcept.
  void begin_stroke(const Brush& brush) noexcept;
  /// @brief Adds the tool position of this tick to the open stroke. Queued: the sweep happens in
  /// work(). Ignored without an open stroke or when @p sample's contact is not in a slab. When the
  /// queue is full the newest position replaces the last queued one (the sweep then spans both).
  /// Reads @p model (the one work() edits) for the tool's axis: the normal of the surface as it
  /// was when the stroke began, around the contact (see ToolSample).
  /// @note O(one-ring of the contact's grid cell): about 20 grid triangles.
  void add_sample(const SlabModel& model, const ToolSample& sample) noexcept;
  /// @brief Ends the open stroke (its undo record closes once its sweeps are done). Queued.
  void end_stroke() noexcept;
  /// @brief Queues an undo of the last stroke (after any queued work). Returns false when the
  /// queue is full.
  bool undo() noexcept;
  /// @brief Queues a redo of the last undone stroke. Returns false when the queue is full.
  bool redo() noexcept;

  /// @brief Does queued work on @p model until @p deadline_ns (steady_clock nanoseconds since its
  /// epoch) or until nothing is left; checks the clock every few dozen samples, so it stops within
  /// about a microsecond of the deadline. A sweep or undo that does not fit continues next call.
  /// @note noexcept, no allocation. @p model must be the one given to the constructor (or a copy
  ///       of it made since, with the same topology), changed by nothing else between calls.
  EditWork work(SlabModel& model, int64_t deadline_ns) noexcept;
  /// True when no sweep or undo is half done and every normal is refreshed: the model holds
  /// whole edits only (what hdm::SlabSnapshots may copy).
  bool between_sweeps() const noexcept;
  /// @brief Asks work() to refresh the pending normals before its next sweep (a publication is
  /// due). noexcept.
  void flush() noexcept;
  /// True when nothing is queued, no sweep is in progress and every normal is refreshed.
  bool idle() const noexcept;
  /// True while a stroke is open (between begin_stroke and its end_stroke being processed).
  bool in_stroke() const noexcept;

  /// Dirty slabs and the other edit buffers (clear_dirty() after consuming the dirty list).
  EditScratch& scratch() noexcept;
  /// The undo history (counts, memory).
  const UndoHistory& history() const noexcept;
  /// Total samples / texels changed since construction.
  int64_t total_changed() const noexcept;

  /// @brief Appends what work() applies from now on (stroke begins and ends, sweeps, undo and
  /// redo steps) to @p log, up to its capacity (reserve it first: nothing is allocated); nullptr
  /// stops. For measurements (the swept tools against the exact boolean,
  /// hdm::measure_edit_fidelity) and replays.
  void record_log(std::vector<EditLogEntry>* log) noexcept;
  /// @brief Queues a logged entry to be applied as recorded (a Sweep entry is applied as is, not
  /// recomputed from tool samples). Returns false when the queue is full.
  bool replay(const EditLogEntry& entry) noexcept;

  /// Steady-clock time now [ns since the clock's epoch], the unit of work()'s deadline.
  static int64_t now_ns() noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hdm
