// SPDX-License-Identifier: MIT
// Self-intersection count and local repair, with CGAL; one of the few translation
// units that include CGAL (heavy templates).
#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/core/error.h>
#include <hdm/mesh/self_intersections.h>
#include <hdm/mesh/crossing_sheets.h>

#include "surface_mesh_copy.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/stitch_borders.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Polygon_mesh_processing/repair.h>

#include <array>
#include <string>
#include <vector>

namespace hdm {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;

// Longest crack (boundary cycle left after stitching the union) that resolve_self_intersections() closes.
constexpr int kMaxCrackEdges = 12;

}  // namespace

int64_t count_self_intersections(const TriangleMesh& mesh) {
  validate_mesh_data(mesh, "count_self_intersections input");
  const Mesh sm = detail::to_surface_mesh<Mesh>(mesh);
  std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> pairs;
  PMP::self_intersections<CGAL::Parallel_if_available_tag>(sm, std::back_inserter(pairs));
  return static_cast<int64_t>(pairs.size());
}

TriangleMesh resolve_self_intersections(const TriangleMesh& mesh, SelfIntersectionReport* report) {
  validate_mesh_data(mesh, "resolve_self_intersections input");
  SelfIntersectionReport rep;
  rep.faces_before = rep.faces_after = static_cast<int64_t>(mesh.faces.size());
  Mesh sm = detail::to_surface_mesh<Mesh>(mesh);
  auto count = [](const Mesh& m) {
    std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> pairs;
    PMP::self_intersections<CGAL::Parallel_if_available_tag>(m, std::back_inserter(pairs));
    return static_cast<int64_t>(pairs.size());
  };
  rep.pairs_before = rep.pairs_after = count(sm);
  auto keep = [&] {
    if (report) *report = rep;
    return mesh;
  };
  if (rep.pairs_before == 0) return keep();
  if (!CGAL::is_closed(sm)) return resolve_crossing_sheets(mesh, report);
  try {
    PMP::experimental::autorefine(sm);
  } catch (const std::exception&) {
    return keep();  // CGAL's refinement is experimental and asserts on some configurations
  }
  const ExactMeshQuery winding(mesh);
  const double eps = 1e-6 * bounds(mesh).diagonal();
  std::vector<Mesh::Face_index> buried;
  for (Mesh::Face_index f : sm.faces()) {
    std::array<Point, 3> c;
    int k = 0;
    for (Mesh::Vertex_index v : CGAL::vertices_around_face(sm.halfedge(f), sm)) c[k++] = sm.point(v);
    const Vec3 a(c[0].x(), c[0].y(), c[0].z()), b(c[1].x(), c[1].y(), c[1].z()), d(c[2].x(), c[2].y(), c[2].z());
    const Vec3 n = (b - a).cross(d - a);
    const Vec3 g = (a + b + d) / 3;
    if (!(n.norm() > 0) || winding.inside(g + eps * n.normalized()) || !winding.inside(g - eps * n.normalized()))
      buried.push_back(f);
  }
  for (Mesh::Face_index f : buried) CGAL::Euler::remove_face(sm.halfedge(f), sm);
  sm.collect_garbage();
  PMP::stitch_borders(sm);
  sm.collect_garbage();
  // Where the union meets itself along an edge or a vertex (parts that touch, slivers of the
  // refinement), stitching leaves a few cracks of a handful of edges: close them flat, as
  // repair_mesh() closes small holes. Anything larger means the classification failed.
  {
    std::vector<Mesh::Halfedge_index> cycles;
    PMP::extract_boundary_cycles(sm, std::back_inserter(cycles));
    for (Mesh::Halfedge_index h : cycles) {
      int edges = 0;
      for (Mesh::Halfedge_index e : CGAL::halfedges_around_face(h, sm)) (void)e, ++edges;
      if (edges > kMaxCrackEdges) return keep();
    }
    for (Mesh::Halfedge_index h : cycles)
      if (sm.is_border(h)) PMP::triangulate_hole(sm, h, CGAL::Emptyset_iterator());
    sm.collect_garbage();
    rep.closed_cracks = static_cast<int64_t>(cycles.size());
  }
  // Parts that touch at a point leave a pinch: one copy per fan, each moved a little into its own
  // fan so the copies do not coincide (the bake finds no room for a shell between coincident corners).
  {
    std::vector<std::vector<Mesh::Vertex_index>> copies;
    PMP::duplicate_non_manifold_vertices(sm, CGAL::parameters::output_iterator(std::back_inserter(copies)));
    for (const auto& group : copies) {
      std::vector<Point> moved;
      for (Mesh::Vertex_index v : group) {
        double c[3] = {0, 0, 0};
        int k = 0;
        for (Mesh::Vertex_index u : CGAL::vertices_around_target(sm.halfedge(v), sm))
          c[0] += sm.point(u).x(), c[1] += sm.point(u).y(), c[2] += sm.point(u).z(), ++k;
        const Point& p = sm.point(v);
        moved.push_back(k ? Point(p.x() + 0.01 * (c[0] / k - p.x()), p.y() + 0.01 * (c[1] / k - p.y()),
                                  p.z() + 0.01 * (c[2] / k - p.z()))
                          : p);
      }
      for (size_t i = 0; i < group.size(); ++i) sm.point(group[i]) = moved[i];
    }
    rep.split_pinches = static_cast<int64_t>(copies.size());
  }
  if (!CGAL::is_closed(sm) || sm.number_of_faces() == 0) return keep();
  rep.pairs_after = count(sm);
  rep.buried_faces = static_cast<int64_t>(buried.size());
  TriangleMesh out = detail::to_triangle_mesh(sm, "resolve_self_intersections");
  rep.faces_after = static_cast<int64_t>(out.faces.size());
  rep.resolved = true;
  if (report) *report = rep;
  return out;
}

}  // namespace hdm
