// SPDX-License-Identifier: MIT
// Self-intersection count and the alpha-wrapped envelope, with CGAL; one of the few translation
// units that include CGAL (heavy templates).
#include <hdm/core/error.h>
#include <hdm/mesh/outer_envelope.h>

#include "surface_mesh_copy.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/alpha_wrap_3.h>

#include <array>
#include <string>
#include <vector>

namespace hdm {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;

// A halfedge mesh of the same triangles; vertices shared by several fans (pinches) are
// duplicated, which leaves the faces, and so their intersections, unchanged.
Mesh to_surface_mesh(const TriangleMesh& mesh) {
  std::vector<Point> points;
  points.reserve(mesh.vertices.size());
  for (const Vec3& p : mesh.vertices) points.emplace_back(p.x(), p.y(), p.z());
  std::vector<std::vector<std::size_t>> polygons;
  polygons.reserve(mesh.faces.size());
  for (const Tri& t : mesh.faces) polygons.push_back({size_t(t[0]), size_t(t[1]), size_t(t[2])});
  PMP::orient_polygon_soup(points, polygons);
  Mesh sm;
  PMP::polygon_soup_to_polygon_mesh(points, polygons, sm);
  return sm;
}

}  // namespace

int64_t count_self_intersections(const TriangleMesh& mesh) {
  validate_mesh_data(mesh, "count_self_intersections input");
  const Mesh sm = to_surface_mesh(mesh);
  std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> pairs;
  PMP::self_intersections<CGAL::Parallel_if_available_tag>(sm, std::back_inserter(pairs));
  return static_cast<int64_t>(pairs.size());
}

TriangleMesh outer_envelope(const TriangleMesh& mesh, const EnvelopeOptions& options) {
  validate_mesh_data(mesh, "outer_envelope input");
  if (!(options.alpha > 0) || !(options.offset > 0))
    throw InvalidInput("outer_envelope: alpha and offset must be positive fractions of the diagonal");
  const double diag = bounds(mesh).diagonal();
  std::vector<Point> points;
  points.reserve(mesh.vertices.size());
  for (const Vec3& p : mesh.vertices) points.emplace_back(p.x(), p.y(), p.z());
  std::vector<std::array<std::size_t, 3>> faces;
  faces.reserve(mesh.faces.size());
  for (const Tri& t : mesh.faces) faces.push_back({size_t(t[0]), size_t(t[1]), size_t(t[2])});
  Mesh wrap;
  try {
    CGAL::alpha_wrap_3(points, faces, options.alpha * diag, options.offset * diag, wrap);
  } catch (const std::exception& e) {
    throw NumericalError(std::string("outer_envelope: alpha wrapping failed: ") + e.what());
  }
  if (wrap.number_of_faces() == 0) throw NumericalError("outer_envelope: alpha wrapping gave an empty surface");

  std::vector<Kernel::Triangle_3> triangles;
  triangles.reserve(mesh.faces.size());
  for (const Tri& t : mesh.faces) triangles.emplace_back(points[t[0]], points[t[1]], points[t[2]]);
  using Primitive = CGAL::AABB_triangle_primitive<Kernel, std::vector<Kernel::Triangle_3>::const_iterator>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
  Tree tree(triangles.begin(), triangles.end());
  tree.accelerate_distance_queries();

  // Where the wrap bridges a gap narrower than alpha, its faces float above the mesh: remesh
  // them finer (isotropic remeshing, Botsch & Kobbelt 2004, on those faces and a ring around),
  // so that snapping below can take the envelope down into the gap.
  {
    std::vector<Mesh::Face_index> floating;
    const double far = 4 * options.offset * diag;
    for (Mesh::Face_index f : wrap.faces()) {
      std::array<Point, 3> c;
      int k = 0;
      for (Mesh::Vertex_index v : CGAL::vertices_around_face(wrap.halfedge(f), wrap)) c[k++] = wrap.point(v);
      if (CGAL::squared_distance(tree.closest_point(CGAL::centroid(c[0], c[1], c[2])), CGAL::centroid(c[0], c[1], c[2])) > far * far)
        floating.push_back(f);
    }
    if (!floating.empty())
      PMP::isotropic_remeshing(floating, options.alpha * diag / 4, wrap, CGAL::parameters::number_of_iterations(2));
    wrap.collect_garbage();
  }

  // Snap the wrap onto the mesh: each vertex to its closest point, so the envelope follows the
  // surface instead of floating `offset` above it (and dips into the gaps it bridged). Where a
  // snap makes the envelope cross itself, the vertices of the crossing faces go back, until none
  // crosses.
  std::vector<Point> wrapped;
  for (Mesh::Vertex_index v : wrap.vertices()) wrapped.push_back(wrap.point(v));
  for (Mesh::Vertex_index v : wrap.vertices()) wrap.point(v) = tree.closest_point(wrap.point(v));
  for (int round = 0; round < 8; ++round) {
    std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> crossing;
    PMP::self_intersections<CGAL::Parallel_if_available_tag>(wrap, std::back_inserter(crossing));
    if (crossing.empty()) break;
    for (const auto& [f, g] : crossing)
      for (Mesh::Face_index h : {f, g})
        for (Mesh::Vertex_index v : CGAL::vertices_around_face(wrap.halfedge(h), wrap)) wrap.point(v) = wrapped[v.idx()];
  }
  if (analyze_topology(mesh).boundary_edges == 0) return detail::to_triangle_mesh(wrap, "outer_envelope");

  // An open mesh: keep the faces of the wrap on the front of the input face nearest to them.
  auto normal = [](const Point& a, const Point& b, const Point& c) {
    return Vec3(Vec3(b.x() - a.x(), b.y() - a.y(), b.z() - a.z()).cross(Vec3(c.x() - a.x(), c.y() - a.y(), c.z() - a.z())));
  };
  std::vector<Mesh::Face_index> drop;
  for (Mesh::Face_index f : wrap.faces()) {
    std::array<Point, 3> c;
    int k = 0;
    for (Mesh::Vertex_index v : CGAL::vertices_around_face(wrap.halfedge(f), wrap)) c[k++] = wrapped[v.idx()];
    const auto hit = tree.closest_point_and_primitive(CGAL::centroid(c[0], c[1], c[2]));
    const Kernel::Triangle_3& t = *hit.second;
    if (normal(c[0], c[1], c[2]).dot(normal(t[0], t[1], t[2])) <= 0) drop.push_back(f);
  }
  for (Mesh::Face_index f : drop) CGAL::Euler::remove_face(wrap.halfedge(f), wrap);
  wrap.collect_garbage();
  return detail::to_triangle_mesh(wrap, "outer_envelope");
}

}  // namespace hdm
