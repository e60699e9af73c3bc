// SPDX-License-Identifier: MIT
// Which faces of a triangle soup cross another: CGAL's box intersection (in parallel with TBB) and
// exact predicates, on the faces as indexed triangles. No halfedge mesh is built: converting a
// 12.6 M-triangle input to a CGAL::Surface_mesh (soup orientation, then one Euler::add_face per
// face) took longer than the crossing test itself.

// CGAL's parallel box intersection is compiled only with this macro; every CGAL type this unit
// instantiates templates with is local to it.
#ifndef CGAL_LINKED_WITH_TBB
#define CGAL_LINKED_WITH_TBB
#endif

#include "self_intersecting_faces.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>
#include <tbb/enumerable_thread_specific.h>

#include <cmath>
#include <utility>

namespace hdm {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Pairs = std::vector<std::pair<int32_t, int32_t>>;

// A face's bounding box in single precision, rounded outwards (so it holds the face): half the
// memory of a box of doubles. CGAL's box intersection gets pointers to them: it copies the
// ranges it sorts, and copies of the boxes themselves (faster to sort, 26 s against 30 s for the
// count at 12.6 M faces) took 2 GB more.
struct FaceBox {
  using NT = float;
  using ID = std::size_t;
  float lo[3], hi[3];
  int32_t face;
  static int dimension() { return 3; }
  float min_coord(int d) const { return lo[d]; }
  float max_coord(int d) const { return hi[d]; }
  ID id() const { return ID(face); }
};

float down(double x) {
  const float f = static_cast<float>(x);
  return double(f) > x ? std::nextafter(f, -INFINITY) : f;
}
float up(double x) {
  const float f = static_cast<float>(x);
  return double(f) < x ? std::nextafter(f, INFINITY) : f;
}

// Whether faces @p a and @p b cross, sharing a vertex or an edge not counting (the rule of CGAL's
// `Polygon_mesh_processing::self_intersections`, with "shared" read as the same vertex index): two
// faces with an edge in common cross when they are coplanar and lie on the same side of it; two
// with a vertex in common, when the edge opposite it in either meets the other; others, when the
// triangles meet.
bool cross(const TriangleMesh& m, const Tri& a, const Tri& b) {
  const auto point = [&](int32_t v) {
    const Vec3& p = m.vertices[v];
    return Point(p.x(), p.y(), p.z());
  };
  int shared = 0, ia = -1, ib = -1;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (a[i] == b[j]) ++shared, ia = i, ib = j;
  if (shared >= 3) return true;  // the same triangle twice
  const Point a0 = point(a[0]), a1 = point(a[1]), a2 = point(a[2]);
  const Point b0 = point(b[0]), b1 = point(b[1]), b2 = point(b[2]);
  if (shared == 2) {
    // The vertex of each face off the shared edge (u, v).
    int oa = 0, ob = 0;
    while (a[oa] == b[0] || a[oa] == b[1] || a[oa] == b[2]) ++oa;
    while (b[ob] == a[0] || b[ob] == a[1] || b[ob] == a[2]) ++ob;
    const Point u = point(a[(oa + 1) % 3]), v = point(a[(oa + 2) % 3]), pa = point(a[oa]), pb = point(b[ob]);
    return CGAL::coplanar(u, v, pa, pb) && CGAL::coplanar_orientation(u, v, pa, pb) == CGAL::POSITIVE;
  }
  const Kernel::Triangle_3 ta(a0, a1, a2), tb(b0, b1, b2);
  if (shared == 1) {
    const Kernel::Segment_3 sa(point(a[(ia + 1) % 3]), point(a[(ia + 2) % 3]));
    const Kernel::Segment_3 sb(point(b[(ib + 1) % 3]), point(b[(ib + 2) % 3]));
    return CGAL::do_intersect(ta, sb) || CGAL::do_intersect(tb, sa);
  }
  return CGAL::do_intersect(ta, tb);
}

}  // namespace

std::vector<std::pair<int32_t, int32_t>> mesh::detail::self_intersecting_pairs(const TriangleMesh& mesh) {
  Pairs out;
  std::vector<FaceBox> boxes;
  boxes.reserve(mesh.faces.size());
  for (size_t f = 0; f < mesh.faces.size(); ++f) {
    const Tri& t = mesh.faces[f];
    const Vec3 &p = mesh.vertices[t[0]], &q = mesh.vertices[t[1]], &r = mesh.vertices[t[2]];
    if (CGAL::collinear(Point(p.x(), p.y(), p.z()), Point(q.x(), q.y(), q.z()), Point(r.x(), r.y(), r.z()))) {
      out.emplace_back(static_cast<int32_t>(f), static_cast<int32_t>(f));  // degenerate: paired with itself, as CGAL does
      continue;
    }
    const Vec3 lo = p.cwiseMin(q).cwiseMin(r), hi = p.cwiseMax(q).cwiseMax(r);
    boxes.push_back({{down(lo.x()), down(lo.y()), down(lo.z())}, {up(hi.x()), up(hi.y()), up(hi.z())}, int32_t(f)});
  }
  std::vector<const FaceBox*> pointers(boxes.size());
  for (size_t i = 0; i < boxes.size(); ++i) pointers[i] = &boxes[i];
  tbb::enumerable_thread_specific<Pairs> found;
  const auto test = [&](const FaceBox* a, const FaceBox* b) {
    if (cross(mesh, mesh.faces[a->face], mesh.faces[b->face])) found.local().emplace_back(a->face, b->face);
  };
  CGAL::box_self_intersection_d<CGAL::Parallel_tag>(pointers.begin(), pointers.end(), test, std::ptrdiff_t(2000));
  for (const Pairs& p : found) out.insert(out.end(), p.begin(), p.end());
  for (auto& [a, b] : out)
    if (a > b) std::swap(a, b);
  std::sort(out.begin(), out.end());  // the same list whatever the threads did
  return out;
}

std::vector<char> mesh::detail::self_intersecting_faces(const TriangleMesh& mesh, int64_t* pairs_out) {
  const Pairs pairs = self_intersecting_pairs(mesh);
  std::vector<char> crossing(mesh.faces.size(), 0);
  for (const auto& [a, b] : pairs) crossing[a] = crossing[b] = 1;
  if (pairs_out) *pairs_out = static_cast<int64_t>(pairs.size());
  return crossing;
}

}  // namespace hdm
