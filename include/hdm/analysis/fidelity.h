// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Analyzers that measure a slab model against its input with exact queries on the input
/// (docs/design.md#how-we-measure). Tests, `hdm bake`, `hdm check` and benchmarks all use these.

#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/slab/slab_model.h>

#include <cstdint>
#include <cmath>
#include <vector>

namespace hdm {

/// Two-sided surface distance, as % of the input's bounding-box diagonal.
struct Fidelity {
  double rms_pct = 0;       ///< RMS distance from reconstructed surface points to the input
  double max_pct = 0;       ///< maximum of those (one-sided Hausdorff)
  double rms_back_pct = 0;  ///< RMS distance from input points to the reconstructed surface
  double max_back_pct = 0;  ///< maximum of those
  int64_t points = 0;       ///< reconstructed points measured (samples and grid-triangle centroids)
  int64_t back_points = 0;  ///< input points measured (vertices and face centroids)
  /// rms_pct with the points beyond measure_fidelity()'s `far_pct` counted as 0: the error of
  /// the sampling where the reconstruction follows the input (equal to rms_pct without far_pct).
  double rms_within_pct = 0;
  double rms_back_within_pct = 0;  ///< rms_back_pct, likewise
};

/// @brief Fidelity of @p model against @p input: every sample and grid-triangle centroid of the
/// reconstructed surface to the input, and every input point (@p input_points, by default every
/// input vertex and face centroid) to the reconstructed surface (Embree BVHs over the displaced
/// grid triangles, one chunk of slabs at a time; each distance is the least over the chunks).
/// @param model   slab model with derived data (rebuild_derived()).
/// @param input   exact queries on the mesh @p model was baked from (same frame and units).
/// @param input_points  optional points of the input's surface that the input-to-model direction
///                measures (surface_points()), in @p input's frame; not owned. A bake of a mesh
///                that crosses itself passes the points of the faces before they were resolved,
///                so that it and `hdm check` (which measures against those faces) measure the
///                same points.
/// @param far_pct  with @p far_points: the distance [% of the input's diagonal] beyond which a
///                measured point is listed.
/// @param[out] far_points  optional: the measured points (reconstructed points, then input points)
///                farther than @p far_pct from the other surface [model units]: where the
///                reconstruction misses a bound (bake_to_tolerance() refines there).
/// @param chunk_triangles  grid triangles per BVH at most (whole slabs, in Morton order of their
///                boxes; at least one slab a chunk): bounds the memory the measurement adds to the
///                model's (about 300 MB per 2^21 triangles). The figures do not depend on it.
/// @note Parallel (TBB); O((#samples + #points) log #F), plus a box test per input point and
///       chunk. At 100,000 slabs (25.6 M grid triangles, 13 chunks) the bake's peak is 1.3 GB
///       instead of 2.7 (docs/performance.md#peak-memory-of-a-100000-slab-bake).
Fidelity measure_fidelity(const SlabModel& model, const ExactMeshQuery& input,
                          const std::vector<Vec3>* input_points = nullptr, double far_pct = INFINITY,
                          std::vector<Vec3>* far_points = nullptr, int64_t chunk_triangles = int64_t(1) << 21);

/// @brief The points of an input that measure_fidelity() measures from the input to a model:
/// every vertex and face centroid, or with @p interior, those on the surface of the material.
/// @param input     exact queries on the input (its mesh and whether it is closed).
/// @param interior  optional #F flags of input faces that are not on the surface of the material
///                (interior_faces()): their centroids, vertices all of whose faces are interior, and
///                vertices inside the material (the point 10⁻⁵, closed input 10⁻⁹, of the
///                diagonal in front of the vertex, along its exposed faces' normal, is inside: a
///                vertex of a face that crosses another part) are left out.
/// @return the points, in @p input's frame.
/// @note O(#V + #F); with @p interior, a winding-number tree (O(#F log #F)) and one query per
///       exposed vertex, parallel (TBB).
std::vector<Vec3> surface_points(const ExactMeshQuery& input, const std::vector<uint8_t>* interior);

/// @brief Faces of an input that are not on the boundary of the material it bounds: faces of a
/// part pushed into another (a mesh that crosses itself), whose outside is still inside the
/// union. Inside is where the generalized winding number (WindingNumber, Jacobson et al. 2013)
/// is at least ½: it counts the parts covering a point, and rays of an open input would leave
/// through its openings. Open input: interior when the point 10⁻⁵ of the diagonal in front of the
/// centroid is inside (the rule resolve_open_self_intersections() drops faces by). Closed input: the
/// rule resolve_self_intersections() keeps pieces by, 10⁻⁹ of the diagonal off the centroid
/// (layers may run closer than 10⁻⁵): interior when the point in front is inside or the point
/// behind is not (no material on either side: a fin, a part turned inside out). No face of a
/// closed, consistently oriented mesh that does not cross itself is interior.
/// @return #F flags (1: interior).
/// @note Parallel (TBB); O(#F log #F) for the winding-number tree, O(log #F) terms per point away
///       from the surface, more near it.
std::vector<uint8_t> interior_faces(const ExactMeshQuery& input);

/// Contact accuracy near the surface.
struct ContactAccuracy {
  int64_t points = 0;              ///< query points
  double agreement = 0;            ///< fraction whose inside/outside matches the exact test on the input
  double depth_rms_pct = 0;        ///< RMS |hdm depth - exact distance| over points inside both, % of diagonal
  double depth_max_pct = 0;        ///< maximum of those
  int64_t missed_below_shell = 0;  ///< disagreements: exactly inside, but in no slab and not inside the core test
  int64_t missed_in_shell = 0;     ///< disagreements: exactly inside, in a slab, but above the displaced surface
  int64_t false_inside =
      0;  ///< disagreements: exactly outside, but below the displaced surface or inside the core test
};

/// @brief Contact accuracy: @p count points on the input surface (uniform by area, fixed @p seed)
/// offset along the face normal by a uniform amount in ±@p offset_pct % of the diagonal (1% in
/// docs/design.md#how-we-measure); hdm's inside/outside (penetration > 0 in a slab, or, in no slab,
/// ExactMeshQuery::inside on the inner shell's triangles for a closed model, on the displaced
/// surface's triangles for an open one: the side of the nearest face, the reference's own rule)
/// against ExactMeshQuery::inside on the input, hdm's depth against the exact distance.
/// @param model       the slab model [model units].
/// @param input       the exact input (Embree).
/// @param count       number of points.
/// @param seed        random seed of the sampling.
/// @param offset_pct  half-range of the offset along the normal, % of the diagonal.
/// @param interior  optional #F flags of interior input faces (interior_faces()). For an open input that
///                crosses itself, the points are drawn from the exposed faces only and judged
///                against them alone (the side of the nearest exposed face): interior faces are not
///                on the surface a user touches (resolve_open_self_intersections() drops them). Ignored for
///                a closed input, whose inside (the union's winding) already accounts for them.
/// @pre @p input is oriented as orient_outward() orients it (an open input's inside is the back
///      of its surface).
/// @note Parallel (TBB).
ContactAccuracy measure_contact(const SlabModel& model, const ExactMeshQuery& input, int64_t count, uint64_t seed,
                                double offset_pct = 1.0, const std::vector<uint8_t>* interior = nullptr);

}  // namespace hdm
