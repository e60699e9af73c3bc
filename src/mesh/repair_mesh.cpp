// SPDX-License-Identifier: MIT
// Mesh repair with CGAL's polygon mesh processing; one of the few translation units that include
// CGAL (heavy templates: kept out of everything else).
#include <hdm/core/error.h>
#include <hdm/mesh/repair_mesh.h>

#include "fill_holes.h"
#include "surface_mesh_copy.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <map>
#include <set>
#include <vector>

namespace hdm {

namespace PMP = CGAL::Polygon_mesh_processing;
using mesh::detail::Point;
using Mesh = mesh::detail::SurfaceMesh;

bool needs_repair(const TriangleMesh& mesh) {
  const MeshTopology t = analyze_topology(mesh);
  return t.degenerate_faces || t.non_manifold_edges || t.inconsistent_edges || t.boundary_edges;
}

namespace {

// Zero-area faces with three distinct, collinear vertices (after welding there are no others): the
// middle vertex w lies on the long edge (u, v). Split the neighbour across that edge at w and drop
// the sliver, so no gap opens (a T-junction becomes two triangles). Faces are consistently
// oriented here, so the neighbour traverses the long edge as (v, u).
int64_t remove_slivers(const std::vector<Point>& points, std::vector<std::vector<std::size_t>>& polygons, double diag) {
  // Zero area as analyze_topology() counts it: |cross| below 1e-14 diag² (a computed midpoint is
  // rarely exactly collinear).
  const double eps = 1e-14 * diag * diag;
  auto v3 = [&](size_t i) { return Vec3(points[i].x(), points[i].y(), points[i].z()); };
  auto sliver = [&](const std::vector<std::size_t>& t) {
    return (v3(t[1]) - v3(t[0])).cross(v3(t[2]) - v3(t[0])).norm() <= eps;
  };
  int64_t removed = 0;
  for (int pass = 0; pass < 8; ++pass) {
    std::map<std::pair<size_t, size_t>, size_t> by_edge;
    for (size_t f = 0; f < polygons.size(); ++f)
      for (int k = 0; k < 3; ++k) by_edge[{polygons[f][k], polygons[f][(k + 1) % 3]}] = f;
    std::vector<uint8_t> dead(polygons.size(), 0);
    std::vector<std::vector<std::size_t>> added;
    bool any = false;
    for (size_t f = 0; f < polygons.size(); ++f) {
      const auto& t = polygons[f];
      if (dead[f] || !sliver(t)) continue;
      any = true;
      int k = 0;  // the longest edge (t[k], t[k+1]); its opposite vertex lies between its ends
      for (int e = 1; e < 3; ++e)
        if ((v3(t[(e + 1) % 3]) - v3(t[e])).squaredNorm() > (v3(t[(k + 1) % 3]) - v3(t[k])).squaredNorm()) k = e;
      dead[f] = 1;
      ++removed;
      const size_t u = t[k], v = t[(k + 1) % 3], w = t[(k + 2) % 3];
      const auto it = by_edge.find({v, u});
      if (it == by_edge.end() || dead[it->second]) continue;  // on a boundary: the boundary moves to w
      const auto& n = polygons[it->second];
      size_t d = n[0];
      for (size_t x : n)
        if (x != u && x != v) d = x;
      dead[it->second] = 1;
      added.push_back({v, w, d});
      added.push_back({w, u, d});
    }
    if (!any) break;
    std::vector<std::vector<std::size_t>> kept;
    for (size_t f = 0; f < polygons.size(); ++f)
      if (!dead[f]) kept.push_back(std::move(polygons[f]));
    for (auto& a : added) kept.push_back(std::move(a));
    polygons = std::move(kept);
  }
  return removed;
}

// Oriented faces as sorted-rotation keys, to count faces whose orientation changed.
std::array<Point, 3> rotated(std::array<Point, 3> t) {
  std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
  return t;
}

}  // namespace

TriangleMesh repair_mesh(const TriangleMesh& mesh, const std::string& name, const RepairOptions& options,
                         RepairReport* report) {
  validate_mesh_data(mesh, name);
  RepairReport rep;
  std::vector<Point> points;
  std::vector<std::vector<std::size_t>> polygons;
  mesh::detail::to_polygon_soup(mesh, points, polygons);
  std::set<std::array<Point, 3>> original_orientation;
  for (const Tri& f : mesh.faces) original_orientation.insert(rotated({points[f[0]], points[f[1]], points[f[2]]}));

  // Weld, drop repeated-vertex and duplicate faces, drop unused points.
  const size_t v0 = points.size(), f0 = polygons.size();
  PMP::repair_polygon_soup(points, polygons);
  rep.removed_faces += static_cast<int64_t>(f0 - polygons.size());
  const size_t v1 = points.size();
  if (!PMP::orient_polygon_soup(points, polygons)) rep.split_vertices = static_cast<int64_t>(points.size() - v1);
  rep.removed_faces += remove_slivers(points, polygons, bounds(mesh).diagonal());
  if (polygons.empty()) throw InvalidInput(name + ": no faces left after removing degenerate (zero-area) faces");

  const double diag = bounds(mesh).diagonal();
  Mesh sm = mesh::detail::fill_holes(points, polygons, diag, options, rep);
  if (CGAL::is_closed(sm)) PMP::orient_to_bound_a_volume(sm);
  sm.collect_garbage();

  TriangleMesh out = mesh::detail::to_triangle_mesh(sm, "repair_mesh");
  for (const Tri& t : out.faces)
    if (original_orientation.count(rotated({sm.point(Mesh::Vertex_index(t[0])), sm.point(Mesh::Vertex_index(t[1])),
                                            sm.point(Mesh::Vertex_index(t[2]))})) == 0 &&
        original_orientation.count(rotated({sm.point(Mesh::Vertex_index(t[0])), sm.point(Mesh::Vertex_index(t[2])),
                                            sm.point(Mesh::Vertex_index(t[1]))})) != 0)
      ++rep.flipped_faces;
  // Welded vertices: input vertices minus those that survive or were removed as unused.
  rep.merged_vertices = static_cast<int64_t>(v0) - static_cast<int64_t>(v1);
  if (report) *report = rep;
  return out;
}

}  // namespace hdm
