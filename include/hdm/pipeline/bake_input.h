// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// The one bake every front end runs (`hdm bake`, the studio, the Python module): a mesh as read
/// becomes a slab model baked to tolerance, with one report. The same mesh and options give the
/// same model, byte for byte, whichever front end asks.

#include <hdm/analysis/bake_to_tolerance.h>
#include <hdm/analysis/fidelity.h>
#include <hdm/pipeline/prepare_input.h>
#include <hdm/slab/bake.h>
#include <hdm/slab/slab_model.h>

#include <string>
#include <vector>

namespace hdm {

/// Options of bake_input().
struct BakeInputOptions {
  BakeOptions bake;        ///< slab count or density, grid, texels, progress callback
  PrepareOptions prepare;  ///< repair and hole filling (PrepareOptions::resolve is always on for a bake)
  /// The error bound [% of the diagonal, both ways], by default hdm's fidelity bound: 0.2 % max and
  /// 0.02 % RMS. Tolerance::interior is set by bake_input() and ignored here.
  Tolerance tolerance{0.2, 0.02};
  /// true: bake_to_tolerance() starting from bake's slab count; false: one bake_slabs() at that
  /// count, measured with measure_fidelity().
  bool bounded = true;
};

/// What bake_input() found, did and measured.
struct BakeInputReport {
  PrepareReport input;                 ///< what prepare_input() did to the mesh
  double diagonal = 0;                 ///< bounding-box diagonal of the prepared mesh [scaled units, in [1, 2)]
  BakeReport bake;                     ///< the bake of the model returned; seconds include the input BVH
  std::vector<ToleranceRound> rounds;  ///< every bake tried (empty when not bounded)
  Fidelity fidelity;                   ///< the model returned against the prepared input, interior faces left out
  int64_t interior_faces = 0;          ///< faces of the prepared input inside the solid it bounds (interior_faces())
  /// Triangles of the remesh decimated instead of the input (remesh_isotropic(): slabs stayed
  /// invalid on the input's own triangles, and the remesh's rounds, appended to `rounds`, ended
  /// better); 0 when the input's own triangles were decimated.
  int64_t remeshed_faces = 0;
  double seconds = 0;  ///< wall time of the whole call [s]
};

/// @brief Bakes a mesh as read into a slab model: prepare_input() (scale, repair, orientation,
/// seams, folds, crossings resolved), one Embree BVH over the prepared mesh, the faces inside
/// the solid it bounds when it crossed itself (left out of the fidelity), then bake_to_tolerance()
/// (or one bake_slabs() and measure_fidelity() when not bounded), and the model scaled back to the
/// input's units (exact: a power of two). When bounded and slabs are still invalid where the
/// rounds stop (the input's own triangles are needles no slab over them can follow, as in CAD
/// fans), the rounds run again on an isotropic remesh of the prepared mesh (remesh_isotropic(),
/// about four triangles per slab reached; the rays still on the prepared mesh), and that model is
/// returned when it ends better (it meets the bound, or has fewer faults, or a smaller worst
/// error). With BakeOptions::slabs = 0, the first slab count follows
/// BakeOptions::density per triangle of @p mesh as given (or of the prepared mesh, if fewer):
/// resolving self-intersections splits faces along the intersection curves, which adds no detail.
/// @param mesh     triangles as read [model units].
/// @param name     file or argument name for error messages and SlabModel::source.
/// @param options  see BakeInputOptions.
/// @param[out] report  see BakeInputReport (optional).
/// @return the model in the input's units; when bounded and the bound was not met, the finest
///         model tried (report->rounds.back().met is false; describe_stop() says why).
/// @throws InvalidInput naming @p name for what prepare_input(), bake_slabs() or
///         bake_to_tolerance() refuse (invalid mesh data, a mesh that cannot be repaired, invalid
///         options or bounds).
/// @note Cost: prepare_input(), the BVH build (O(#F log #F)), then up to Tolerance::max_rounds
///       bakes and fidelity measurements on it (twice, with the remesh, where slabs stay invalid). Parallel (TBB).
///       Reports progress through options.bake.progress.
SlabModel bake_input(TriangleMesh mesh, const std::string& name, const BakeInputOptions& options = {},
                     BakeInputReport* report = nullptr);

}  // namespace hdm
