// SPDX-License-Identifier: MIT
#pragma once
// Shared haptics fixtures: a baked analytic sphere with its locator and a workspace; the paper's
// bunny bake with its locator and the exact reference on the input.

#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/harness/voxel_surface.h>
#include <hdm/haptics/proxy.h>

#include <algorithm>
#include <map>
#include <memory>
#include <string>
#include <tuple>

namespace hdm::test {

/// Unit sphere (icosphere, 4 subdivisions, radius 1 at the origin) baked into slabs (grid 8),
/// with a workspace of 10 model units per metre (the sphere is 0.1 m in radius at the device).
struct SphereFixture {
  SlabModel model;
  std::unique_ptr<SlabLocator> locator;
  Workspace ws;
  double diag = 0;
};

/// Built once per process.
const SphereFixture& sphere();

/// Params for the sphere: k = 1000 N/m, b = 0, max 3.3 N, frictionless unless @p friction.
ProxyParams sphere_params(bool friction = false);

/// A copy of the sphere's model with static friction 0.5 and dynamic friction 0.3 at every sample.
SlabModel sphere_with_friction();

/// bunny00.off baked at the paper's configuration (150 slabs, n = 16, test::baked_bunny), its
/// locator, and exact queries on the input (the scenarios' reference).
struct BunnyFixture {
  const SlabModel& model;
  SlabLocator locator{model};
  ExactMeshQuery reference;
  double diag = 0;  ///< the input's bounding-box diagonal
};

/// Built once per process.
const BunnyFixture& paper_bunny();

/// @p mesh baked at @p slabs slabs with @p grid_n intervals per edge, its locator, and exact
/// queries on @p mesh: a scenario's three inputs.
struct BakedMesh {
  BakedMesh(const TriangleMesh& mesh, const std::string& name, int slabs, int grid_n);
  SlabModel model;
  SlabLocator locator;  // after model: built from it
  ExactMeshQuery reference;
};

/// The angle between @p a and @p b [degrees, 0 to 180]: acos of their unit vectors' clamped dot
/// product. Nonzero vectors.
double angle_deg(const Vec3& a, const Vec3& b);

/// The boundary of a union of grid cubes (hdm::voxel_surface, the harness's analytic blocks).
using ::hdm::voxel_surface;

}  // namespace hdm::test
