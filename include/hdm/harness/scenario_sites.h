// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Where the `hdm feel` scenarios touch a model, found from the model's own geometry (the exact
/// input mesh, and the slab corners for `edges`) rather than laid out for one model: a smooth,
/// exposed stroke for `slide`, a thick smooth spot for `press`, the thinnest sheet reachable from
/// outside for `thin`, and a spiral round a slab corner for `edges`.
///
/// Every search is deterministic: surface samples come from a fixed-seed generator and ties are
/// broken by sample order. All lengths are in model units, in the model frame; normals are unit.

#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/query/slab_locator.h>
#include <hdm/slab/slab_model.h>

#include <cstdint>
#include <vector>

namespace hdm {

/// A point on the input surface with its normals.
struct SurfacePoint {
  Vec3 point = Vec3::Zero();         ///< on the input mesh [model units]
  Vec3 normal = Vec3::UnitZ();       ///< interpolated (area-weighted vertex) normal there, unit
  Vec3 face_normal = Vec3::UnitZ();  ///< normal of the face that holds it, unit
  int32_t face = -1;                 ///< that face
};

/// A stroke over the surface: points about evenly spaced along a curve on the input.
struct SurfaceStroke {
  std::vector<SurfacePoint> points;  ///< in stroke order
  double roughness_deg = 0;          ///< p95 angle between face and interpolated normals along it [deg]
  double bend_deg = 0;               ///< largest turn of the interpolated normal between neighbouring points [deg]
  int slab_crossings = 0;            ///< changes of the slab that holds the point along the stroke (edges only)
};

/// A place to push through a thin part.
struct ThinSite {
  SurfacePoint entry;        ///< where the push enters (its normal points out of the part)
  Vec3 exit = Vec3::Zero();  ///< where the line entry - t·normal leaves the part [model units]
  double thickness = 0;      ///< |exit - entry| [model units]
};

/// Settings of the searches. Fractions are of the input's bounding-box diagonal.
struct SiteOptions {
  uint64_t seed = 20020701;     ///< surface-sampling seed (fixed: runs are reproducible)
  int samples = 16384;          ///< area-weighted surface samples
  int candidates = 256;         ///< exposed samples tried as stroke starts / press spots
  double clearance = 0.1;       ///< free line along the normal that makes a point "exposed"
  double stroke_length = 0.25;  ///< slide stroke length (one way)
  double min_depth = 0.04;      ///< slide / edges: the part under the stroke is at least this thick
  double min_thin = 0.008;      ///< thin: thinner parts count as degenerate (below the bake's resolution)
  double max_thin = 0.06;       ///< thin: thicker parts are not "thin"
};

/// Surface sampling and normals of an input mesh, and the site searches.
///
/// Threading: const methods may run concurrently. Cost: construction O(#V + #F + samples·ray);
/// each search is a few hundred thousand Embree queries at most (well under a second on the
/// real models).
class ScenarioSites {
 public:
  /// @brief Precomputes vertex normals and @p options.samples area-weighted surface samples.
  /// @param reference  the exact input (must outlive this object); closed and outward-oriented.
  /// @param options    sample count and the site searches' settings.
  /// @throws InvalidInput when the mesh has no face of positive area.
  ScenarioSites(const ExactMeshQuery& reference, const SiteOptions& options = {});

  /// @brief The closest point of the input to @p p, with its interpolated and face normals.
  SurfacePoint project(const Vec3& p) const;

  /// @brief True when the segment from just off @p s along its normal to @p distance away misses the input.
  bool exposed(const SurfacePoint& s, double distance) const;

  /// @brief Distance from @p s along -normal to where that line leaves the part; +inf when it never does.
  double thickness(const SurfacePoint& s) const;

  /// @brief Slide: the smoothest exposed stroke of `stroke_length` over a part at least
  /// `min_depth` thick (least roughness + bend, over `candidates` starts × 8 directions), walked
  /// on the surface by repeated closest-point projection.
  /// @throws InvalidInput when no candidate stroke qualifies.
  SurfaceStroke slide_stroke() const;

  /// @brief Press: among exposed samples with a smooth neighbourhood, the one over the thickest part.
  /// @throws InvalidInput when none qualifies.
  SurfacePoint press_spot() const;

  /// @brief Thin: the thinnest sheet reachable from outside. A sample qualifies when it is exposed,
  /// the line along -normal leaves the part within [min_thin, max_thin] through a face turned at
  /// least 145° from the entry's, the far side is exposed too, the slab model represents the entry
  /// side (a point a quarter thickness inside is inside the model's surface, within a quarter
  /// thickness of the input's tangent plane, normal within 25°), and the sheet is neither a sliver
  /// nor a rim: on at least six of eight sides 1.5 thicknesses away (at least 0.02 of the diagonal)
  /// the thickness is within 0.5-3× and the normal within 35°. The thinnest sample among those
  /// agreeing on all eight sides wins, else seven, else six.
  /// @param model    the slab model baked from the input: parts it cannot resolve are degenerate.
  /// @param locator  its locator.
  /// @throws InvalidInput when no sample qualifies (the model has no thin part).
  ThinSite thin_site(const SlabModel& model, const SlabLocator& locator) const;

  /// @brief Edges: a two-turn spiral (radius 0.35 to 1.1 of the mean corner spacing) round the
  /// slab corner whose neighbourhood is smoothest and exposed, so that it crosses every slab edge
  /// at that corner twice and passes the neighbouring corners, among the spirals the slab model
  /// represents (at every point, 0.002 of the diagonal under it is inside the rendered surface,
  /// whose point is within that depth of the input's tangent plane and whose normal is within 15°
  /// of the input's interpolated normal).
  /// @param model    the slab model baked from the input (its coarse corners and slabs).
  /// @param locator  its locator, to count slab crossings and test the representation.
  /// @throws InvalidInput when no corner qualifies.
  SurfaceStroke edges_spiral(const SlabModel& model, const SlabLocator& locator) const;

  /// The input's bounding-box diagonal [model units].
  double diagonal() const { return diag_; }

 private:
  SurfaceStroke walk(const SurfacePoint& start, const Vec3& direction, double length, int steps) const;
  void score(SurfaceStroke& s) const;
  bool stroke_ok(const SurfaceStroke& s) const;

  const ExactMeshQuery& ref_;
  SiteOptions o_;
  double diag_ = 1;
  std::vector<Vec3> vertex_normals_;
  std::vector<SurfacePoint> samples_;
};

}  // namespace hdm
