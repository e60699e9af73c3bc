// SPDX-License-Identifier: MIT
#pragma once
// Workloads, timers and statistics shared by `hdm bench` (apps/hdm/cmd_bench.cpp) and the Google
// Benchmark micro-benchmarks (bench_*.cpp): the same device paths, near-surface points, strokes and
// timing method everywhere, so their figures can be compared. Not an installed library
// (target hdm_bench_workloads); docs/performance.md describes the measurements.
//
// Timing method: a latency figure is a distribution over batches of kBatch consecutive queries,
// each batch timed with two steady_clock reads and divided by kBatch, so the timer's own cost
// (~20-40 ns) is spread over the batch. Median and p99 are over batches; max is the slowest batch
// mean (one slow query shows up diluted by kBatch). A measurement is repeated, and the figures
// reported are the median over repeats with the spread (min..max of the repeat medians).

#include <hdm/edit/edit_tools.h>
#include <hdm/edit/stroke_editor.h>
#include <hdm/haptics/force.h>
#include <hdm/haptics/proxy.h>
#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/query/slab_query.h>

#include <chrono>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

namespace hdm {
class CgalClosestPoint;
}

namespace hdm::bench {

constexpr int kBatch = 16;  ///< queries per timed batch
using Clock = std::chrono::steady_clock;

/// Seconds from @p t0 to now.
inline double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// Distribution of one measurement (any unit; latencies in ns per query).
struct Stats {
  double median = 0, p99 = 0, max = 0, mean = 0;
};

/// Median, p99 (element at ⌊0.99·size⌋), max and mean of @p v; all zero when @p v is empty.
Stats stats_of(std::vector<double> v);

/// Median over repeats of each statistic, plus the spread (min..max) of the repeat medians.
struct Summary {
  Stats s;
  double spread_lo = 0, spread_hi = 0;
};

/// Summary of @p runs (one Stats per repeat). @pre @p runs not empty.
Summary summarise(const std::vector<Stats>& runs);

/// Times `body(k)` for k in [0, n) in batches of @p batch consecutive calls (a tail shorter than a
/// batch is not run); returns the distribution of ns per call over the batches. A call of tens of
/// microseconds (the rigid tool's tick) is timed alone (@p batch = 1): the timer's cost is then
/// negligible, and p99 is over calls, not over batches that one preempted call inflates.
template <class Body>
Stats time_batches(size_t n, Body&& body, size_t batch = kBatch) {
  std::vector<double> per_query;
  per_query.reserve(n / batch + 1);
  for (size_t k0 = 0; k0 + batch <= n; k0 += batch) {
    const auto t0 = Clock::now();
    for (size_t k = k0; k < k0 + batch; ++k) body(k);
    const auto t1 = Clock::now();
    per_query.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / batch);
  }
  return stats_of(std::move(per_query));
}

/// Surface point of sample @p s rounded to float [model units]: the points every workload is laid
/// out from, as when the model cached them in float, so the paths and points stay the same.
inline Vec3 float_point(const SlabModel& m, int32_t s) { return sample_position(m, s).cast<float>().cast<double>(); }

/// A 1 kHz device path over the surface of @p m [model units]: a greedy walk over the sample graph
/// towards random target samples, offset along the interpolated normal by depth·sin(2π·tick/1000)
/// (a period of one second), so the point slides along and into the surface. The curve is traced
/// finely and no tick moves further than @p step. Returns exactly @p ticks points.
std::vector<Vec3> coherent_path(const SlabModel& m, int ticks, double step, double depth, std::mt19937_64& rng);

/// @p count uniformly random near-surface points [model units]: a random grid triangle of @p m, a
/// uniform point on it, offset along its normal by a uniform amount in [-dist, dist].
std::vector<Vec3> global_points(const SlabModel& m, int count, double dist, std::mt19937_64& rng);

/// Device velocity [m/s] of each point of a 1 kHz @p path [model units] under @p ws (zero at the first).
std::vector<Vec3> path_velocity(const std::vector<Vec3>& path, const Workspace& ws);

/// Orientations (tool frame → model frame) of a tool held along a @p path [model units]: its +z axis
/// follows the surface normal under the path with a lag of about 50 ticks (a hand's, not the
/// normal field's facets), so it leans off the normal where the surface turns.
std::vector<Eigen::Quaterniond> tool_orientations(const SlabModel& model, const SlabLocator& locator,
                                                  const std::vector<Vec3>& path);

