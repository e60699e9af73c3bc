// SPDX-License-Identifier: MIT
// One polygon of a mesh file -> triangles: fans for convex polygons, CGAL's constrained Delaunay
// triangulation (odd nesting) in the best-fit plane for the others. The one translation unit of
// hdm::io that includes CGAL: header-only, with CGAL's own exact number types (CGAL_NO_GMP, set
// in src/io/CMakeLists.txt), so hdm::io adds no library to a consumer's link line. Its kernel is
// a class of this file, not CGAL's Epick, so no template it instantiates is shared with the
// GMP-based CGAL code of hdm::repair.
#include "triangulate_polygon.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Filtered_kernel.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

namespace hdm::io::detail {
namespace {

// Exact predicates, inexact constructions (as CGAL's Epick), under a name of this file.
struct Kernel : CGAL::Filtered_kernel_adaptor<
                    CGAL::Type_equality_wrapper<CGAL::Simple_cartesian<double>::Base<Kernel>::Type, Kernel>, true> {};

struct Corner {
  int32_t id = -1;     // the file's vertex id of a triangulation vertex
  int32_t index = -1;  // its number among the polygon's distinct points
};
using Vb = CGAL::Triangulation_vertex_base_with_info_2<Corner, Kernel>;
using Fb =
    CGAL::Triangulation_face_base_with_info_2<int8_t, Kernel, CGAL::Constrained_triangulation_face_base_2<Kernel>>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
// An edge may pass through a corner; an edge that crosses or overlaps another throws (resolving
// either would need new points, or a count of overlaps whose bookkeeping can grow quadratically).
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::No_constraint_intersection_tag>;

using Vec2 = std::array<double, 2>;

double turn(const Vec2& o, const Vec2& a, const Vec2& b) {
  return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

void fan(const int32_t* ids, size_t k, std::vector<Tri>& out) {
  for (size_t i = 1; i + 1 < k; ++i) out.push_back({ids[0], ids[i], ids[i + 1]});
}

// Odd nesting: faces reached from the infinite face across an odd number of outline edges.
void odd_nesting_faces(Cdt& cdt, std::vector<Tri>& out) {
  for (const Cdt::Face_handle f : cdt.all_face_handles()) f->info() = -1;
  std::vector<Cdt::Face_handle> stack{cdt.infinite_face()};
  cdt.infinite_face()->info() = 0;
  while (!stack.empty()) {
    const Cdt::Face_handle f = stack.back();
    stack.pop_back();
    for (int j = 0; j < 3; ++j) {
      const Cdt::Face_handle n = f->neighbor(j);
      if (n->info() >= 0) continue;
      n->info() = static_cast<int8_t>(f->info() ^ (f->is_constrained(j) ? 1 : 0));
      stack.push_back(n);
    }
  }
  for (const Cdt::Face_handle f : cdt.finite_face_handles())
    if (f->info() == 1) out.push_back({f->vertex(0)->info().id, f->vertex(1)->info().id, f->vertex(2)->info().id});
}

// Constrained Delaunay triangulation of the outline q (counter-clockwise faces: the plane's
// orientation, so the polygon's winding). Only edges the outline runs along an odd number of
// times bound its inside: those are the constraints.
PolygonTriangles triangulate_outline(const std::vector<Vec2>& q, const int32_t* ids, size_t k, std::vector<Tri>& out) {
  Cdt cdt;
  std::vector<Cdt::Vertex_handle> point;  // the distinct points, by index
  std::vector<int32_t> index(k);          // corner -> its point
  Cdt::Face_handle hint;
  for (size_t i = 0; i < k; ++i) {
    const Cdt::Vertex_handle v = cdt.insert(Kernel::Point_2(q[i][0], q[i][1]), hint);
    // Corners at one point of the plane are one vertex, the first corner's.
    if (v->info().index < 0) {
      v->info() = {ids[i], static_cast<int32_t>(point.size())};
      point.push_back(v);
    }
    index[i] = v->info().index;
    hint = v->face();
  }
  if (cdt.dimension() < 2) {  // collinear in exact arithmetic: no area to cover
    fan(ids, k, out);
    return PolygonTriangles::Done;
  }
  std::vector<std::pair<int32_t, int32_t>> edges;
  for (size_t i = 0; i < k; ++i) {
    const int32_t a = index[i], b = index[(i + 1) % k];
    if (a != b) edges.emplace_back(std::min(a, b), std::max(a, b));
  }
  std::sort(edges.begin(), edges.end());
  try {
    for (size_t i = 0; i < edges.size();) {
      size_t j = i;
      while (j < edges.size() && edges[j] == edges[i]) ++j;
      if ((j - i) % 2 == 1) cdt.insert_constraint(point[edges[i].first], point[edges[i].second]);
      i = j;
    }
  } catch (const Cdt::Intersection_of_constraints_exception&) {
    return PolygonTriangles::CrossesItself;
  }
  odd_nesting_faces(cdt, out);
  return PolygonTriangles::Done;
}

}  // namespace

PolygonTriangles triangulate_polygon(const std::vector<Vec3>& positions, const int32_t* ids, size_t k,
                                     std::vector<Tri>& out, std::vector<Vec2>& q) {
  if (k == 3) {
    out.push_back({ids[0], ids[1], ids[2]});
    return PolygonTriangles::Done;
  }
  // Newell normal about the centroid (less cancellation than about the origin).
  Vec3 centre = Vec3::Zero();
  for (size_t i = 0; i < k; ++i) centre += positions[ids[i]];
  centre /= double(k);
  Vec3 n = Vec3::Zero();
  bool spans_area = false;  // some corner pair spans a triangle of area with the centroid
  for (size_t i = 0; i < k; ++i) {
    const Vec3 t = (positions[ids[i]] - centre).cross(positions[ids[(i + 1) % k]] - centre);
    spans_area = spans_area || t != Vec3::Zero();
    n += t;
  }
  const double len = n.norm();
  // Area in its parts but none in all (a bowtie's two lobes cancel): not a simple polygon.
  if (len == 0 && spans_area) return PolygonTriangles::CrossesItself;
  if (!(len > 0) || !std::isfinite(len)) {  // no plane: every triangle has zero area anyway
    fan(ids, k, out);
    return PolygonTriangles::Done;
  }
  n /= len;
  // A basis (e1, e2) of the plane with e1 x e2 = n, so the polygon runs counter-clockwise in it.
  const Vec3 a = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 e1 = n.cross(a).normalized(), e2 = n.cross(e1);
  q.resize(k);
  for (size_t i = 0; i < k; ++i) {
    const Vec3 d = positions[ids[i]] - centre;
    q[i] = {d.dot(e1), d.dot(e2)};
  }
  // Convex: no right turn, and one turn around in all (a pentagram turns left twice around).
  size_t reflex = k, reflex_count = 0;
  double turning = 0;
  for (size_t i = 0; i < k; ++i) {
    const Vec2 &p = q[(i + k - 1) % k], &c = q[i], &nx = q[(i + 1) % k];
    const double t = turn(p, c, nx);
    if (t < 0) reflex = i, ++reflex_count;
    turning += std::atan2(t, (c[0] - p[0]) * (nx[0] - c[0]) + (c[1] - p[1]) * (nx[1] - c[1]));
  }
  if (reflex_count == 0 && turning < 3 * std::numbers::pi) {
    fan(ids, k, out);
    return PolygonTriangles::Done;
  }
  if (k == 4 && reflex_count == 1) {  // a dart: both triangles start at the reflex corner
    const size_t r = reflex;
    out.push_back({ids[r], ids[(r + 1) % 4], ids[(r + 2) % 4]});
    out.push_back({ids[r], ids[(r + 2) % 4], ids[(r + 3) % 4]});
    return PolygonTriangles::Done;
  }
  return triangulate_outline(q, ids, k, out);
}

}  // namespace hdm::io::detail
