// SPDX-License-Identifier: MIT
#include <hdm/pipeline/bake_input.h>
#include <hdm/slab/scale_model.h>

#include <algorithm>
#include <chrono>
#include <utility>

namespace hdm {

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
  if (bake.slabs == 0 && bake.grid_n >= 1 && bake.density > 0 && bake.density <= 1024)  // else bake_slabs() refuses
    bake.slabs = default_slab_count(std::min<int64_t>(given_triangles, reference.mesh().faces.size()), bake);
  SlabModel model;
  if (options.bounded) {
    Tolerance t = options.tolerance;
    t.input_points = in.surface_points.empty() ? nullptr : &in.surface_points;
    model = bake_to_tolerance(reference, name, bake, t, &r.rounds, &r.bake);
    r.fidelity = r.rounds.back().fidelity;
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
