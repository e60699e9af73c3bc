// SPDX-License-Identifier: MIT
// Bake: the coarse surface (checked decimation), ray directions and shell offsets, every slab kept
// valid, one ray per sample against the input (Embree, TBB). Each stage is in its own file of this
// folder; this one runs them. Design notes §2.2, §3.7, §9-Q1..Q3.
#include <hdm/core/error.h>
#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/slab/bake.h>
#include <hdm/slab/shell_check.h>

#include "cast_columns.h"
#include "coarse_surface.h"
#include "grow_shell.h"
#include "ray_frames.h"
#include "shell_targets.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <string>

namespace hdm {
namespace {

using namespace slab::detail;

void progress(const BakeOptions& o, const char* stage, double f) {
  if (o.progress) o.progress(stage, f);
}

// Refuses options outside their ranges, naming the option.
void check_options(const BakeOptions& o) {
  if (o.grid_n < 1 || o.grid_n > 256)
    throw InvalidInput("--grid " + std::to_string(o.grid_n) + ": must be in [1, 256]");
  if (o.texel_density < 1 || o.texel_density > 16)
    throw InvalidInput("texel density " + std::to_string(o.texel_density) + ": must be in [1, 16]");
  if (o.slabs < 0) throw InvalidInput("--slabs " + std::to_string(o.slabs) + ": must be positive");
  if (!(o.density > 0 && o.density <= 1024))
    throw InvalidInput("--density " + std::to_string(o.density) + ": must be in (0, 1024]");
  if (o.sample_budget < 0 || o.min_grid < 1)
    throw InvalidInput("sample budget " + std::to_string(o.sample_budget) + " and smallest grid " +
                       std::to_string(o.min_grid) + ": must be at least 0 and 1");
}

// The grid n for @p slabs under BakeOptions::sample_budget.
int grid_for(const BakeOptions& o, size_t slabs) {
  if (o.sample_budget <= 0 || slabs == 0) return o.grid_n;
  const int n = static_cast<int>(std::floor(std::sqrt(double(o.sample_budget) / double(slabs))));
  return std::clamp(n, std::min(o.min_grid, o.grid_n), o.grid_n);
}

// A model with the coarse faces as slabs, its sample layout and every displacement at mid-shell.
SlabModel new_model(const TriangleMesh& mesh, const CoarseMesh& coarse, const std::string& name, const BakeOptions& o,
                    double diag) {
  SlabModel model;
  model.grid_n = o.grid_n;
  model.texel_density = o.texel_density;
  model.slabs = coarse.faces;
  model.source = name;
  model.source_triangles = static_cast<int64_t>(mesh.faces.size());
  model.source_diagonal = diag;
  model.samples = build_sample_layout(model.slabs, static_cast<int>(coarse.vertices.size()), o.grid_n);
  model.displacement.assign(model.samples.count, 0.5f);
  return model;
}

// Grows the shell and casts the columns in two passes: with slab separation, and, if thinning the
// shell where slabs overlap leaves more than BakeOptions::miss_limit of the rays without a surface,
// without it (overlaps are then reported by `hdm check`). Each pass runs up to 8 rounds of growth,
// separation and casting, widening the shell where rays missed; a round recasts only the columns
// whose slab moved. Sets @p missed and @p undercut per sample, and the report's separation,
// shell iterations, ray misses and overlapping pairs.
void grow_and_cast(SlabModel& model, const CoarseMesh& coarse, const ExactMeshQuery& input, Shell& shell,
                   const BakeOptions& o, std::vector<uint8_t>& missed, std::vector<uint8_t>& undercut,
                   BakeReport& rep) {
  const size_t nv = coarse.vertices.size();
  const int ns = model.samples.count;
  std::vector<uint8_t> grow_in(nv), grow_out(nv), stale(nv);
  for (int pass = 0; pass < 2; ++pass) {
    const bool separating = pass == 0 && o.separate_slabs;
    if (pass == 1 && !o.separate_slabs) break;
    shell.restart();
    rep.separated = separating;
    // Corners at the last cast: later rounds recast only the columns whose slab moved.
    std::vector<Vec3> cast_inner(nv, Vec3::Constant(NAN)), cast_outer(nv, Vec3::Constant(NAN));
    for (int round = 0; round < 8; ++round) {
      rep.shell_iterations = round + 1;
      progress(o, "grow shell", round / 8.0);
      shell.grow();
      progress(o, "separate", round / 8.0);
      if (separating) shell.separate();
      for (size_t v = 0; v < nv; ++v)
        stale[v] = !(model.inner[v] == cast_inner[v]) || !(model.outer[v] == cast_outer[v]);
      cast_inner = model.inner;
      cast_outer = model.outer;
      cast_columns(model, coarse, input, stale, missed, undercut, o);
      // Grow the shell where rays missed: outward if the outer end is inside the input, else inward.
      rep.ray_misses = flag_missed_columns(model, input, missed, grow_in, grow_out);
      if (rep.ray_misses == 0 || round == 7) break;
      if (!shell.widen(grow_in, grow_out)) break;
    }
    if (rep.ray_misses <= o.miss_limit * ns) break;
  }
  // Slab pairs that still overlap: none once separation converged; without separation (the
  // second pass) the exact check runs once here.
  const std::vector<std::pair<int32_t, int32_t>> pairs =
      rep.separated ? shell.current_pairs() : overlapping_pairs(model);
  rep.overlapping_pairs = static_cast<int64_t>(pairs.size());
  for (const auto& [s, t] : pairs) rep.overlapping_slabs.push_back(s), rep.overlapping_slabs.push_back(t);
}

// The bake; `prebuilt` is the caller's BVH over `mesh`, or null to build one here.
SlabModel bake(const TriangleMesh& mesh, const ExactMeshQuery* prebuilt, const std::string& name,
               const BakeOptions& given, BakeReport* report) {
  const auto start = std::chrono::steady_clock::now();
  check_options(given);
  // The coarse surface comes from the source: the mesh itself, or a remesh of the same surface
  // whose triangles can carry slabs where the mesh's own cannot (BakeOptions::source).
  const TriangleMesh& source = given.source ? *given.source : mesh;
  if (given.source) validate_for_bake(mesh, name);
  validate_for_bake(source, name);
  const double diag = bounds(mesh).diagonal();
  const int target =
      given.slabs > 0 ? given.slabs : default_slab_count(static_cast<int64_t>(source.faces.size()), given);

  progress(given, "decimate", 0);
  BakeReport rep;
  const CoarseMesh coarse =
      coarse_surface(source, target, given.max_edge, given.max_decimation_cost, &rep.decimation_cost);
  progress(given, "decimate", 1);
  BakeOptions o = given;  // the stages below read the grid chosen for the slabs made
  o.max_edge = {};
  o.source = nullptr;
  o.grid_n = grid_for(given, coarse.faces.size());
  const int n = o.grid_n;
  const VertexFrame fr = vertex_frames(coarse, o.direction_smoothing);
  std::unique_ptr<const ExactMeshQuery> own;
  if (!prebuilt) own = std::make_unique<const ExactMeshQuery>(mesh);
  const ExactMeshQuery& input = prebuilt ? *prebuilt : *own;
  const ExactMeshQuery coarse_query(TriangleMesh{coarse.vertices, coarse.faces});

  progress(o, "measure", 0);
  ShellTargets targets = shell_targets(mesh, input, coarse, coarse_query, fr, o, diag);
  SlabModel model = new_model(mesh, coarse, name, o, diag);
  const int ns = model.samples.count;
  std::vector<uint8_t> missed(ns, 0), undercut(ns, 0);
  Shell shell(model, coarse, fr, targets);
  grow_and_cast(model, coarse, input, shell, o, missed, undercut, rep);
  // A column that misses the input still has a best point: the one on its line nearest the input.
  progress(o, "fill misses", 0);
  fill_missed_columns(model, input, missed);
  rep.undercut_columns = std::count(undercut.begin(), undercut.end(), uint8_t(1));
  // rebuild_derived() builds the texel layout (and fills `colour` with its default); the bake's
  // colour is set afterwards, so the layout is built once.
  model.colour.assign(0, Srgb8{});
  progress(o, "derived data", 0);
  rebuild_derived(model);
  model.colour.assign(model.texels.count, encode_srgb8(o.colour));
  progress(o, "derived data", 1);

  rep.invalid_slabs = count_invalid_slabs(model);
  std::sort(rep.overlapping_slabs.begin(), rep.overlapping_slabs.end());
  rep.overlapping_slabs.erase(std::unique(rep.overlapping_slabs.begin(), rep.overlapping_slabs.end()),
                              rep.overlapping_slabs.end());
  rep.slabs = model.slab_count();
  rep.grid_n = n;
  rep.input_triangles = static_cast<int64_t>(mesh.faces.size());
  rep.submesh_triangles = int64_t(rep.slabs) * n * n;
  rep.samples = ns;
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (report) *report = rep;
  return model;
}

}  // namespace

int default_slab_count(int64_t triangles, const BakeOptions& o) {
  const double submesh = std::min(double(triangles) * o.density, double(kMaxDensitySubmesh));
  return std::max(8, static_cast<int>(std::lround(submesh / (double(o.grid_n) * o.grid_n))));
}

SlabModel bake_slabs(const TriangleMesh& mesh, const std::string& name, const BakeOptions& o, BakeReport* report) {
  return bake(mesh, nullptr, name, o, report);
}

SlabModel bake_slabs(const ExactMeshQuery& input, const std::string& name, const BakeOptions& o, BakeReport* report) {
  return bake(input.mesh(), &input, name, o, report);
}

}  // namespace hdm