/// Latency of every query kind over all repeats (one Stats per repeat, ns per query).
struct LatencyRuns {
  std::vector<Stats> coherent, global, tick, proxy_tick;  ///< hdm
  std::vector<Stats> sphere_tick;                     ///< hdm's sphere proxy (r = 1 % of the diagonal) on the same path
  std::vector<Stats> rigid_tick;                      ///< hdm's rigid tool (1,000-point burr, r = 1 %), per tick
  std::vector<Stats> embree_coherent, embree_global;  ///< Embree closest point + inside test
  std::vector<Stats> cgal_coherent, cgal_global;      ///< CGAL closest point (when given)
  int64_t in_shell_coherent = 0, in_shell_global = 0;  ///< points in a slab (last repeat)
  int64_t contacts = 0;                                ///< path ticks with a penalty force (last repeat)
  int64_t rigid_contacts = 0;                          ///< path ticks with a rigid-tool wrench (last repeat)
};

/// Times, @p repeat times and interleaved so that machine noise hits all of them: hdm's query on
/// @p path (coherent, cache kept) and on @p points (a fresh search each), Embree's closest point plus
/// inside test on both, CGAL's closest point on both (when @p cgal is not null), the servo tick with
/// the penalty force, with the proxy (proxy_step), with the sphere proxy (sphere_proxy_step, its
/// default radius of 1 % of the diagonal) and with the rigid tool (rigid_tool_step: a 1,000-point
/// burr_shell of head radius 1 % of the diagonal, its tip on the path, held as tool_orientations()) on @p path at
/// @p velocity [m/s].
LatencyRuns time_queries(const SlabModel& model, const SlabLocator& locator, const ExactMeshQuery& exact,
                         const CgalClosestPoint* cgal, const Workspace& ws, const std::vector<Vec3>& path,
                         const std::vector<Vec3>& velocity, const std::vector<Vec3>& points, int repeat);

/// Work and time of one kind of edit.
struct EditRow {
  const char* tool;     ///< brush tool name
  double radius_pct;    ///< tool radius [% of the input diagonal]
  int64_t ops = 0;      ///< edits (cold) or ticks (warm strokes)
  int64_t visited = 0;  ///< samples (texels for paint) visited
  int64_t changed = 0;  ///< samples (texels) changed
  double ns = 0;        ///< total time [ns]
};

/// The brush the edit workloads stroke with for @p tool (a registered brush) at @p radius [model
/// units]: the brush's default falloff (hdm::BrushInfo::falloff), a ridge of 0.2 radius (add),
/// strength 0.5 for smooth and flatten (half their rate) and 1 for the others, the default colour.
Brush workload_brush(BrushTool tool, double radius);

/// Warm strokes: one tool sample per 1 kHz tick, the tool sliding at 20 mm/s of device motion over
/// the surface under @p path (StrokeEditor::add_sample + work, timed together per tick), the HIP 0.2
/// radius under the surface, at most @p ticks ticks; every registered brush (workload_brush()) at
/// radii 1 and 2 % of @p diag. Each stroke is undone afterwards, which restores @p model bit for bit.
std::vector<EditRow> warm_strokes(SlabModel& model, const SlabLocator& locator, const Workspace& ws,
                                  const std::vector<Vec3>& path, double diag, int ticks);

/// Cold stamps: @p ops single carve, add and paint edits per radius (0.25, 0.5, 1, 2 % of @p diag)
/// at random samples of @p model, the HIP 0.2 radius under the surface. Edits @p model (kept).
std::vector<EditRow> cold_stamps(SlabModel& model, const SlabLocator& locator, double diag, std::mt19937_64& rng,
                                 int ops = 40);

/// Memory of a slab model by part [bytes, vector capacities] (hdm::model_memory() regrouped, plus the locator).
struct ModelBytes {
  size_t samples = 0;  ///< per-sample fields and the sample layout
  size_t texels = 0;   ///< colour, roughness and the texel layout
  size_t slabs = 0;    ///< per-slab data, adjacency and the locator
};

/// The bytes @p model and @p locator hold, by part.
ModelBytes model_bytes(const SlabModel& model, const SlabLocator& locator);

/// Peak resident set size of this process so far [MB] (getrusage).
double peak_rss_mb();

}  // namespace hdm::bench
