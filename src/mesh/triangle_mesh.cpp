// SPDX-License-Identifier: MIT
#include <hdm/core/error.h>
#include <hdm/mesh/triangle_mesh.h>
#include "../core/parallel_for.h"
#include "disjoint_sets.h"
#include "edge_buckets.h"

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <numeric>
#include <string>

namespace hdm {

Aabb bounds(const TriangleMesh& mesh) {
  Aabb box;
  for (const Vec3& v : mesh.vertices) box.extend(v);
  return box;
}

namespace {

constexpr size_t kGrain = 1 << 16;  // faces per block of the parallel area test

}  // namespace

MeshTopology analyze_topology(const TriangleMesh& mesh) {
  MeshTopology t;
  const double area_eps = 1e-14 * std::pow(std::max(bounds(mesh).diagonal(), 1e-300), 2);
  std::vector<int> degenerate(core::detail::parallel_workers(mesh.faces.size(), kGrain), 0);
  core::detail::parallel_blocks(mesh.faces.size(), kGrain, [&](size_t begin, size_t end, size_t w) {
    for (size_t i = begin; i < end; ++i) {
      const Tri& f = mesh.faces[i];
      const bool repeats = f[0] == f[1] || f[1] == f[2] || f[0] == f[2];
      degenerate[w] += repeats || (mesh.vertices[f[1]] - mesh.vertices[f[0]])
                                          .cross(mesh.vertices[f[2]] - mesh.vertices[f[0]])
                                          .norm() <= area_eps;
    }
  });
  t.degenerate_faces = std::accumulate(degenerate.begin(), degenerate.end(), 0);
  mesh::detail::EdgeBuckets edges(mesh, false);
  mesh::detail::DisjointSets<> sets(mesh.vertices.size());
  for (size_t lo = 0; lo < mesh.vertices.size(); ++lo) {
    // Group the uses of each edge (lo, hi); count uses and directions.
    edges.sort(lo);
    for (uint64_t i = edges.start[lo], end = edges.start[lo + 1]; i < end;) {
      const int32_t hi = edges.hi(edges.uses[i]);
      int uses = 0, forward = 0;
      for (; i < end && edges.hi(edges.uses[i]) == hi; ++i) ++uses, forward += edges.forward(edges.uses[i]);
      if (uses == 1)
        ++t.boundary_edges;
      else if (uses > 2)
        ++t.non_manifold_edges;
      else if (forward != 1)
        ++t.inconsistent_edges;
      sets.unite(int32_t(lo), hi);
    }
  }
  for (size_t v = 0; v < mesh.vertices.size(); ++v)
    t.components += sets.find(static_cast<int32_t>(v)) == static_cast<int32_t>(v);
  return t;
}

void validate_mesh_data(const TriangleMesh& mesh, const std::string& name) {
  if (mesh.faces.empty() || mesh.vertices.empty()) throw InvalidInput(name + ": mesh is empty (no triangles)");
  for (size_t v = 0; v < mesh.vertices.size(); ++v)
    if (!mesh.vertices[v].allFinite())
      throw InvalidInput(name + ": vertex " + std::to_string(v) + " has a non-finite coordinate");
  const auto nv = static_cast<int32_t>(mesh.vertices.size());
  for (size_t f = 0; f < mesh.faces.size(); ++f)
    for (int32_t id : mesh.faces[f])
      if (id < 0 || id >= nv)
        throw InvalidInput(name + ": face " + std::to_string(f) + " uses vertex id " + std::to_string(id) +
                           " outside [0, " + std::to_string(nv) + ")");
}

void validate_for_bake(const TriangleMesh& mesh, const std::string& name) {
  validate_mesh_data(mesh, name);
  const MeshTopology t = analyze_topology(mesh);
  if (t.non_manifold_edges > 0)
    throw InvalidInput(name + ": " + std::to_string(t.non_manifold_edges) +
                       " non-manifold edges (used by three or more triangles); repair the mesh first");
  if (t.inconsistent_edges > 0)
    throw InvalidInput(name + ": " + std::to_string(t.inconsistent_edges) +
                       " edges where neighbouring triangles have opposite orientation; orient the mesh consistently");
}

}  // namespace hdm
