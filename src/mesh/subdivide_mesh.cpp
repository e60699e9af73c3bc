// SPDX-License-Identifier: MIT
// √3 subdivision with CGAL; lives in the hdm::repair target, the only one that includes CGAL.
#include <hdm/core/error.h>
#include <hdm/mesh/subdivide_mesh.h>

#include "surface_mesh_copy.h"

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Subdivision_method_3/subdivision_methods_3.h>
#include <CGAL/Surface_mesh.h>

#include <string>
#include <vector>

namespace hdm {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;

// Steps that take a closed mesh of `faces` faces to at least `wanted` (each step triples them).
int steps_for(int64_t faces, int64_t wanted) {
  int s = 0;
  for (int64_t f = faces; f < wanted; f *= 3) ++s;
  return s;
}

}  // namespace

TriangleMesh subdivide_mesh(const TriangleMesh& mesh, int64_t min_triangles, int* steps) {
  validate_mesh_data(mesh, "subdivide_mesh input");
  if (min_triangles < 0 || min_triangles > (int64_t(1) << 30))
    throw InvalidInput("--min-triangles " + std::to_string(min_triangles) + ": must be in [0, 2^30]");
  const MeshTopology topo = analyze_topology(mesh);
  if (topo.non_manifold_edges || topo.inconsistent_edges || topo.degenerate_faces)
    throw InvalidInput("subdivide_mesh input: " + std::to_string(topo.non_manifold_edges) + " non-manifold edges, " +
                       std::to_string(topo.inconsistent_edges) + " inconsistently oriented edges, " +
                       std::to_string(topo.degenerate_faces) + " degenerate faces (repair the mesh first)");
  if (steps) *steps = 0;
  if (static_cast<int64_t>(mesh.faces.size()) >= min_triangles) return mesh;

  Mesh sm;
  sm.reserve(static_cast<Mesh::size_type>(mesh.vertices.size()), static_cast<Mesh::size_type>(3 * mesh.faces.size()),
             static_cast<Mesh::size_type>(mesh.faces.size()));
  std::vector<Mesh::Vertex_index> vid;
  vid.reserve(mesh.vertices.size());
  for (const Vec3& p : mesh.vertices) vid.push_back(sm.add_vertex(Point(p.x(), p.y(), p.z())));
  for (size_t f = 0; f < mesh.faces.size(); ++f) {
    const Tri& t = mesh.faces[f];
    if (sm.add_face(vid[t[0]], vid[t[1]], vid[t[2]]) == Mesh::null_face())
      throw InvalidInput("subdivide_mesh input: face " + std::to_string(f) +
                         " makes a non-manifold vertex (repair the mesh first)");
  }

  int made = 0;
  while (static_cast<int64_t>(sm.number_of_faces()) < min_triangles && made < 20) {
    const int s = steps_for(static_cast<int64_t>(sm.number_of_faces()), min_triangles);
    CGAL::Subdivision_method_3::Sqrt3_subdivision(sm, CGAL::parameters::number_of_iterations(s));
    made += s;
  }
  if (steps) *steps = made;
  if (sm.has_garbage()) sm.collect_garbage();

  return mesh::detail::to_triangle_mesh(sm, "subdivide_mesh");
}

}  // namespace hdm
