// SPDX-License-Identifier: MIT
#include <hdm/core/error.h>
#include <hdm/mesh/triangle_mesh.h>
#include "disjoint_sets.h"

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

MeshTopology analyze_topology(const TriangleMesh& mesh) {
  MeshTopology t;
  const double area_eps = 1e-14 * std::pow(std::max(bounds(mesh).diagonal(), 1e-300), 2);
  // One key per directed edge: the undirected edge (lo, hi) in the high bits, the direction
  // (a < b) in the lowest, so one parallel integer sort groups the uses of each edge.
  std::vector<uint64_t> edges;
  edges.reserve(mesh.faces.size() * 3);
  mesh::detail::DisjointSets<> sets(mesh.vertices.size());
  for (const Tri& f : mesh.faces) {
    if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) {
      ++t.degenerate_faces;
      continue;
    }
    const Vec3 n = (mesh.vertices[f[1]] - mesh.vertices[f[0]]).cross(mesh.vertices[f[2]] - mesh.vertices[f[0]]);
    if (n.norm() <= area_eps) ++t.degenerate_faces;
    for (int k = 0; k < 3; ++k) {
      const int32_t a = f[k], b = f[(k + 1) % 3];
      const auto [lo, hi] = std::minmax(a, b);
      edges.push_back((((uint64_t(uint32_t(lo)) << 32) | uint32_t(hi)) << 1) | uint64_t(a < b));
      sets.unite(a, b);
    }
  }
  // Group by undirected edge; count uses and directions.
  std::sort(edges.begin(), edges.end());
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    const uint64_t key = edges[i] >> 1;
    int forward = 0;
    while (j < edges.size() && (edges[j] >> 1) == key) {
      forward += static_cast<int>(edges[j] & 1);
      ++j;
    }
    const size_t uses = j - i;
    if (uses == 1)
      ++t.boundary_edges;
    else if (uses > 2)
      ++t.non_manifold_edges;
    else if (forward != 1)
      ++t.inconsistent_edges;
    i = j;
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
