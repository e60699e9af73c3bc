// SPDX-License-Identifier: MIT
// The bake's columns: one ray per sample against the input (docs/design.md#casting-the-displacements).
#include "cast_columns.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace hdm::slab::detail {

// One ray per distinct sample, from the outer end inward; of the hits whose triangle faces
// outward, keep the one nearest the coarse surface, not the outermost: in a thick shell
// between close parts, fingers or the walls of a hole, the outermost hit can be another
// part's surface, while the coarse surface follows the local one.
void cast_columns(SlabModel& model, const CoarseMesh& coarse, const ExactMeshQuery& input,
                  const std::vector<uint8_t>& stale, std::vector<uint8_t>& missed, std::vector<uint8_t>& undercut,
                  const BakeOptions& o) {
  const int ns = model.samples.count, n = model.grid_n;
  const int blocks = 20;
  for (int b = 0; b < blocks; ++b) {
    const int lo = int(int64_t(ns) * b / blocks), hi = int(int64_t(ns) * (b + 1) / blocks);
    tbb::parallel_for(tbb::blocked_range<int>(lo, hi, 512), [&](const tbb::blocked_range<int>& r) {
      std::vector<SegmentHit> hits;
      for (int s = r.begin(); s < r.end(); ++s) {
        const Tri& home = model.slabs[model.samples.home(s).slab];
        if (!stale[home[0]] && !stale[home[1]] && !stale[home[2]]) continue;
        Vec3 p0, p1;
        projection_line(model, model.samples.home(s).slab, model.samples.home(s).index, p0, p1);
        input.segment_hits(p1, p0, hits);
        const Vec3 up = p1 - p0;
        missed[s] = 1;
        undercut[s] = hits.size() > 1;
        const int index = model.samples.home(s).index;
        const double wT = model.samples.point_i[index] / double(n), wS = model.samples.point_j[index] / double(n);
        const Vec3 coarse_point =
            (1 - wT - wS) * coarse.vertices[home[0]] + wS * coarse.vertices[home[1]] + wT * coarse.vertices[home[2]];
        const double t_coarse = (coarse_point - p0).dot(up) / std::max(up.squaredNorm(), 1e-300);
        double best = INFINITY;
        for (const SegmentHit& h : hits)
          if (input.face_normal(h.face).dot(up) > 0 && std::abs(1.0 - h.t - t_coarse) < best) {
            best = std::abs(1.0 - h.t - t_coarse);
            model.displacement[s] = static_cast<float>(std::clamp(1.0 - h.t, 0.0, 1.0));
            missed[s] = 0;
          }
      }
    });
    if (o.progress) o.progress("cast rays", double(b + 1) / blocks);
  }
}

int64_t flag_missed_columns(const SlabModel& model, const ExactMeshQuery& input, const std::vector<uint8_t>& missed,
                            std::vector<uint8_t>& grow_in, std::vector<uint8_t>& grow_out) {
  const int ns = model.samples.count;
  std::fill(grow_in.begin(), grow_in.end(), 0);
  std::fill(grow_out.begin(), grow_out.end(), 0);
  // The inside tests run in parallel; the flags are gathered after.
  std::vector<uint8_t> outer_inside(ns, 0);
  tbb::parallel_for(tbb::blocked_range<int>(0, ns, 512), [&](const tbb::blocked_range<int>& r) {
    for (int s = r.begin(); s < r.end(); ++s) {
      if (!missed[s]) continue;
      Vec3 p0, p1;
      projection_line(model, model.samples.home(s).slab, model.samples.home(s).index, p0, p1);
      outer_inside[s] = input.inside(p1);
    }
  });
  int64_t misses = 0;
  for (int s = 0; s < ns; ++s) {
    if (!missed[s]) continue;
    ++misses;
    for (int32_t v : model.slabs[model.samples.home(s).slab]) (outer_inside[s] ? grow_out : grow_in)[v] = 1;
  }
  return misses;
}

void fill_missed_columns(SlabModel& model, const ExactMeshQuery& input, const std::vector<uint8_t>& missed) {
  tbb::parallel_for(0, model.samples.count, [&](int s) {
    if (!missed[s]) return;
    Vec3 p0, p1;
    projection_line(model, model.samples.home(s).slab, model.samples.home(s).index, p0, p1);
    auto dist = [&](double t) { return input.closest_point(p0 + t * (p1 - p0)).distance; };
    double best_t = 0, best = dist(0);
    for (int k = 1; k <= 16; ++k)
      if (const double d = dist(k / 16.0); d < best) best = d, best_t = k / 16.0;
    double lo = std::max(0.0, best_t - 1 / 16.0), hi = std::min(1.0, best_t + 1 / 16.0);
    const double g = (std::sqrt(5.0) - 1) / 2;
    for (int it = 0; it < 20; ++it) {  // each distance once (two closest-point queries per step)
      const double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
      const bool left = dist(x1) < dist(x2);
      (left ? hi : lo) = left ? x2 : x1;
    }
    model.displacement[s] = static_cast<float>(std::clamp(0.5 * (lo + hi), 0.0, 1.0));
  });
}

}  // namespace hdm::slab::detail
