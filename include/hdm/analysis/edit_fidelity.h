// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// How closely an edited slab model follows the exact boolean of its input with the swept tools:
/// an independent reference for carve and add (Embree distances and inside tests on the input
/// combined with analytic capsule distances), as for the bake's fidelity
/// (docs/design.md#how-we-measure).

#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/slab/slab_model.h>

#include <vector>

namespace hdm {

/// One swept sphere: the capsule of radius `radius` around the segment [a, b] [model units].
struct ToolCapsule {
  /// @{ Ends of the swept segment [model units].
  Vec3 a = Vec3::Zero(), b = Vec3::Zero();
  /// @}
  double radius = 0;     ///< radius of the swept sphere [model units], > 0
  bool add = false;      ///< false: material removed (carve); true: material added (union)
  bool measured = true;  ///< the band measured is around the measured tools (all tools shape the exact solid)
};

/// Distances between the edited model's surface and the exact edited solid, near the tools.
struct EditFidelity {
  double rms_pct = 0;       ///< RMS distance from model surface points to the exact surface, % of the diagonal
  double max_pct = 0;       ///< maximum of the same
  double rms_back_pct = 0;  ///< RMS distance from exact surface points to the model surface, % of the diagonal
  double max_back_pct = 0;  ///< maximum of the same
  int64_t points = 0;       ///< model surface points measured (samples and grid-triangle centroids)
  int64_t back_points = 0;  ///< exact surface points measured (tool walls and untouched input)
  double diagonal = 0;      ///< the input's bounding-box diagonal [model units]
};

/// @brief Measures the edited @p model against the exact solid B: the input (closed mesh) with the
/// @p tools applied in order (carve: B ∖ capsule, add: B ∪ capsule).
///
/// The exact signed distance of B at a point composes the input's (Embree closest point, sign by
/// ray parity) with the analytic capsule distances (max(d, −c) for carve, min(d, c) for add). It is
/// the exact distance to B's surface wherever the nearest feature is a face of B and a lower bound
/// near B's concave creases. Measured, in both directions, only within `margin` beyond the tools
/// (where the edit could change anything), around the tools marked `measured`:
/// - model → exact: every sample and grid-triangle centroid of the displaced surface within
///   radius + margin of a tool segment, |signed distance of B| there;
/// - exact → model: points of B's surface there (the tools' walls inside the input for carve,
///   outside it for add, sampled on the swept envelope about every @p spacing; and the input's
///   vertices and face centroids that no tool touched), their distance to the displaced surface
///   (an Embree BVH over its grid triangles).
/// @param model    the edited slab model (derived data built) [model units].
/// @param input    exact queries on the input mesh the model was baked from.
/// @param tools    the swept spheres, in the order they were applied (e.g. a session's sweep log).
/// @param margin   width of the measured band beyond the tools [model units], > 0.
/// @param spacing  sampling step of the tools' walls [model units], > 0 (about the grid spacing).
/// @throws InvalidInput when @p tools is empty or margin / spacing are not positive.
/// @note Allocates; O(points · (log #F + tools nearby)); parallel (TBB).
EditFidelity measure_edit_fidelity(const SlabModel& model, const ExactMeshQuery& input,
                                   const std::vector<ToolCapsule>& tools, double margin, double spacing);

}  // namespace hdm
