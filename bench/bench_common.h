// SPDX-License-Identifier: MIT
#pragma once
// Shared fixture of the micro-benchmarks: one baked model and its query points, built once per
// process from the environment (HDM_BENCH_MODEL, HDM_BENCH_SLABS, HDM_BENCH_GRID, HDM_BENCH_HDM).

#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/query/slab_query.h>

#include <memory>
#include <string>
#include <vector>

namespace hdm::bench {

/// A baked model with the same kinds of points `hdm bench` uses [model units].
struct Fixture {
  std::string path;                      ///< input mesh file
  TriangleMesh mesh;                     ///< input mesh
  SlabModel model;                       ///< baked model (derived data built)
  std::unique_ptr<SlabLocator> locator;  ///< its search structure
  double diagonal = 0;                   ///< input bounding-box diagonal
  std::vector<Vec3> path_points;         ///< coherent_path (workloads.h), ≤ diagonal/1600 between points
  std::vector<Vec3> global_points;       ///< global_points (workloads.h), within 1% of the diagonal of the surface
};

/// The process-wide fixture (baked on first use; not thread-safe to initialise).
const Fixture& fixture();

/// The input mesh path from $HDM_BENCH_MODEL or the repository's bunny00.off.
std::string model_path();

}  // namespace hdm::bench
