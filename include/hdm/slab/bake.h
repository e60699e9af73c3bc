// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Baking: a detailed triangle mesh becomes a slab model with displacement maps (paper §2, §7),
/// with no hand edits: decimation, per-vertex ray directions, shell offsets grown while every slab
/// stays valid, then one ray per sample against the input.

#include <hdm/mesh/triangle_mesh.h>
#include <hdm/slab/slab_model.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

namespace hdm {

class ExactMeshQuery;

/// Options of bake_slabs(). Tolerances are relative to the input's bounding-box diagonal.
struct BakeOptions {
  int slabs = 0;         ///< target slab count; 0: input triangles · density / n²
  double density = 4.0;  ///< with slabs = 0: submesh triangles (slabs·n²) per input triangle. At 1 the reconstruction
                         ///< has the input's resolution, and its interpolation error between samples (about 0.003% of
                         ///< the diagonal on bunny00) bounds the inside/outside agreement within ±1% to about 99.7%;
                         ///< at 4 it passes 99.9%
  int grid_n = 16;       ///< displacement intervals per slab edge (paper: 15, i.e. 16 samples per edge)
  int texel_density = 2;   ///< colour texels per displacement interval
  double headroom = 0.25;  ///< carve/add headroom each side, as a fraction of the mean coarse edge length at the vertex
  double max_thickness =
      1.0;  ///< largest shell thickness each side, as a fraction of the mean coarse edge length at the vertex
  double min_thickness = 0.01;  ///< wanted shell thickness each side, fraction of the diagonal (cursor penetration
                                ///< F_max/k_s plus carve headroom), capped in thin parts
  int direction_smoothing =
      10;  ///< Laplacian smoothing passes over the ray directions (each kept only while it sees all incident faces)
  bool separate_slabs = true;  ///< thin the shell where slabs of different parts overlap (falls back to no separation
                               ///< when that leaves more than miss_limit rays without a surface)
  double miss_limit =
      0.10;  ///< when separation leaves more than this fraction of sample rays without a surface, bake again without it
  Vec3f colour{0.82f, 0.80f, 0.76f};  ///< initial surface colour, linear RGB
  /// The surface decimated into slabs when it is not the mesh baked: the same surface as a
  /// closed or open, edge-manifold, consistently oriented mesh whose triangles are better shaped
  /// (remesh_isotropic() of it, where the mesh's own slivers leave slabs invalid at any slab
  /// count) [model units]. The rays are still cast on the mesh baked. Null: the mesh baked is its
  /// own source. Not owned; must outlive the bake.
  const TriangleMesh* source = nullptr;
  /// Local refinement (bake_to_tolerance()): optional #V per vertex of the coarse source (the mesh
  /// baked, or #source), the longest coarse edge allowed at it [model units]
  /// (DecimateOptions::max_edge); empty: none.
  std::vector<double> max_edge;
  /// Local refinement: the decimation stops at this quadric error as well as at the slab count
  /// (DecimateOptions::max_cost; BakeReport::decimation_cost of an earlier bake); +inf: the slab
  /// count alone.
  double max_decimation_cost = INFINITY;
  /// Submesh triangles (slabs·n²) to aim at: once the decimation has made the slabs, n becomes the
  /// largest value in [min(min_grid, grid_n), grid_n] with slabs·n² within this budget, so a
  /// decimation that stops above its target (thin parts) or a locally refined coarse mesh keeps
  /// the sample count of the density. 0: n = grid_n.
  int64_t sample_budget = 0;
  int min_grid = 4;  ///< smallest n sample_budget chooses
  /// Progress callback: stage name and fraction in [0,1] of that stage. Called from the calling thread.
  std::function<void(const char* stage, double fraction)> progress;
};

/// Counters of one bake.
struct BakeReport {
  int slabs = 0;                  ///< slabs built
  int grid_n = 0;                 ///< intervals per edge
  int64_t input_triangles = 0;    ///< triangles of the input
  int64_t submesh_triangles = 0;  ///< slabs·n², the triangles of the reconstructed surface
  int64_t samples = 0;            ///< distinct displacement samples
  int invalid_slabs = 0;          ///< slabs whose Jacobian is not positive everywhere (docs/design.md#slab-validity)
  int64_t ray_misses = 0;  ///< sample rays that found no outward-facing input surface (filled at the point of their
                           ///< line nearest the input)
  int64_t overlapping_pairs = 0;  ///< slab pairs of different parts that overlap (0 when separation converged)
  int64_t undercut_columns = 0;   ///< sample rays that cross the input more than once
  int shell_iterations = 0;       ///< rounds of shrinking/growing the shell
  bool separated = false;         ///< overlapping slabs were thinned apart (see BakeOptions::separate_slabs)
  double seconds = 0;             ///< wall time of the bake [s]
  double decimation_cost = 0;  ///< largest quadric error of a collapse the decimation made (DecimateReport::last_cost)
  /// Sorted ids of the slabs that overlap another (of a different part): where a finer coarse
  /// mesh separates the parts.
  std::vector<int32_t> overlapping_slabs;
};

/// Most submesh triangles (slabs·n²) the density rule asks for: 4,194,304, the density's 4 per
/// input triangle up to a million input triangles. A larger input (a scan of ten million
/// triangles, a subdivided model) starts there, about 180 MB of model, and the error-bounded bake
/// (bake_to_tolerance()) adds slabs where its bound asks: the model follows the shape's detail, not
/// the input's triangle count.
inline constexpr int64_t kMaxDensitySubmesh = int64_t(1) << 22;

/// @brief The slab count a bake targets when BakeOptions::slabs is 0: min(@p triangles ·
/// BakeOptions::density, kMaxDensitySubmesh) / n², at least 8, so that the submesh (slabs·n²
/// triangles) has density times the input's triangles, up to kMaxDensitySubmesh.
/// @param triangles  the input's triangle count, >= 0.
/// @param options    density in (0, 1024] and grid_n >= 1 (checked by bake_slabs(), not here).
/// @return the target slab count. @note O(1).
int default_slab_count(int64_t triangles, const BakeOptions& options);

/// @brief Bakes @p mesh into a slab model.
/// @param mesh     closed or open, edge-manifold, consistently oriented triangle mesh [model units].
/// @param name     file or argument name used in error messages.
/// @param options  see BakeOptions.
/// @param[out] report  counters of the bake (optional).
/// @return the model with derived data built; displacements δ in [0,1] with δ the parameter of
///         the outermost outward-facing hit of the sample's projection line (docs/design.md#casting-the-displacements).
/// @throws InvalidInput (naming @p name) for an invalid mesh or options. A shell that cannot
///         enclose the input everywhere at this slab count is not an error: the report counts the
///         rays that missed, the invalid slabs and the overlapping pairs, and bake_to_tolerance()
///         bakes again with more slabs.
/// @note Parallel (TBB) ray casting; O(#F log #F + #S·n²).
/// @see Jagnow & Dorsey 2002 §2 and §7; docs/design.md#bake and #slab-validity.
SlabModel bake_slabs(const TriangleMesh& mesh, const std::string& name, const BakeOptions& options,
                     BakeReport* report = nullptr);

/// @brief Bakes `input.mesh()` into a slab model, casting the sample rays on the caller's Embree
/// BVH @p input instead of building one (`hdm bake` reuses it to measure the fidelity: one BVH
/// build less, about 3 s at 1.4 M input triangles on two cores).
/// @param input    BVH over the mesh to bake; the mesh must pass validate_mesh_data() (checked
///                 before building @p input, since the BVH reads the vertex ids).
/// @param name     file or argument name used in error messages.
/// @param options  see BakeOptions.
/// @param[out] report  counters of the bake (optional).
/// Otherwise as bake_slabs(const TriangleMesh&, ...), with the same result.
SlabModel bake_slabs(const ExactMeshQuery& input, const std::string& name, const BakeOptions& options,
                     BakeReport* report = nullptr);

}  // namespace hdm
