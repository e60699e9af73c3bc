// SPDX-License-Identifier: MIT
#pragma once
// Internal: the resumable edit job shared by the one-shot tools (edit_tools.cpp) and the stroke
// editor (stroke_editor.cpp). A job is one sweep of a brush, or one undo / redo step; it runs in
// phases (flood fill, then normals → force-shading normals of the changed samples'
// rings), each of which can stop at a deadline and resume on the next call with the same result
// bit for bit: the flood visits the same samples in the same order however it is cut.

#include <hdm/edit/edit_tools.h>
#include <hdm/edit/undo_history.h>

#include <bit>
#include <chrono>
#include <cstdint>
#include <vector>

namespace hdm::edit::detail {

// A texel's stored codes (SlabModel::colour and roughness): 4 bytes, copied without decoding and
// compared as one word (no branch per channel: paint compares every blend it makes).
struct TexelCodes {
  Srgb8 colour;
  uint8_t roughness = 0;
  friend bool operator==(const TexelCodes& a, const TexelCodes& b) noexcept {
    return std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b);
  }
};
static_assert(sizeof(TexelCodes) == 4);

// Per-stroke memory: the values each sample and texel had when the stroke first touched it, and the
// largest paint intensity the stroke reached there. Lets Add measure from the stroke's starting
// surface, Paint blend once per stroke, and undo record each value once. Texels keep their codes
// (4 bytes, not 16 of decoded floats): paint decodes them to blend, undo when it records.
struct StrokeMemory {
  explicit StrokeMemory(const SlabModel& m);
  uint32_t id = 0;  // current stroke (0: none); marks equal to id are valid
  std::vector<uint32_t> sample_mark, texel_mark;
  std::vector<SampleValues> sample_base;
  std::vector<TexelCodes> texel_base;
  std::vector<float> sample_k, texel_k;
  UndoHistory* history = nullptr;  // receives a record at each first touch (optional)
  void next_stroke() noexcept;
};

inline SampleValues sample_values(const SlabModel& m, int32_t s) noexcept {
  return {m.displacement[s],    m.friction_static[s],    m.friction_dynamic[s],
          m.stiffness_scale[s], m.layer_displacement[s], m.hardness[s]};
}
// The texel's stored codes decoded; set_texel_values() of them writes the same codes back
// (every code survives decode → encode), so undo and the stroke's base restore texels exactly.
inline TexelCodes texel_codes(const SlabModel& m, int32_t t) noexcept { return {m.colour[t], m.roughness[t]}; }
inline TexelValues decode_texel(TexelCodes c) noexcept {
  const Vec3f v = decode_srgb8(c.colour);
  return {v.x(), v.y(), v.z(), unorm8_to_unit(c.roughness)};
}
inline TexelValues texel_values(const SlabModel& m, int32_t t) noexcept { return decode_texel(texel_codes(m, t)); }
inline void set_texel_values(SlabModel& m, int32_t t, float r, float g, float b, float roughness) noexcept {
  m.colour.set(t, encode_srgb8(Vec3f(r, g, b)));
  m.roughness.set(t, unit_to_unorm8(roughness));
}

// Deadline on steady_clock, read once every `kEvery` checks (a clock read costs ~25 ns).
class Deadline {
 public:
  explicit Deadline(int64_t end_ns) noexcept : end_ns_(end_ns) {}
  static Deadline never() noexcept { return Deadline(INT64_MAX); }
  // @p work: elements about to be processed (the clock is read once about every kEvery of them).
  bool expired(int work = 1) noexcept {
    if (end_ns_ == INT64_MAX) return false;
    if ((countdown_ -= work) > 0) return false;
    countdown_ = kEvery;
    return now_ns() >= end_ns_;
  }
  static int64_t now_ns() noexcept {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
  }

 private:
  static constexpr int kEvery = 24;
  int64_t end_ns_;
  int countdown_ = 1;
};

class EditJob;
struct DirtyMarker;

// What a sweep floods: nothing (the sweep has no effect), the samples or the texels.
enum class FloodOn : uint8_t { Nothing, Samples, Texels };

// A brush's kernel (src/edit/brush_registry.cpp lists one per brush; each is defined in its
// family's flood_*.cpp). `start` decides from the sweep and its relaxation coefficient (rate ×
// strength × pressure × dt) whether and what the sweep floods; `flood` runs the job's flood until
// done (true) or until the deadline, resumable with the same result bit for bit.
struct BrushHooks {
  FloodOn (*start)(const BrushSweep& sweep, double coef) noexcept;
  bool (*flood)(EditJob& job, SlabModel& m, EditScratch& s, Deadline& d) noexcept;
};

