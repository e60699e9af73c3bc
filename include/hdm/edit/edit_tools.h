// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Sculpting and painting kernels: one application of a brush swept between two tool positions
/// (a sphere when they coincide, a capsule otherwise), by flood fill over the global sample (or
/// texel) graph, which crosses slab edges and corners by construction (paper §4-5;
/// docs/design.md#edits). The paper's single-stamp tools (carve, add_material, paint) are the same kernels with
/// both ends at one point. Strokes, the per-tick work budget and undo are in stroke_editor.h.

#include <hdm/edit/brush.h>
#include <hdm/query/slab_query.h>

#include <array>
#include <cstdint>
#include <vector>

namespace hdm {

/// A check the editor makes before it first writes a slab's data (displacement, normals, fields,
/// texels) after the dirty flags were cleared: hdm::SculptSession sets SlabSnapshots::before_write()
/// here, so that the slab's committed state is copied before the edit changes it. Unset: every slab
/// may be written.
struct WriteGate {
  /// true: slab @p slab may be written until the dirty flags are cleared (clear_dirty()); false:
  /// not yet. hdm::StrokeEditor then stops before that write and retries it on its next call.
  bool (*allow)(void* user, int32_t slab) noexcept = nullptr;
  void* user = nullptr;  ///< passed to `allow`
};

/// Caller-owned buffers for edits, sized once for a model so that edits never allocate (they may
/// run in the servo loop). One per editing thread.
struct EditScratch {
  /// @brief Sizes every buffer for @p model and gives its fields of one value their arrays
  /// (materialise_fields()), so that no edit allocates. Allocates O(#samples + #texels + #S): about
  /// 12 bytes per sample, 8 per texel, 5 per slab, plus a fixed ~120 KB (face-normal memo), and up
  /// to 10 bytes per sample and 4 per texel in the model.
  explicit EditScratch(SlabModel& model);
  /// @{ Visit marks of the current edit: #samples and #texels entries (equal to `stamp` once visited).
  std::vector<uint32_t> sample_stamp, texel_stamp;
  /// @}
  uint32_t stamp = 0;          ///< current edit's mark
  std::vector<int32_t> queue;  ///< flood-fill queue (samples or texels)
  /// Samples whose displacement changed since their normals were last refreshed, once each:
  /// `changed[0 .. changed_count)`. Sweeps list them; refresh_normals() (or the stroke editor's
  /// batched refresh) recomputes the normals of their rings and empties the list.
  std::vector<int32_t> changed;
  int32_t changed_count = 0;           ///< entries of `changed` in use
  std::vector<uint32_t> changed_mark;  ///< per sample: == changed_epoch when listed
  uint32_t changed_epoch = 1;          ///< current listing's mark
  std::vector<int32_t> ring;           ///< changed samples plus their neighbours
  /// #S flags: slabs whose data (displacement, normals, fields, colours) edits changed since the
  /// flags were last cleared; `dirty_list[0 .. dirty_count)` lists them once each. The consumer
  /// (a renderer, hdm::SlabSnapshots' publisher) clears both with clear_dirty().
  std::vector<uint8_t> dirty_slabs;
  std::vector<int32_t> dirty_list;  ///< #S: the flagged slabs, in the order flagged
  int32_t dirty_count = 0;          ///< entries of dirty_list in use
  /// Asked before a slab is first flagged dirty, which is before it is written. Only
  /// hdm::StrokeEditor honours a refusal; the one-shot edits (apply_brush(), carve(), add_material(),
  /// paint(), refresh_normals()) need it unset.
  WriteGate gate;
  bool write_refused = false;  ///< the gate refused a slab in the last call: the edit stopped before writing it
  FaceNormalCache faces;       ///< per-triangle normals, each computed once per edit
  /// per_slab entries: barycentrics (wR, wS, wT) of each grid index of the displacement grid, as
  /// projection_line() computes them (same bits), so the flood fill does not divide per sample.
  std::vector<std::array<double, 3>> grid_weights;
  /// texels.per_slab entries: for each texel grid index, its barycentrics (wS, wT) and the grid
  /// cell of the displacement grid that holds it (three grid indices and their weights, as
  /// evaluate_surface() finds them), so paint evaluates a texel's surface point without searching.
  std::vector<std::array<double, 5>> texel_weights;  ///< wS, wT, wa, wb, wd
  std::vector<std::array<int32_t, 3>> texel_points;  ///< la, lb, ld
  /// Mean length of a displacement-grid edge on the surface at construction [model units]: the
  /// flood fill of Carve and Add continues through samples up to max(0.25·r, 1.5 × this) outside
  /// the tool, so that it crosses the surface the previous sweep left on the tool's boundary.
  double sample_spacing = 0;
};

/// @brief Clears the dirty flags and list of @p scratch. noexcept, O(dirty_count).
void clear_dirty(EditScratch& scratch) noexcept;

/// @brief Recomputes the normals, the slab-major copy and the force-shading normals of the rings
/// of the samples listed in `scratch.changed`, flags their slabs dirty and empties the list.
/// @note noexcept, no allocation; O(listed·valence²). apply_brush() and the single-stamp tools
///       call it; hdm::StrokeEditor batches it over several sweeps.
void refresh_normals(SlabModel& model, EditScratch& scratch) noexcept;

/// What one edit did.
struct EditResult {
  int32_t visited = 0;  ///< samples (texels for texel fields) the flood fill visited
  int32_t changed = 0;  ///< samples (texels) whose value changed
};

/// One application of a brush, swept from `from` to `to` (model units, model frame).
///
/// The tool's path: for Carve and Add the sphere's centre; for Smooth, Flatten and Paint the
/// surface contact point (the brush centre). The flood fill is seeded with the grid cell under
/// (seed_slab, seed_bary), normally the contact at `to`.
struct BrushSweep {
  Brush brush;                        ///< the brush
  Vec3 from = Vec3::Zero();           ///< path start [model units]
  Vec3 to = Vec3::Zero();             ///< path end [model units]
  Vec3 plane_point = Vec3::Zero();    ///< Flatten: a point of the tool's plane [model units]
  Vec3 plane_normal = Vec3::UnitZ();  ///< Flatten: the plane's unit normal
  int32_t seed_slab = -1;             ///< slab of the seed cell (nothing happens when < 0)
  Vec3 seed_bary = Vec3::Zero();      ///< barycentrics (wR, wS, wT) of the seed in that slab
  double pressure = 1;                ///< [0,1]: scales Smooth, Flatten and Paint
  double dt = 0;                      ///< Smooth, Flatten, Drill: contact time the sweep stands for [s]
  double normal_force_n = 0;          ///< Drill: the contact's normal force over that time [N], >= 0
  /// Drill: model units per metre (hdm::Workspace::scale, the model's size as the hand feels it):
  /// converts the radius to metres for the burr's speed and the removed volume [m³] to model units.
  double units_per_metre = 1000;
};

/// @brief Applies @p sweep to @p model at once (every sample it reaches, then the normals), as
/// a stroke of its own: the stroke's starting values are the model's current ones.
/// @return samples (texels for Colour and Roughness) visited and changed.
/// @note noexcept; no allocation; refreshes normals, the slab-major copy and the
///       force-shading normals of the changed samples and their rings, and flags dirty slabs.
///       Cost O(visited·valence). For a bounded cost per servo tick use hdm::StrokeEditor.
EditResult apply_brush(SlabModel& model, EditScratch& scratch, const BrushSweep& sweep) noexcept;

/// @brief Carve: remove material inside a sphere of radius @p radius centred at
/// hip + n·(radius + resilience), n the contact normal (paper §4.1, Fig. 7).
/// @param model       slab model with derived data; edited in place.
/// @param scratch     buffers sized for @p model (EditScratch).
/// @param contact     current contact (must be in a slab; nothing happens otherwise).
/// @param hip         haptic interaction point [model units].
/// @param radius      tool radius [model units], > 0.
/// @param resilience  resilient band k [model units], >= 0: carving starts once the depth exceeds it.
/// @note No allocation. Displacement of a sample whose projection line enters the sphere below its
///       surface is lowered to the sphere's entry point; a sphere buried below the surface leaves
///       the column unchanged (no cavities); δ stays in [0,1]. Never raises a sample. Updates the
///       slab-major copies and normals of the changed samples and their one-ring, marks dirty slabs.
///       Cost O(visited·valence). apply_brush() with BrushTool::Carve and from = to.
EditResult carve(SlabModel& model, EditScratch& scratch, const Contact& contact, const Vec3& hip, double radius,
                 double resilience) noexcept;

/// @brief Add material: a cone of height @p height and radius @p radius centred at the surface
/// contact point: δ += height·max(0, 1 - d/r)/|P1 - P0|, clamped to 1 (paper §4.2; the cone falls
/// linearly with distance, docs/design.md#adding-material). The paper's cumulative deposit (each call adds),
/// kept for comparison; strokes use BrushTool::Add (a swept boolean union).
/// @note Never lowers a sample. No allocation; O(visited·valence).
EditResult add_material(SlabModel& model, EditScratch& scratch, const Contact& contact, double radius,
                        double height) noexcept;

/// @brief Paint: texels within @p radius of the surface contact point blend towards @p colour with
/// intensity k = pressure·(1 - d/r): c ← k·colour + (1-k)·c (paper §5).
/// @param model     slab model with derived data; its `colour` texels are edited in place.
/// @param scratch   buffers sized for @p model (EditScratch).
/// @param contact   current contact (must be in a slab; nothing happens otherwise).
/// @param radius    brush radius [model units], > 0.
/// @param colour    target colour, linear RGB in [0,1].
/// @param pressure  in [0,1] (clamped), from the penetration depth (see paint_pressure()).
/// @note Texel positions are taken on the displaced surface. No allocation; O(visited).
///       apply_brush() with BrushTool::Paint, BrushField::Colour, Falloff::Linear and from = to.
EditResult paint(SlabModel& model, EditScratch& scratch, const Contact& contact, double radius, const Vec3f& colour,
                 double pressure) noexcept;

/// @brief Paint pressure from penetration depth: clamp((depth - d0)/(d1 - d0), 0, 1) (docs/design.md#painting).
/// @param depth  penetration depth [model units] (or a normal force [N], with d0, d1 in N).
/// @param d0  dead zone [model units]: lighter touches do not paint. @param d1 depth of full pressure.
/// The same ramp maps a normal force to pressure (hdm::StrokeEditor: d0 = 0.1·F1, d1 = F1).
double paint_pressure(double depth, double d0, double d1) noexcept;

/// @brief Puts the under-layer @p thickness below the current surface, measured along the surface
/// normal (SlabModel::layer_displacement = clamp(δ − thickness/(|P1 − P0|·cos θ), 0, 1), θ the
/// angle between the projection line and the normal, cos θ at least 0.2), and sets its material:
/// the two-layer set-up of paper §2 (e.g. enamel over dentin).
/// @param model      slab model with derived data; `layer_displacement` and `under_layer` are set.
/// @param thickness  [model units], >= 0.
/// @param material   the under-layer's colour, stiffness and friction.
/// @throws std::bad_alloc when the layer's array (2 bytes per sample; none when every sample's top
///         comes out the same) cannot be allocated.
/// @note O(#samples): a set-up step (not for the servo tick). Derived data need no refresh (the
///       layer is read directly by the proxy and the renderer).
void set_under_layer(SlabModel& model, double thickness, const UnderLayer& material);

/// @brief The interval of t in which the line p0 + t·L passes within @p radius of the segment
/// [a, b] (the capsule around it; a sphere when a = b).
/// @param p0      a point of the line [model units].
/// @param L       the line's direction (any length, not zero); t is measured in units of |L|.
/// @param a       one end of the segment [model units].
/// @param b       the other end [model units].
/// @param radius  capsule radius [model units], >= 0.
/// @param[out] t_in, t_out  the interval's ends when it is not empty.
/// @return false when the line misses the capsule.
/// @note noexcept, O(1): the union of the intervals of the two end spheres and of the cylinder
///       between them, which is one interval because the capsule is convex.
bool line_capsule(const Vec3& p0, const Vec3& L, const Vec3& a, const Vec3& b, double radius, double& t_in,
                  double& t_out) noexcept;

}  // namespace hdm
