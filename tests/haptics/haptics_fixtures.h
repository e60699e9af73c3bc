// SPDX-License-Identifier: MIT
#pragma once
// Shared haptics fixtures: a baked analytic sphere with its locator and a workspace; the paper's
// bunny bake with its locator and the exact reference on the input.

#include <hdm/mesh/exact_mesh_query.h>
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

/// The boundary of a union of grid cubes of edge @p h: a closed manifold mesh whose faces are
/// the cubes' faces that no other cube covers (a cell is solid where @p solid(i, j, k) is true).
template <class Solid>
TriangleMesh voxel_surface(int nx, int ny, int nz, double h, const Vec3& origin, Solid solid) {
  TriangleMesh m;
  std::map<std::tuple<int, int, int>, int32_t> id;
  auto vertex = [&](int i, int j, int k) {
    auto [it, added] = id.emplace(std::make_tuple(i, j, k), int32_t(m.vertices.size()));
    if (added) m.vertices.push_back(origin + h * Vec3(i, j, k));
    return it->second;
  };
  auto in = [&](int i, int j, int k) {
    return i >= 0 && j >= 0 && k >= 0 && i < nx && j < ny && k < nz && solid(i, j, k);
  };
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      for (int k = 0; k < nz; ++k) {
        if (!in(i, j, k)) continue;
        for (int axis = 0; axis < 3; ++axis)
          for (int side = 0; side < 2; ++side) {
            int c[3] = {i, j, k};
            c[axis] += side ? 1 : -1;
            if (in(c[0], c[1], c[2])) continue;
            // The face's four corners, counter-clockwise seen from outside.
            int base[3] = {i, j, k};
            base[axis] += side;
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            int q[4][3];
            for (int t = 0; t < 4; ++t) {
              std::copy(base, base + 3, q[t]);
              q[t][u] += (t == 1 || t == 2);
              q[t][v] += (t >= 2);
            }
            int32_t a[4];
            for (int t = 0; t < 4; ++t) a[t] = vertex(q[t][0], q[t][1], q[t][2]);
            if (side) {
              m.faces.push_back({a[0], a[1], a[2]});
              m.faces.push_back({a[0], a[2], a[3]});
            } else {
              m.faces.push_back({a[0], a[2], a[1]});
              m.faces.push_back({a[0], a[3], a[2]});
            }
          }
      }
  return m;
}

}  // namespace hdm::test
