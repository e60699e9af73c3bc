// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Error-bounded baking: the coarse resolution is chosen so that the measured fidelity meets a
/// bound, instead of being given as a slab count.

#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/analysis/fidelity.h>
#include <hdm/slab/bake.h>

#include <string>
#include <vector>

namespace hdm {

/// Fidelity bounds for bake_to_tolerance(), as % of the input's bounding-box diagonal. A bound of
/// +infinity (the default) is not checked.
struct Tolerance {
  double max_pct = INFINITY;  ///< bound on the maximum distance, both ways (Fidelity::max_pct, max_back_pct)
  double rms_pct = INFINITY;  ///< bound on the RMS distance, both ways (Fidelity::rms_pct, rms_back_pct)
  /// No model has more slabs than this: round 1 (from the density) and global rounds ask for at most
  /// this many, and a round that makes more (a local one, or one whose decimation stopped above its
  /// target) is not kept (bake_to_tolerance()). See bake_to_tolerance() for the input's triangles.
  int max_slabs = 100000;
  int max_rounds = 8;  ///< bakes tried at most
  /// Lower the grid n as the slab count grows, so that the samples (slabs·n²) do not grow with it
  /// unless the RMS bound asks for them. Off: every round keeps options.grid_n.
  bool adapt_grid = true;
  int min_grid = 4;  ///< smallest grid n adapt_grid chooses (never above options.grid_n)
  /// The sample budget's floor [submesh triangles, slabs·n²]: a low-poly input (a few thousand
  /// triangles) still gets the samples of a 20,000-triangle one at the default density, enough for
  /// a smooth force-shading field; inputs above 20,000 triangles keep their density.
  int64_t min_samples = 80000;
  /// Optional points of the input's surface that the fidelity's input-to-model direction measures
  /// (measure_fidelity()'s `input_points`, surface_points()). Not owned.
  const std::vector<Vec3>* input_points = nullptr;
};

/// Why bake_to_tolerance() stopped after a round.
enum class ToleranceStop {
  NotLast,  ///< another round followed
  Met,      ///< the round met every bound
  SlabCap,  ///< the next round would pass Tolerance::max_slabs, or this one did (the model is then an earlier round's)
  InputFaces,  ///< the next round would have more slabs than the input has triangles, and splitting them would not help
  Rounds,      ///< Tolerance::max_rounds bakes were tried
  Faults,      ///< invalid or overlapping slabs that more slabs did not reduce (the input's own crossings or folds)
  Finest,      ///< the next round would bake an earlier round's model again (no finer coarse mesh at that count)
};

/// One bake tried by bake_to_tolerance().
struct ToleranceRound {
  int slabs = 0;                  ///< slabs built
  int grid_n = 0;                 ///< grid n used
  Fidelity fidelity;              ///< measured against the input
  int invalid_slabs = 0;          ///< BakeReport::invalid_slabs of the round
  int64_t overlapping_pairs = 0;  ///< BakeReport::overlapping_pairs of the round
  int64_t ray_misses = 0;         ///< BakeReport::ray_misses of the round
  bool met = false;               ///< every bound of the Tolerance holds, and no slab is invalid or overlaps another
  bool local = false;  ///< this round refined where the round before missed (local refinement), else every slab
  /// A trial with fewer slabs after a global round met the bounds by a wide margin: the last round
  /// when it met them with a tenth to spare, else listed just before the round that met them.
  bool fewer = false;
  ToleranceStop stop = ToleranceStop::NotLast;  ///< why the bake stopped here (the last round), else NotLast
};

/// @brief A sentence for a user on why an error-bounded bake stopped at @p round without meeting
/// its bounds, naming the option that changes it ("the slab cap (--max-slabs 100000) was reached").
/// @param round the last round of bake_to_tolerance(); @param tolerance the bounds it used.
/// @param input_triangles triangles of the input. @return "" when the round met the bounds.
/// @note O(1); allocates the string.
std::string describe_stop(const ToleranceRound& round, const Tolerance& tolerance, int64_t input_triangles);

/// @brief Bakes the mesh of @p input with more and more slabs until the fidelity measured against it
/// meets @p tolerance (an error-bounded bake).
///
/// Round 1 bakes with @p options as given (options.slabs = 0: the density's count, at most
/// Tolerance::max_slabs). A round meets the tolerance when its fidelity holds
/// every bound and it has no invalid slab and no overlapping pair. While a round does not:
/// - **Local refinement** where the misses have a place: slabs that overlap another, and the slabs
///   nearest the points beyond the maximum error (measure_fidelity()'s far points). Input vertices
///   within half such a slab's longest edge get half that edge as the longest coarse edge allowed
///   (BakeOptions::max_edge), and the next decimation stops at the quadric error the last global
///   round reached (BakeOptions::max_decimation_cost): the faulty regions get smaller slabs and the
///   rest of the mesh the same ones. This goes on while it helps: each local round must reduce the
///   faults or the maximum error by a tenth. A local round that leaves more faults or a larger
///   maximum error than the round before it is undone: the global round that follows grows that
///   round (its slab count times its own ratio), not the local one. Refining one place moves the
///   decimation everywhere, and with Tolerance::adapt_grid lowers the grid of every slab; growing
///   the worse round by its larger ratio made up to three times the slabs the bound needed.
/// - **Global growth** otherwise: for invalid slabs (where the input folds, a finer coarse mesh
///   follows the fold and a coarser one spans it), for spots local refinement did not fix, and for
///   a missed RMS bound (measured without the far points: the coarse mesh too coarse everywhere).
///   The slab count is the previous one times the worst ratio of measured to wanted error (2 for
///   an invalid or overlapping shell), clamped to [1.5, 3] (on smooth parts the error falls like
///   the coarse edge length squared, so like 1/slabs); a missed RMS bound alone multiplies it by
///   1.1 times its ratio, clamped to [1.2, 3]. Capped at Tolerance::max_slabs; the caps of local
///   refinement are dropped.
/// - **A finer source** when the input runs short: a decimation makes at most the faces it starts
///   from, so when a global round asks for more slabs than the mesh decimated has triangles and
///   the round before reached its target, that mesh's faces are split in four at their edge
///   midpoints (split_faces(): the same surface; a cube of 12 triangles gets small slabs along its
///   edges). The fidelity is still measured against @p input. Not after a round with invalid or
///   overlapping slabs (faults at the input's own resolution come from its faces, which cross or
///   fold), nor when the decimation stopped above its target (thin parts keep their faces): the
///   slab count then stays at most the input's triangles.
///
/// - **Fewer slabs** after a global round that meets every bound with a quarter to spare, when the
///   round it grew missed the maximum error alone: growth linear in the error ratio overshoots
///   where the error is a few spots that slabs of some size resolve (it then falls faster than
///   1/slabs). Fitting error ∝ slabs^-p on the two rounds, one more round bakes the count aimed at
///   3/4 of the maximum bound, if that saves a sixth of the slabs; it is kept when it meets every
///   bound with a tenth to spare (ToleranceRound::fewer), else the round that met them is.
///
/// With Tolerance::adapt_grid each round's grid n is the largest n <= options.grid_n (and >=
/// min_grid) with slabs·n² within the sample budget (BakeOptions::sample_budget): round 1's target
/// slabs·n² (at least Tolerance::min_samples), times the RMS ratio (up to 3) in each round that missed the RMS bound
/// alone. Smaller slabs at a lower grid follow the input better than larger ones at a finer grid with as many samples,
/// so the budget holds the samples at the density while the slabs adapt. Every other option stays as given. Stops at
/// the first model that meets the bounds, at the cap, after Tolerance::max_rounds bakes, or when the round before had
/// invalid or overlapping slabs and this round has more of them, or as many for the second round running (faults that
/// more slabs do not reduce come from the input: faces that cross or fold at every resolution; a sliver of a resolved
/// union needs one round more), or when the next round would be a global one asking what the last global round asked
/// (the same slab count of the same source with the same sample budget): the bake is deterministic, so it would make
/// the same model, and the rounds after it would repeat those after that one (the decimation made all it can of the
/// source at that count: at the cap, at the source's own triangles, or where its edges below the resolution go
/// whatever the count; ToleranceStop::Finest without faults); the model returned is the last one baked (the finest).
/// A round that makes more slabs than Tolerance::max_slabs (a local round, whose count the caps at
/// its spots set, or one whose decimation stopped above its target) ends the rounds: the last round
/// within the cap is baked again and returned (ToleranceStop::SlabCap; rounds gets that round
/// again as the last). The bake is deterministic, so it is the same model, at the cost of one bake
/// rather than of a second model held through every round. Only when no round was within the cap
/// is a model above it returned.
///
/// The decimation that places the coarse vertices is already error-driven (edge collapses of
/// least quadric error first, decimate_mesh()), so this chooses how far it goes, measured on the
/// finished slab model rather than on the coarse mesh: the error that counts includes undercut
/// columns and sampling, which the coarse mesh's own error does not see.
///
/// @param input     BVH over the input mesh [model units]: the bake's rays and the reference of
///                  measure_fidelity(); its mesh must pass validate_mesh_data().
/// @param name      file or argument name for error messages.
/// @param options   bake options; options.slabs (or, at 0, options.density) gives round 1.
/// @param tolerance bounds and limits.
/// @param[out] rounds  every bake tried, in order (optional).
/// @param[out] report  the returned model's bake report (optional).
/// @return the model of the last round; rounds->back().met says whether it meets the bounds.
/// @throws InvalidInput naming @p name for an invalid mesh, options or tolerance (a bound that is
///         not positive, max_slabs < 1, max_rounds < 1, options.slabs > max_slabs).
/// @note Cost: up to max_rounds bakes and fidelity measurements, all on the one BVH of @p input;
///       one round when the first bake meets the bounds.
SlabModel bake_to_tolerance(const ExactMeshQuery& input, const std::string& name, const BakeOptions& options,
                            const Tolerance& tolerance, std::vector<ToleranceRound>* rounds = nullptr,
                            BakeReport* report = nullptr);

}  // namespace hdm
