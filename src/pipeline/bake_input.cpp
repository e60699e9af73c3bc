// SPDX-License-Identifier: MIT
#include <hdm/mesh/remesh_isotropic.h>
#include <hdm/pipeline/bake_input.h>
#include <hdm/slab/scale_model.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

namespace hdm {
namespace {

// Whether the rounds @p a end better than @p b: meeting the bound where the other does not, else
// fewer invalid or overlapping slabs, else a smaller worst error relative to its bound.
bool better(const std::vector<ToleranceRound>& a, const std::vector<ToleranceRound>& b, const Tolerance& t) {
  if (a.empty() || b.empty()) return !a.empty();
  const ToleranceRound &x = a.back(), &y = b.back();
  if (x.met != y.met) return x.met;
  const int64_t fx = x.invalid_slabs + x.overlapping_pairs, fy = y.invalid_slabs + y.overlapping_pairs;
  if (fx != fy) return fx < fy;
  const auto worst = [&](const Fidelity& f) {
    return std::max(
        {f.max_pct / t.max_pct, f.max_back_pct / t.max_pct, f.rms_pct / t.rms_pct, f.rms_back_pct / t.rms_pct});
  };
  return worst(x.fidelity) < worst(y.fidelity);
}

// The triangles a remesh of @p mesh should have for a bake that ended at @p slabs slabs: four per
// slab, between 4,000 and 40,000 (well under the input's count for a large input; enough to carry
// the local refinement's smaller slabs), as the edge length of an equilateral tiling.
double remesh_edge_length(const TriangleMesh& mesh, int slabs) {
  double area = 0;
  for (const Tri& t : mesh.faces)
    area += 0.5 * (mesh.vertices[t[1]] - mesh.vertices[t[0]]).cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]).norm();
  const double faces = std::clamp(4.0 * slabs, 4000.0, 40000.0);
  return std::sqrt(4 * area / (std::sqrt(3.0) * faces));
}

}  // namespace

SlabModel bake_input(TriangleMesh mesh, const std::string& name, const BakeInputOptions& options,
                     BakeInputReport* report) {
  const auto start = std::chrono::steady_clock::now();
  const auto since = [](auto t) { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count(); };
  BakeInputReport local;
  BakeInputReport& r = report ? *report : local;
  r = BakeInputReport{};
  const auto progress = [&](const char* stage, double f) {
    if (options.bake.progress) options.bake.progress(stage, f);
  };
  progress("prepare", 0);
  const int64_t given_triangles = static_cast<int64_t>(mesh.faces.size());
  PrepareOptions prepare = options.prepare;
  prepare.resolve = true;
  PreparedInput in = prepare_input(std::move(mesh), name, prepare);
  r.input = in.report;
  r.diagonal = bounds(in.mesh).diagonal();
  // One BVH over the prepared mesh for the bake's rays and the fidelity measurement; the bake
  // time reported includes its build.
  progress("input BVH", 0);
  const auto bvh_start = std::chrono::steady_clock::now();
  const ExactMeshQuery reference(std::move(in.mesh));  // the prepared mesh lives on in the BVH alone
  // A mesh that crossed itself bounds the union of its parts; faces still inside it (where the
  // seams closed it and what crosses stays) are reported. The fidelity measures the points of
  // the material's surface, taken before the resolution (PreparedInput::surface_points).
  std::vector<uint8_t> interior;
  if (r.input.self_intersections > 0) interior = interior_faces(reference);
  r.interior_faces = std::count(interior.begin(), interior.end(), uint8_t(1));
  const double bvh_seconds = since(bvh_start);
  // BakeOptions::density counts the triangles the user gave, not the prepared mesh's: resolving
  // self-intersections splits faces along every intersection curve, which adds no detail to
  // sample. The smaller count is used, since repair may also drop duplicate or degenerate faces.
  BakeOptions bake = options.bake;
  if (bake.slabs == 0 && bake.grid_n >= 1 && bake.density > 0 && bake.density <= 1024) {  // else bake_slabs() refuses
    bake.slabs = default_slab_count(std::min<int64_t>(given_triangles, reference.mesh().faces.size()), bake);
    if (options.bounded && options.tolerance.max_slabs >= 1)  // the cap holds for the density's count too
      bake.slabs = std::min(bake.slabs, options.tolerance.max_slabs);
  }
  SlabModel model;
  if (options.bounded) {
    Tolerance t = options.tolerance;
    t.input_points = in.surface_points.empty() ? nullptr : &in.surface_points;
    model = bake_to_tolerance(reference, name, bake, t, &r.rounds, &r.bake);
    r.fidelity = r.rounds.back().fidelity;
    // Slabs still invalid, and none overlapping, where the rounds stopped: the input's own
    // triangles (needles of a CAD tessellation) cannot carry them; the same surface remeshed may.
    // (Overlapping slabs come from parts too close together, which a remesh does not separate.)
    const ToleranceRound& last = r.rounds.back();
    if (!last.met && last.invalid_slabs > 0 && last.overlapping_pairs == 0 && options.prepare.repair) {
      progress("remesh", 0);
      TriangleMesh remeshed;
      try {
        remeshed = remesh_isotropic(reference.mesh(), remesh_edge_length(reference.mesh(), last.slabs));
        validate_for_bake(remeshed, name);
      } catch (const std::exception&) {
        remeshed = {};  // CGAL refused the mesh or left one the bake cannot take: the bake on its own triangles stands
      }
      if (!remeshed.faces.empty()) {
        BakeOptions over = bake;
        over.source = &remeshed;
        std::vector<ToleranceRound> rounds;
        BakeReport report;
        SlabModel other = bake_to_tolerance(reference, name, over, t, &rounds, &report);
        if (better(rounds, r.rounds, t)) {
          r.remeshed_faces = static_cast<int64_t>(remeshed.faces.size());
          r.rounds.insert(r.rounds.end(), rounds.begin(), rounds.end());
          r.bake = report;
          r.fidelity = rounds.back().fidelity;
          model = std::move(other);
        }
      }
    }
  } else {
    model = bake_slabs(reference, name, bake, &r.bake);
    progress("fidelity", 0);
    r.fidelity = measure_fidelity(model, reference, in.surface_points.empty() ? nullptr : &in.surface_points);
    progress("fidelity", 1);
  }
  r.bake.seconds += bvh_seconds;
  scale_model(model, -r.input.scale_exponent);  // back to the input's units, exactly
  r.seconds = since(start);
  return model;
}

}  // namespace hdm
