// SPDX-License-Identifier: MIT
#include <hdm/analysis/bake_to_tolerance.h>
#include <hdm/core/error.h>

#include <algorithm>
#include <cmath>

namespace hdm {

SlabModel bake_to_tolerance(const ExactMeshQuery& input, const std::string& name, const BakeOptions& options,
                            const Tolerance& tolerance, std::vector<ToleranceRound>* rounds, BakeReport* report) {
  if (!(tolerance.max_pct > 0) || !(tolerance.rms_pct > 0))
    throw InvalidInput(name + ": error bounds must be positive (max " + std::to_string(tolerance.max_pct) + "%, RMS " +
                       std::to_string(tolerance.rms_pct) + "%)");
  if (tolerance.max_slabs < 1 || tolerance.max_rounds < 1)
    throw InvalidInput(name + ": the slab cap and the number of rounds must be at least 1");
  const int cap =
      static_cast<int>(std::min<int64_t>(tolerance.max_slabs, static_cast<int64_t>(input.mesh().faces.size())));
  BakeOptions o = options;
  std::vector<ToleranceRound> tried;
  double budget = 0;
  int stalls = 0;               // rounds running with as many faults as the round before
  int64_t previous_faults = 0;  // invalid slabs + overlapping pairs of the previous round  // submesh triangles
                                // (slabs·n²) the next round may use when the grid adapts
  for (int round = 0;; ++round) {
    BakeReport r;
    SlabModel model = bake_slabs(input, name, o, &r);
    ToleranceRound t;
    t.slabs = r.slabs;
    t.grid_n = r.grid_n;
    t.fidelity = measure_fidelity(model, input, tolerance.interior);
    const Fidelity& f = t.fidelity;
    const double worst_rms = std::max(f.rms_pct / tolerance.rms_pct, f.rms_back_pct / tolerance.rms_pct);
    double worst = std::max({f.max_pct / tolerance.max_pct, f.max_back_pct / tolerance.max_pct, worst_rms});
    // A shell that is invalid somewhere or overlaps itself is a coarse-geometry fault as well:
    // slabs that small enough parts get fix it (thin tubes, low-poly inputs, handles).
    t.invalid_slabs = r.invalid_slabs;
    t.overlapping_pairs = r.overlapping_pairs;
    t.ray_misses = r.ray_misses;
    if (r.invalid_slabs > 0 || r.overlapping_pairs > 0) worst = std::max(worst, 2.0);
    t.met = worst <= 1;
    tried.push_back(t);
    // The decimation may land below its target (it stops where no collapse is allowed), so the
    // next count grows from the larger of target and result.
    const int base = std::max(r.slabs, o.slabs);
    const int next = static_cast<int>(std::min<double>(cap, std::ceil(base * std::clamp(worst, 1.5, 3.0))));
    // Invalid or overlapping slabs that grew with more slabs, or stayed as many over two rounds
    // running, come from the input itself (faces that cross or fold at any resolution), not from
    // a coarse mesh too coarse for a part: further rounds only cost time (pig.stl: 285, 919,
    // 1878, ... faults over six rounds). One round with as many is not enough: a sliver of a
    // resolved union needs slabs smaller than it (mannequin-devil.off: 13, 13, then 0 faults).
    const int64_t faults = int64_t(r.invalid_slabs) + r.overlapping_pairs;
    const bool counted = round > 0 && previous_faults > 0;
    stalls = counted && faults == previous_faults ? stalls + 1 : 0;
    const bool stuck = counted && (faults > previous_faults || stalls >= 2);
    previous_faults = faults;
    if (t.met || stuck || round + 1 >= tolerance.max_rounds || base >= cap || next <= base) {
      const bool by_slab_cap = tolerance.max_slabs <= static_cast<int64_t>(input.mesh().faces.size());
      tried.back().stop = t.met                               ? ToleranceStop::Met
                          : stuck                             ? ToleranceStop::Faults
                          : round + 1 >= tolerance.max_rounds ? ToleranceStop::Rounds
                          : by_slab_cap                       ? ToleranceStop::SlabCap
                                                              : ToleranceStop::InputFaces;
      if (rounds) *rounds = std::move(tried);
      if (report) *report = r;
      return model;
    }
    o.slabs = next;
    if (tolerance.adapt_grid) {
      if (round == 0) budget = static_cast<double>(r.slabs) * o.grid_n * o.grid_n;
      // Only a round that meets the maximum error and misses the RMS misses by sampling density.
      // A round that misses the maximum misses it by coarse geometry (a part the coarse mesh cuts
      // off, undercut columns, overlapping slabs), and those spots raise its RMS as well: more
      // slabs fix them, denser samples everywhere would not.
      const bool max_met =
          std::max(f.max_pct, f.max_back_pct) <= tolerance.max_pct && r.invalid_slabs == 0 && r.overlapping_pairs == 0;
      if (worst_rms > 1 && max_met) budget *= std::min(worst_rms, 3.0);
      const int n = static_cast<int>(std::floor(std::sqrt(budget / next)));
      o.grid_n = std::clamp(n, std::min(tolerance.min_grid, options.grid_n), options.grid_n);
    }
  }
}

std::string describe_stop(const ToleranceRound& round, const Tolerance& tolerance, int64_t input_triangles) {
  switch (round.stop) {
    case ToleranceStop::NotLast:
    case ToleranceStop::Met:
      return "";
    case ToleranceStop::SlabCap:
      return "the slab cap (--max-slabs " + std::to_string(tolerance.max_slabs) + ") was reached";
    case ToleranceStop::InputFaces:
      return "the model has as many slabs as the input has triangles (" + std::to_string(input_triangles) +
             "), the most a bake makes";
    case ToleranceStop::Rounds:
      return "the " + std::to_string(tolerance.max_rounds) + " rounds a bake tries were used";
    case ToleranceStop::Faults:
      return std::to_string(round.invalid_slabs) + " invalid slabs and " + std::to_string(round.overlapping_pairs) +
             " overlapping pairs did not go with more slabs (faces of the input that cross or fold)";
  }
  return "";
}

}  // namespace hdm