class EditJob {
 public:
  // A sweep (nothing happens when the seed is not in a slab). `stroke` may be null: the stroke's
  // starting values are then the current ones and nothing is recorded.
  void start_sweep(const SlabModel& m, EditScratch& s, const BrushSweep& sweep, StrokeMemory* stroke) noexcept;
  // The paper's cumulative cone deposit (add_material).
  void start_paper_cone(const SlabModel& m, EditScratch& s, const Contact& c, double radius, double height) noexcept;
  // Swaps the records of the last applied (undo) or first undone (redo) stroke into the model.
  void start_history(EditScratch& s, UndoHistory& h, bool redo) noexcept;
  // Refreshes the normals of the rings of the samples listed in s.changed, then empties the list.
  void start_normals(EditScratch& s) noexcept;
  // Runs until done (returns true) or until the deadline.
  bool run(SlabModel& m, EditScratch& s, Deadline& d) noexcept;
  bool active() const noexcept { return phase_ != Phase::Idle; }
  /// The largest squared distance a sample moved in this job [model units²].
  double motion2() const noexcept { return motion2_; }
  /// The flood's stamp, new for each sweep: a seed for the sweep's rounding draws.
  uint32_t stamp() const noexcept { return stamp_; }
  EditResult result;

  // What the kernels read: the sweep being run and its constants, derived once per sweep.
  BrushSweep sweep;
  StrokeMemory* stroke = nullptr;
  Vec3 u = Vec3::Zero();  // to − from
  double r2 = 0;          // radius²
  double coef = 0;        // relaxation exponent per unit falloff: 20 s⁻¹ × strength × pressure × dt
  bool soft = false;      // strength < 1 or a falloff other than constant
  // State a two-pass kernel (drill: the contact area, then the removal) carries between calls;
  // zero at each sweep's start.
  double kernel_sum = 0;
  int32_t kernel_cursor = 0;
  bool kernel_second = false;

  // The flood fill from the seeds start_sweep queued: visit(id) returns whether the fill goes on
  // through that element; resumable at the deadline.
  template <class Visit>
  bool flood(const SampleLayout& L, std::vector<uint32_t>& marks, EditScratch& s, Deadline& d, Visit visit) noexcept;
  // Stores a sample's new displacement (rounded to its unorm16 code; nothing when that is the code
  // it has) on its projection line of squared length line2 (its motion, for the snapshot's bound),
  // recording its first touch in the stroke; false, with nothing written, when the write gate
  // refused one of its slabs.
  bool set_delta(SlabModel& m, EditScratch& s, DirtyMarker& dirty, int32_t id, float v, double line2) noexcept;

 private:
  // An edit's phases, in order: the flood over the tool (Flood) or an undo record's replay
  // (History); the changed samples and their one-ring listed (Ring), their normals (Normals); the
  // ring's ring listed (ShadingRing), whose force-shading normals are recomputed (ForceShading).
  enum class Phase : uint8_t { Idle, Flood, History, Ring, Normals, ShadingRing, ForceShading };
  bool run_flood(SlabModel& m, EditScratch& s, Deadline& d) noexcept;
  bool run_history(SlabModel& m, EditScratch& s, Deadline& d) noexcept;
  bool run_normals(SlabModel& m, EditScratch& s, Deadline& d) noexcept;

  Phase phase_ = Phase::Idle;
  bool (*flood_)(EditJob&, SlabModel&, EditScratch&, Deadline&) noexcept = nullptr;
  UndoHistory* history_ = nullptr;
  bool redo_ = false;
  uint64_t rec_pos_ = 0, rec_end_ = 0;
  // flood state
  size_t head_ = 0, tail_ = 0;
  uint32_t stamp_ = 0;
  // normals state
  int32_t cursor_ = 0, ring_count_ = 0, shading_count_ = 0;
  int32_t marked_ = 0;  // ring samples whose slabs are flagged, before their normals are written
  double motion2_ = 0;
};

// The paper's cone deposit (add_material), the one kernel that is not a brush (flood_shape.cpp).
bool paper_cone_flood(EditJob& job, SlabModel& m, EditScratch& s, Deadline& d) noexcept;

}  // namespace hdm::edit::detail
