// SPDX-License-Identifier: MIT
// Isotropic remeshing with CGAL; in the hdm::repair target with the other CGAL units.
#include <hdm/core/error.h>
#include <hdm/mesh/remesh_isotropic.h>

#include "surface_mesh_copy.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/detect_features.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Surface_mesh.h>

#include <string>
#include <vector>

namespace hdm {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
namespace PMP = CGAL::Polygon_mesh_processing;

constexpr double kSharpDegrees = 60;  // a dihedral turn above this is a feature the remesh keeps
constexpr unsigned kIterations = 3;

}  // namespace

TriangleMesh remesh_isotropic(const TriangleMesh& mesh, double edge_length) {
  validate_for_bake(mesh, "remesh_isotropic input");
  if (!(edge_length > 0))
    throw InvalidInput("remesh_isotropic: edge length " + std::to_string(edge_length) + " must be positive");
  Mesh sm = mesh::detail::to_surface_mesh<Mesh>(mesh);
  auto feature = sm.add_property_map<Mesh::Edge_index, bool>("e:hdm_feature", false).first;
  PMP::detect_sharp_edges(sm, kSharpDegrees, feature);
  for (Mesh::Halfedge_index h : sm.halfedges())
    if (sm.is_border(h)) feature[sm.edge(h)] = true;
  std::vector<Mesh::Edge_index> kept;
  for (Mesh::Edge_index e : sm.edges())
    if (feature[e]) kept.push_back(e);
  PMP::split_long_edges(kept, edge_length, sm, CGAL::parameters::edge_is_constrained_map(feature));
  PMP::isotropic_remeshing(
      faces(sm), edge_length, sm,
      CGAL::parameters::number_of_iterations(kIterations).edge_is_constrained_map(feature).protect_constraints(true));
  sm.collect_garbage();
  return mesh::detail::to_triangle_mesh(sm, "remesh_isotropic");
}

}  // namespace hdm
