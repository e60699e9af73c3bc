// SPDX-License-Identifier: MIT
#include <hdm/analysis/bake_to_tolerance.h>
#include <hdm/core/error.h>

#include <hdm/mesh/split_faces.h>

#include "edge_caps.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>

namespace hdm {

namespace {

// What a round leaves to the next: the options it changes and the faults it counts.
struct Plan {
  BakeOptions options;
  double budget = 0;            // submesh triangles (slabs·n²) each round aims at (adapt_grid)
  bool refine = false;          // the next round refines locally
  int64_t before_faults = 0;    // faults of the round before
  double before_max = 0;        // its maximum error over the bound
  int64_t before_slabs = 0;     // its slabs
  double before_worst = 0;      // its worst_ratio()
  int stalls = 0;               // rounds running with as many faults as the round before
  int64_t previous_faults = 0;  // invalid slabs + overlapping pairs of the previous round
  // The last global round: its slabs, grid, faults and source (see stuck()).
  int64_t global_slabs = -1, global_faults = -1;
  int global_grid = 0;
  const TriangleMesh* global_source = nullptr;
  // What the last global round asked of the bake besides its source (global_source): its slab
  // count, sample budget and the source's faces (a split source is another mesh). A global round
  // asking the same makes the same model (the bake is deterministic).
  int global_request = -1;
  int64_t global_budget = -1;
  size_t global_request_faces = 0;
  // The round the next global round grows: its slabs, its maximum error over the bound and its
  // faults (fewer_slabs()); slabs -1 when the next round is a local one.
  int64_t grown_slabs = -1;
  double grown_max = 0;
  int64_t grown_faults = 0;
  double decimation_cost = -1;  // quadric error the decimation reached in the last round that set the
                                // slab count (-1: the next round sets it)
  // The mesh the rays are cast on: the input, or the input with its faces split (a low-poly input
  // whose bound asks for more slabs than it has triangles); the same surface either way.
  // Every split is kept: a round that passes the slab cap bakes an earlier round's again (WithinCap).
  const ExactMeshQuery* target = nullptr;
  std::vector<std::unique_ptr<ExactMeshQuery>> splits;
  // The mesh decimated into slabs: the target's own, or BakeOptions::source (a remesh of the same
  // surface), split in turn when it runs short.
  const TriangleMesh* source = nullptr;
  std::vector<std::unique_ptr<TriangleMesh>> split_sources;
};

// The last round whose model had at most Tolerance::max_slabs slabs, and what it asked of the bake.
// A round that passes the cap (a local one, whose count the caps of its spots set, or one whose
// decimation stopped above its target) is not kept: this one is baked again, the bake being
// deterministic, rather than holding a second model through every round.
struct WithinCap {
  BakeOptions options;
  const ExactMeshQuery* target = nullptr;
  ToleranceRound round;
};

// A decimation cannot make more faces than it starts from. The source runs short when a global
// round asks for more slabs (@p next) than it has triangles and the last round's decimation
// reached its target (@p slabs; a collapse removes two faces), or when a local round is to follow
// one whose decimation kept every face; its faces are then split in four (the same surface). A
// decimation that stopped above its target (thin parts keep their faces) is not limited by the
// source's resolution, and splitting would only multiply its slabs. Called only after a round
// without invalid or overlapping slabs: faults at the input's own resolution come from faces that
// cross or fold, which smaller slabs follow rather than remove.
bool source_runs_short(const Plan& plan, bool local, int64_t slabs, int64_t next, int64_t max_slabs) {
  const auto faces = static_cast<int64_t>(plan.source->faces.size());
  if (faces >= max_slabs) return false;
  if (local) return slabs >= faces;  // the decimation kept every face: the caps ask for finer ones
  const int64_t target = plan.options.slabs > 0 ? plan.options.slabs : default_slab_count(faces, plan.options);
  return next > faces && slabs <= target + 2;
}

// Splits the faces of the mesh decimated into slabs in four (source_runs_short()), carrying a local
// round's edge caps to the new vertices; when that mesh is the one the rays are cast on, the rays'
// mesh is split with it (the same surface either way).
void split_source(Plan& plan) {
  std::vector<double>* caps = plan.options.max_edge.empty() ? nullptr : &plan.options.max_edge;
  if (plan.source == &plan.target->mesh()) {
    plan.splits.push_back(std::make_unique<ExactMeshQuery>(split_faces(plan.target->mesh(), caps)));
    plan.target = plan.splits.back().get();
    plan.source = &plan.target->mesh();
  } else {
    plan.split_sources.push_back(std::make_unique<TriangleMesh>(split_faces(*plan.source, caps)));
    plan.source = plan.split_sources.back().get();
  }
}

// The worst ratio of a measured error to its bound (2 with invalid or overlapping slabs).
double worst_ratio(const ToleranceRound& t, const Tolerance& tolerance) {
  const Fidelity& f = t.fidelity;
  const double rms = std::max(f.rms_pct, f.rms_back_pct) / tolerance.rms_pct;
  double worst = std::max({f.max_pct / tolerance.max_pct, f.max_back_pct / tolerance.max_pct, rms});
  if (t.invalid_slabs > 0 || t.overlapping_pairs > 0) worst = std::max(worst, 2.0);
  return worst;
}

// Invalid or overlapping slabs that grew in number, or stayed as many over two rounds running,
// come from the input itself (faces that cross or fold at any resolution), not from a coarse mesh
// too coarse for a part: further rounds only cost time. One round with as many is not enough: a
// sliver of a resolved union needs slabs smaller than it. Unless a global round made as many
// slabs, on the same grid and source, with as many faults, as the last global round before it: it
// asked for a count the decimation cannot make of the source (the edges below the resolution go
// whatever the target), baked the same coarse mesh again, and the rounds after it would repeat
// the same pair (a global round, then a local one that does not help).
bool stuck(Plan& plan, int round, const ToleranceRound& t) {
  const int64_t faults = int64_t(t.invalid_slabs) + t.overlapping_pairs;
  const bool counted = round > 0 && plan.previous_faults > 0;
  plan.stalls = counted && faults == plan.previous_faults ? plan.stalls + 1 : 0;
  bool repeated = false;
  if (!t.local) {
    repeated = faults > 0 && faults == plan.global_faults && t.slabs == plan.global_slabs &&
               t.grid_n == plan.global_grid && plan.source == plan.global_source;
    plan.global_slabs = t.slabs, plan.global_faults = faults, plan.global_grid = t.grid_n;
    plan.global_source = plan.source;
  }
  const bool s = (counted && (faults > plan.previous_faults || plan.stalls >= 2)) || repeated;
  plan.previous_faults = faults;
  return s;
}

// One round's measurements against the bounds; @p local: its coarse mesh was refined locally.
ToleranceRound measure_round(const SlabModel& model, const BakeReport& r, const ExactMeshQuery& input,
                             const Tolerance& tolerance, bool local, std::vector<Vec3>& far) {
  ToleranceRound t;
  t.slabs = r.slabs;
  t.grid_n = r.grid_n;
  t.fidelity = measure_fidelity(model, input, tolerance.input_points, tolerance.max_pct, &far);
  t.invalid_slabs = r.invalid_slabs;
  t.overlapping_pairs = r.overlapping_pairs;
  t.ray_misses = r.ray_misses;
  t.local = local;
  t.met = worst_ratio(t, tolerance) <= 1;
  return t;
}

double max_ratio(const ToleranceRound& t, const Tolerance& tolerance) {
  return std::max(t.fidelity.max_pct, t.fidelity.max_back_pct) / tolerance.max_pct;
}

int64_t faults(const ToleranceRound& t) { return int64_t(t.invalid_slabs) + t.overlapping_pairs; }

// What a round that missed asks of the next one.
struct Decision {
  bool spots = false;   // misses with a place: overlapping slabs, points beyond the maximum error
  bool local = false;   // the next round refines at the spots alone
  bool stuck = false;   // faults more slabs do not reduce (stuck())
  bool finest = false;  // the next round would repeat an earlier one, without faults
  bool split = false;   // the source's faces are split in four first (source_runs_short())
  bool grows = false;   // the next round would have more slabs than the one it grows
  int cap = 0;          // most slabs the next round may have
  int next = 0;         // slabs of the next round when it is global
  double rms = 0;       // the RMS ratio to its bound, measured without the far points
  // The round a global next round grows: this one, or the one before an undone local round.
  int64_t base_slabs = 0, base_faults = 0;
  double base_max = 0;
};

Decision decide(Plan& plan, int round, const ToleranceRound& t, const BakeReport& r, bool far_points,
                const Tolerance& tolerance) {
  Decision d;
  const double worst = worst_ratio(t, tolerance), max = max_ratio(t, tolerance);
  const int64_t f = faults(t);
  // Misses with a place (overlapping slabs, points beyond the maximum error) are refined there
  // alone, as long as that helps: the round before was not a local one, or it reduced the faults
  // or the maximum error by a tenth. Not with invalid slabs: where the input folds, a finer
  // coarse mesh follows the fold, a coarser one spans it.
  d.spots = !r.overlapping_slabs.empty() || far_points;
  const bool helped = !t.local || f < plan.before_faults || max < 0.9 * plan.before_max;
  d.local = d.spots && helped && t.invalid_slabs == 0;
  // A local round that did not help (fewer faults, or a tenth off the maximum error) is undone:
  // the next round grows the round before it instead, by its own ratio. Refining one place moved
  // the decimation, and the grid the sample budget allows, everywhere else; growing the local
  // round's extra slabs as well would pay for a refinement that bought nothing.
  const bool undone = t.local && !helped;
  // An undone round does not count for stuck(): the next round is compared with the one it grows.
  d.stuck = !undone && stuck(plan, round, t);
  // Otherwise more slabs everywhere: for a missed RMS bound (the coarse mesh too coarse
  // everywhere: smaller slabs at a lower grid follow the input better than larger ones at a
  // finer grid with as many samples), or for spots that refining alone did not fix.
  d.rms = std::max(t.fidelity.rms_within_pct, t.fidelity.rms_back_within_pct) / tolerance.rms_pct;
  // A missed RMS bound alone grows the slabs by its ratio: the RMS falls about as fast.
  const double growth = d.spots || f > 0 ? std::clamp(worst, 1.5, 3.0) : std::clamp(1.1 * d.rms, 1.2, 3.0);
  // Past the source's triangles only where it runs short, and then on its faces split.
  d.base_slabs = undone ? plan.before_slabs : r.slabs;
  d.base_max = undone ? plan.before_max : max;
  d.base_faults = undone ? plan.before_faults : f;
  const double base = double(d.base_slabs);
  const double wanted = std::min<double>(
      tolerance.max_slabs, std::ceil(undone ? base * std::clamp(plan.before_worst, 1.5, 3.0) : base * growth));
  d.split = f == 0 && source_runs_short(plan, d.local, r.slabs, wanted, tolerance.max_slabs);
  const auto source_faces = static_cast<int64_t>(plan.source->faces.size());
  d.cap = static_cast<int>(d.split ? tolerance.max_slabs : std::min<int64_t>(tolerance.max_slabs, source_faces));
  d.next = static_cast<int>(std::min<double>(d.cap, wanted));
  d.grows = d.local ? r.slabs < d.cap : r.slabs < d.cap && d.next > base;
  // A global round that asks what the last global round asked (the same slab count of the same
  // source with the same sample budget) bakes the same model again, the bake being deterministic,
  // and the rounds after it would repeat those after that one: the decimation made all it can of
  // the source at that count (at the cap, at the source's own triangles, or where its edges below
  // the resolution go whatever the count), or a local round between them was undone. Stop instead.
  // (stuck() above has recorded this round's source as global_source if the round was global.)
  const bool budget_moves = tolerance.adapt_grid && !d.spots && d.rms > 1;
  if (!d.local && !d.split && !budget_moves && d.next == plan.global_request &&
      plan.options.sample_budget == plan.global_budget && plan.source == plan.global_source &&
      plan.source->faces.size() == plan.global_request_faces) {
    d.grows = false;
    d.stuck = d.stuck || f > 0;
    d.finest = f == 0 && d.next < tolerance.max_slabs;
  }
  return d;
}

// Why the rounds stop at @p t, or NotLast.
ToleranceStop stop_reason(const ToleranceRound& t, const Decision& d, int round, const Tolerance& tolerance) {
  if (t.met) return ToleranceStop::Met;
  if (d.stuck) return ToleranceStop::Faults;
  if (d.finest) return ToleranceStop::Finest;
  if (round + 1 >= tolerance.max_rounds) return ToleranceStop::Rounds;
  if (!d.grows) return d.cap == tolerance.max_slabs ? ToleranceStop::SlabCap : ToleranceStop::InputFaces;
  return ToleranceStop::NotLast;
}

// Sets the options of the round after @p t: caps at its spots (local), or a larger slab count
// everywhere (global).
void plan_next_round(Plan& plan, const SlabModel& model, const BakeReport& r, const ToleranceRound& t,
                     const Decision& d, const std::vector<Vec3>& far, const Tolerance& tolerance) {
  plan.refine = d.local;
  plan.before_faults = faults(t);
  plan.before_max = max_ratio(t, tolerance);
  plan.before_slabs = r.slabs;
  plan.before_worst = worst_ratio(t, tolerance);
  if (d.split) split_source(plan);
  if (d.local) {
    analysis::detail::tighten_edge_caps(model, *plan.source, r.overlapping_slabs, far, plan.options.max_edge);
    // The next decimation stops at the quadric error the last global round reached, so the
    // rest of the mesh decimates as far as before, and keeps the faulty regions at half size.
    // A thousandth above it: collapses of equal cost (a symmetric part) all go, whatever their
    // last bits, so the bake stays the same at any scale of the input.
    plan.options.max_decimation_cost = plan.decimation_cost * (1 + 1e-3);
    plan.options.slabs = 1;
    plan.grown_slabs = -1;
    return;
  }
  plan.grown_slabs = d.base_slabs, plan.grown_max = d.base_max, plan.grown_faults = d.base_faults;
  // A global round starts afresh: its slabs are smaller everywhere, and caps kept where the
  // input folds would pin the coarse mesh to the fold (invalid slabs at any slab count).
  plan.options.slabs = d.next;
  plan.options.max_edge.clear();
  plan.options.max_decimation_cost = INFINITY;
  plan.decimation_cost = -1;  // the next round's decimation sets the level local refinement keeps
  // Only a round that met the maximum and had no faults misses by sampling density as well.
  if (!d.spots && d.rms > 1) plan.budget *= std::min(d.rms, 3.0);
  if (tolerance.adapt_grid) plan.options.sample_budget = static_cast<int64_t>(std::ceil(plan.budget));
}

// The slab count to try after a global round @p t that met the bounds, or 0 for none. The round it
// grew missed the maximum error alone, by a ratio the growth (linear in the ratio) may overshoot:
// where the error is that of a few spots the slabs resolve at some size, it falls faster than
// 1/slabs (man.off: 3.0 to 0.46 of the bound for 3 times the slabs). Fitting error ∝ slabs^-p on
// the two rounds, the count whose maximum is kTrialAim of the bound; tried when it saves at least
// a sixth of the slabs and both of the round's errors are below kTrialAim of their bounds.
constexpr double kTrialAim = 0.75, kTrialAccept = 0.9, kTrialSaving = 1.2;
int fewer_slabs(const Plan& plan, const ToleranceRound& t, const Tolerance& tolerance) {
  if (t.local || plan.grown_slabs <= 0 || plan.grown_faults > 0 || !(plan.grown_max > 1)) return 0;
  const double w = max_ratio(t, tolerance);
  if (!(w > 0) || !(worst_ratio(t, tolerance) < kTrialAim) || t.slabs <= plan.grown_slabs) return 0;
  const double p = std::log(plan.grown_max / w) / std::log(double(t.slabs) / double(plan.grown_slabs));
  if (!(p > 0)) return 0;
  const double s = std::ceil(t.slabs * std::pow(w / kTrialAim, 1 / p));
  return s * kTrialSaving <= t.slabs && s > plan.grown_slabs ? static_cast<int>(s) : 0;
}

// Bakes @p w's round again as the last one (a later round passed the slab cap), stopping at the cap.
SlabModel bake_within_cap(const WithinCap& w, const std::string& name, int64_t faces,
                          std::vector<ToleranceRound>& tried, BakeReport& r) {
  SlabModel model = bake_slabs(*w.target, name, w.options, &r);
  model.source_triangles = faces;
  tried.push_back(w.round);
  tried.back().stop = ToleranceStop::SlabCap;
  return model;
}

// Bakes the trial of fewer_slabs(): @p fewer slabs, the met round's other options. Kept (in @p model,
// @p r and as the last of @p tried) when it meets the bounds with kTrialAccept of them to spare;
// else listed before the met round, which stays the last, and false.
bool try_fewer_slabs(Plan& plan, int fewer, const ExactMeshQuery& input, const std::string& name, int64_t faces,
                     const Tolerance& tolerance, std::vector<ToleranceRound>& tried, SlabModel& model, BakeReport& r,
                     std::vector<Vec3>& far) {
  BakeOptions o = plan.options;
  o.slabs = fewer;
  BakeReport tr;
  SlabModel trial = bake_slabs(*plan.target, name, o, &tr);
  trial.source_triangles = faces;
  ToleranceRound t = measure_round(trial, tr, input, tolerance, false, far);
  t.fewer = true;
  if (t.met && worst_ratio(t, tolerance) <= kTrialAccept && t.slabs < tried.back().slabs) {
    tried.back().stop = ToleranceStop::NotLast;
    t.stop = ToleranceStop::Met;
    tried.push_back(t);
    model = std::move(trial);
    r = tr;
    return true;
  }
  tried.insert(tried.end() - 1, t);
  return false;
}

}  // namespace

SlabModel bake_to_tolerance(const ExactMeshQuery& input, const std::string& name, const BakeOptions& options,
                            const Tolerance& tolerance, std::vector<ToleranceRound>* rounds, BakeReport* report) {
  if (!(tolerance.max_pct > 0) || !(tolerance.rms_pct > 0))
    throw InvalidInput(name + ": error bounds must be positive (max " + std::to_string(tolerance.max_pct) + "%, RMS " +
                       std::to_string(tolerance.rms_pct) + "%)");
  if (tolerance.max_slabs < 1 || tolerance.max_rounds < 1)
    throw InvalidInput(name + ": the slab cap and the number of rounds must be at least 1");
  if (options.slabs > tolerance.max_slabs)
    throw InvalidInput(name + ": the first round's " + std::to_string(options.slabs) +
                       " slabs (--slabs) pass the cap of " + std::to_string(tolerance.max_slabs) + " (--max-slabs)");
  const int64_t faces = static_cast<int64_t>(input.mesh().faces.size());
  Plan plan;
  plan.options = options;
  plan.target = &input;
  plan.source = options.source ? options.source : &input.mesh();
  // The density's count for the first round is capped as every later round's is.
  if (options.slabs <= 0 && default_slab_count(faces, options) > tolerance.max_slabs)
    plan.options.slabs = tolerance.max_slabs;
  if (tolerance.adapt_grid) {
    // The samples of the first round's target: each round's grid follows its slab count.
    const int target = plan.options.slabs > 0 ? plan.options.slabs : default_slab_count(faces, options);
    plan.budget = std::max(double(target) * options.grid_n * options.grid_n, double(tolerance.min_samples));
    plan.options.sample_budget = static_cast<int64_t>(plan.budget);
    plan.options.min_grid = tolerance.min_grid;
  }
  std::vector<ToleranceRound> tried;
  std::vector<Vec3> far;
  std::optional<WithinCap> within;
  for (int round = 0;; ++round) {
    BakeReport r;
    plan.options.source = plan.source == &plan.target->mesh() ? nullptr : plan.source;
    SlabModel model = bake_slabs(*plan.target, name, plan.options, &r);
    model.source_triangles = faces;
    if (!plan.refine) {
      plan.global_request = plan.options.slabs;
      plan.global_budget = plan.options.sample_budget;
      plan.global_request_faces = plan.source->faces.size();
    }
    if (plan.decimation_cost < 0) plan.decimation_cost = r.decimation_cost;
    tried.push_back(measure_round(model, r, input, tolerance, plan.refine, far));
    if (r.slabs > tolerance.max_slabs && within) {
      model = bake_within_cap(*within, name, faces, tried, r);
      if (rounds) *rounds = std::move(tried);
      if (report) *report = r;
      return model;
    }
    if (r.slabs <= tolerance.max_slabs) within = WithinCap{plan.options, plan.target, tried.back()};
    const Decision d = decide(plan, round, tried.back(), r, !far.empty(), tolerance);
    tried.back().stop = stop_reason(tried.back(), d, round, tolerance);
    const int fewer = tried.back().stop == ToleranceStop::Met && round + 1 < tolerance.max_rounds
                          ? fewer_slabs(plan, tried.back(), tolerance)
                          : 0;
    if (fewer > 0 && try_fewer_slabs(plan, fewer, input, name, faces, tolerance, tried, model, r, far)) {
      if (rounds) *rounds = std::move(tried);
      if (report) *report = r;
      return model;
    }
    if (tried.back().stop != ToleranceStop::NotLast) {
      if (rounds) *rounds = std::move(tried);
      if (report) *report = r;
      return model;
    }
    plan_next_round(plan, model, r, tried.back(), d, far, tolerance);
  }
}

std::string describe_stop(const ToleranceRound& round, const Tolerance& tolerance, int64_t input_triangles) {
  switch (round.stop) {
    case ToleranceStop::NotLast:
    case ToleranceStop::Met:
      return "";
    case ToleranceStop::SlabCap:
      if (round.slabs > tolerance.max_slabs)
        return "the decimation keeps more faces than the slab cap (--max-slabs " + std::to_string(tolerance.max_slabs) +
               ") allows: thin parts keep their triangles";
      return "the slab cap (--max-slabs " + std::to_string(tolerance.max_slabs) + ") was reached";
    case ToleranceStop::InputFaces:
      return "the model has as many slabs as the input has triangles (" + std::to_string(input_triangles) +
             "), the most a bake makes where slabs are invalid or overlap or the decimation keeps the input's faces";
    case ToleranceStop::Rounds:
      return "the " + std::to_string(tolerance.max_rounds) + " rounds a bake tries were used";
    case ToleranceStop::Finest:
      return "the next round would bake the model of an earlier one again (" + std::to_string(round.slabs) +
             " slabs): the decimation makes no finer coarse mesh of the input at the count the bound asks for";
    case ToleranceStop::Faults:
      return std::to_string(round.invalid_slabs) + " invalid slabs and " + std::to_string(round.overlapping_pairs) +
             " overlapping pairs did not go with more slabs (faces of the input that cross or fold)";
  }
  return "";
}

}  // namespace hdm
