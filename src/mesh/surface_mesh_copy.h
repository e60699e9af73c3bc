// SPDX-License-Identifier: MIT
#pragma once
// Internal, for the CGAL translation units only: a TriangleMesh to a CGAL::Surface_mesh and back.

#include <hdm/core/error.h>
#include <hdm/mesh/triangle_mesh.h>

#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/boost/graph/iterator.h>

#include <vector>

#include <string>

namespace hdm::mesh::detail {

// The triangles of @p mesh as a CGAL polygon soup, as the soup functions of CGAL's polygon mesh
// processing take it: @p points in vertex order, one polygon (three indices into @p points) per
// face, in face order; both are replaced. O(V + F).
template <class Point>
void to_polygon_soup(const TriangleMesh& mesh, std::vector<Point>& points,
                     std::vector<std::vector<std::size_t>>& polygons) {
  points.clear();
  points.reserve(mesh.vertices.size());
  for (const Vec3& p : mesh.vertices) points.emplace_back(p.x(), p.y(), p.z());
  polygons.clear();
  polygons.reserve(mesh.faces.size());
  for (const Tri& t : mesh.faces) polygons.push_back({size_t(t[0]), size_t(t[1]), size_t(t[2])});
}

// A halfedge mesh of the same triangles; vertices shared by several fans (pinches) are
// duplicated, which leaves the faces, and so their intersections, unchanged. O(F log F).
template <class SurfaceMesh>
SurfaceMesh to_surface_mesh(const TriangleMesh& mesh) {
  std::vector<typename SurfaceMesh::Point> points;
  std::vector<std::vector<std::size_t>> polygons;
  to_polygon_soup(mesh, points, polygons);
  CGAL::Polygon_mesh_processing::orient_polygon_soup(points, polygons);
  SurfaceMesh sm;
  CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(points, polygons, sm);
  return sm;
}

// Vertex k of the result is Surface_mesh vertex index k, so @p sm must have no garbage
// (collect_garbage() first). Throws NumericalError naming @p who for a face that is not a triangle.
template <class SurfaceMesh>
TriangleMesh to_triangle_mesh(const SurfaceMesh& sm, const char* who) {
  using Vertex = typename SurfaceMesh::Vertex_index;
  using Face = typename SurfaceMesh::Face_index;
  TriangleMesh out;
  out.vertices.reserve(sm.number_of_vertices());
  for (Vertex v : sm.vertices()) {
    const auto& p = sm.point(v);
    out.vertices.emplace_back(p.x(), p.y(), p.z());
  }
  out.faces.reserve(sm.number_of_faces());
  for (Face f : sm.faces()) {
    Tri t{};
    int k = 0;
    for (Vertex v : CGAL::vertices_around_face(sm.halfedge(f), sm)) {
      if (k == 3) throw NumericalError(std::string(who) + ": a face with more than three vertices");
      t[k++] = static_cast<int32_t>(v.idx());
    }
    out.faces.push_back(t);
  }
  return out;
}

}  // namespace hdm::mesh::detail
