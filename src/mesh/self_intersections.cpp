// SPDX-License-Identifier: MIT
// Self-intersection count and local repair, with CGAL; one of the few translation
// units that include CGAL (heavy templates).
#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/core/error.h>
#include <hdm/mesh/self_intersections.h>
#include <hdm/mesh/open_self_intersections.h>
#include <hdm/mesh/winding_number.h>

#include "self_intersecting_faces.h"
#include "nearly_closed.h"
#include "surface_mesh_copy.h"
#include "refine_crossings.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/stitch_borders.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/repair.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/repair_self_intersections.h>

#include <algorithm>
#include <array>
#include <string>
#include <vector>

namespace hdm {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;

// Longest crack (boundary cycle left after stitching the union) that resolve_self_intersections() closes,
// and longer ones up to kMaxSmallCrackEdges when they span at most kSmallCrack of the diagonal
// (mannequin-devil.off: one of 16 edges where a horn meets the head).
constexpr int kMaxCrackEdges = 12;
constexpr int kMaxSmallCrackEdges = 64;
constexpr double kSmallCrack = 0.01;
// Most crossing face pairs resolve_self_intersections() refines exactly. The refinement costs about
// 0.5 ms per pair where crossings pile up in degenerate configurations (a printer bed of stacked
// coplanar plates: 103,289 pairs in 49 s, exact predicates on collinear points), so this bounds
// it near 10 s; the crossings of scans and assemblies number hundreds to a few thousand
// (mannequin-devil.off: 1,643 pairs in 0.26 s).
constexpr int64_t kMaxRefinedPairs = 20000;
// Most face pairs still meeting after the resolution that CGAL's `remove_self_intersections` is
// asked to clear (see resolve_self_intersections()).
constexpr int64_t kMaxCleanupPairs = 256;
// Longest hole filled so (the fill costs O(h³)); mannequin-devil.off's open base has 64 edges.
constexpr size_t kMaxFillEdges = 256;

// Whether @p sm's holes are small enough to fill for good: at most kMaxFillEdges edges each, and
// nearly closed by orient_outward()'s rule (mesh::detail::nearly_closed(): fans about their centroids
// of less than a quarter of its area; cheap, before the O(h³) fill).
bool holes_fillable(const Mesh& sm) {
  std::vector<Mesh::Halfedge_index> cycles;
  PMP::extract_boundary_cycles(sm, std::back_inserter(cycles));
  double fans = 0;
  for (Mesh::Halfedge_index h : cycles) {
    std::vector<Vec3> loop;
    for (Mesh::Halfedge_index e : CGAL::halfedges_around_face(h, sm)) {
      const Point& q = sm.point(sm.target(e));
      loop.emplace_back(q.x(), q.y(), q.z());
    }
    if (loop.size() > kMaxFillEdges) return false;
    Vec3 c = Vec3::Zero();
    for (const Vec3& q : loop) c += q / double(loop.size());
    for (size_t i = 0; i < loop.size(); ++i)
      fans += mesh::detail::cap_triangle_area(loop[i], loop[(i + 1) % loop.size()], c);
  }
  return mesh::detail::nearly_closed(fans, PMP::area(sm));
}

// Fills every boundary cycle of @p sm (Liepa 2003: minimal-area triangulation refined to the
// surrounding density, as repair_mesh() fills small holes); returns the area of the added faces.
double fill_holes(Mesh& sm) {
  std::vector<Mesh::Halfedge_index> cycles;
  PMP::extract_boundary_cycles(sm, std::back_inserter(cycles));
  std::vector<Mesh::Face_index> caps;
  for (Mesh::Halfedge_index h : cycles)
    if (sm.is_border(h)) PMP::triangulate_and_refine_hole(sm, h, std::back_inserter(caps), CGAL::Emptyset_iterator());
  double area = 0;
  for (Mesh::Face_index f : caps) area += PMP::face_area(f, sm);
  return area;
}

// The boundary of the solid that the closed @p solid encloses by its generalized winding number,
// @p sm the same faces as a halfedge mesh (see resolve_self_intersections()): the crossings
// refined exactly (refine_crossings()), each piece kept where the winding number crosses ½
// through it, turned to face out. False, @p sm in any state, when that leaves cracks.
bool resolve_closed(Mesh& sm, const TriangleMesh& solid, SelfIntersectionReport& rep) {
  std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> crossing;
  PMP::self_intersections<CGAL::Parallel_if_available_tag>(sm, std::back_inserter(crossing));
  // The exact refinement's cost grows with the crossings (see kMaxRefinedPairs).
  if (crossing.size() > size_t(kMaxRefinedPairs)) return false;
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(crossing.size());
  for (const auto& [a, b] : crossing) pairs.emplace_back(std::minmax(int(a.idx()), int(b.idx())));
  // A parallel search (CGAL built with TBB, which this build is not) lists the pairs in the order
  // its threads found them: sorted, the refinement (and so the bake) is the same from run to run.
  std::sort(pairs.begin(), pairs.end());
  sm.collect_garbage();
  const TriangleMesh refined =
      mesh::detail::refine_crossings(mesh::detail::to_triangle_mesh(sm, "resolve_self_intersections"), pairs);
  // The generalized winding number counts how many parts cover a point, so a piece inside two
  // (or any even number of) overlapping parts is interior too, where ray parity calls it outside.
  const WindingNumber winding(solid);
  const double diagonal = bounds(solid).diagonal();
  // Just off the face: where the surface runs in nearly coincident layers (mannequin-devil.off:
  // folds closer than 10⁻⁶ of the diagonal), a point farther out would pass the layer above and
  // keep both layers. Near faces are summed exactly, so the jump of 1 across the face is sharp.
  const double eps = 1e-9 * diagonal;
  // The exposed pieces are joined as a soup: stitching joins only halfedges whose vertices are shared.
  std::vector<Point> points;
  points.reserve(refined.vertices.size());
  for (const Vec3& p : refined.vertices) points.emplace_back(p.x(), p.y(), p.z());
  // Each patch between crossing curves is classified once, at its largest face (the farthest
  // from the patch's edges, where the offset points are surest).
  int32_t count = 0;
  const std::vector<int32_t> patch = mesh::detail::patches_between_crossings(refined, count);
  std::vector<double> largest(size_t(count), 0);
  std::vector<int32_t> sample(size_t(count), -1);
  for (size_t f = 0; f < refined.faces.size(); ++f) {
    const Tri& t = refined.faces[f];
    const double area = (refined.vertices[size_t(t[1])] - refined.vertices[size_t(t[0])])
                            .cross(refined.vertices[size_t(t[2])] - refined.vertices[size_t(t[0])])
                            .norm();
    if (area > largest[size_t(patch[f])]) largest[size_t(patch[f])] = area, sample[size_t(patch[f])] = int32_t(f);
  }
  enum Side : uint8_t { kInterior, kKept, kFlipped };
  std::vector<Side> side(size_t(count), kInterior);  // patches of zero area stay out
  for (int32_t p = 0; p < count; ++p) {
    if (sample[size_t(p)] < 0) continue;
    const Tri& t = refined.faces[size_t(sample[size_t(p)])];
    const Vec3 &a = refined.vertices[size_t(t[0])], &b = refined.vertices[size_t(t[1])], &d = refined.vertices[size_t(t[2])];
    const Vec3 n = (b - a).cross(d - a).normalized();
    const Vec3 g = (a + b + d) / 3;
    const bool front = winding.inside(g + eps * n), back = winding.inside(g - eps * n);
    side[size_t(p)] = front == back ? kInterior : front ? kFlipped : kKept;
  }
  std::vector<std::array<std::size_t, 3>> polygons;
  rep.interior_faces = 0;
  for (size_t f = 0; f < refined.faces.size(); ++f) {
    const Tri& t = refined.faces[f];
    const Side s = side[size_t(patch[f])];
    const Vec3& a = refined.vertices[size_t(t[0])];
    if (s == kInterior || !((refined.vertices[size_t(t[1])] - a).cross(refined.vertices[size_t(t[2])] - a).norm() > 0))
      ++rep.interior_faces;
    else if (s == kKept) polygons.push_back({size_t(t[0]), size_t(t[1]), size_t(t[2])});
    else polygons.push_back({size_t(t[0]), size_t(t[2]), size_t(t[1])});
  }
  PMP::repair_polygon_soup(points, polygons);
  PMP::orient_polygon_soup(points, polygons);
  sm.clear();
  PMP::polygon_soup_to_polygon_mesh(points, polygons, sm);
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
      Aabb box;
      for (Mesh::Halfedge_index e : CGAL::halfedges_around_face(h, sm)) {
        ++edges;
        const Point& q = sm.point(sm.target(e));
        box.extend(Vec3(q.x(), q.y(), q.z()));
      }
      if (edges > kMaxCrackEdges && !(edges <= kMaxSmallCrackEdges && box.diagonal() <= kSmallCrack * diagonal))
        return false;
    }
    // Liepa's search over every triangulation of the crack, not CGAL's default search within a 3D
    // Delaunay triangulation of its corners, which gave another triangulation of the same crack from
    // one run of hdm to the next (a 19-edge crack of a CAD bed: 2 runs in 12).
    for (Mesh::Halfedge_index h : cycles)
      if (sm.is_border(h))
        PMP::triangulate_hole(sm, h, CGAL::Emptyset_iterator(), CGAL::parameters::use_delaunay_triangulation(false));
    sm.collect_garbage();
    rep.closed_cracks = static_cast<int64_t>(cycles.size());
  }
  return true;
}

}  // namespace

int64_t count_self_intersections(const TriangleMesh& mesh) {
  validate_mesh_data(mesh, "count_self_intersections input");
  int64_t pairs = 0;
  mesh::detail::self_intersecting_faces(mesh, &pairs);
  return pairs;
}

TriangleMesh fill_nearly_closed(const TriangleMesh& mesh) {
  validate_mesh_data(mesh, "fill_nearly_closed input");
  Mesh sm = mesh::detail::to_surface_mesh<Mesh>(mesh);
  if (CGAL::is_closed(sm) || !holes_fillable(sm)) return {};
  const double area = PMP::area(sm);
  const double caps = fill_holes(sm);
  if (!CGAL::is_closed(sm) || !mesh::detail::nearly_closed(caps, area)) return {};
  return mesh::detail::to_triangle_mesh(sm, "fill_nearly_closed");
}

TriangleMesh resolve_self_intersections(const TriangleMesh& mesh, SelfIntersectionReport* report) {
  validate_mesh_data(mesh, "resolve_self_intersections input");
  SelfIntersectionReport rep;
  rep.faces_before = rep.faces_after = static_cast<int64_t>(mesh.faces.size());
  Mesh sm = mesh::detail::to_surface_mesh<Mesh>(mesh);
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
  const bool open = !CGAL::is_closed(sm);
  auto give_up = [&] { return open ? resolve_open_self_intersections(mesh, report) : keep(); };
  if (open) {
    // A nearly closed input (a bust with an open base, a scan with a cut) is resolved as the
    // solid it nearly bounds: its holes are filled (Liepa) and stay filled, so the result is a
    // closed surface. Sheets, and inputs whose fills do not close them, go to the sheet path.
    if (!holes_fillable(sm)) return give_up();
    Mesh filled = sm;
    const double area = PMP::area(sm);
    const double caps = fill_holes(filled);
    if (!CGAL::is_closed(filled) || !mesh::detail::nearly_closed(caps, area)) return give_up();
    const TriangleMesh solid = mesh::detail::to_triangle_mesh(filled, "resolve_self_intersections");
    if (!resolve_closed(filled, solid, rep)) return give_up();
    rep.filled_faces = static_cast<int64_t>(solid.faces.size() - mesh.faces.size());
    sm = std::move(filled);
  } else if (!resolve_closed(sm, mesh, rep)) {
    return keep();
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
  if (!CGAL::is_closed(sm) || sm.number_of_faces() == 0) return give_up();
  rep.pairs_after = count(sm);
  // Where parts of the union touch along an edge (or the rounding of the exact intersection points
  // leaves pieces crossing by a double's spacing), faces still meet: CGAL removes them with the
  // faces around and refills the holes (`remove_self_intersections`), a change of the size of those
  // faces, used only when it leaves a closed surface with fewer pairs. Its cost grows with each
  // spot it treats, so beyond kMaxCleanupPairs (stacked coplanar plates of a CAD part: minutes)
  // the contacts stay as they are.
  if (rep.pairs_after > 0 && rep.pairs_after <= kMaxCleanupPairs) {
    Mesh cleaned = sm;
    bool done = false;
    try {
      done = PMP::experimental::remove_self_intersections(cleaned, CGAL::parameters::preserve_genus(false));
    } catch (const std::exception&) {
      done = false;
    }
    if (done && CGAL::is_closed(cleaned) && cleaned.number_of_faces() > 0) {
      cleaned.collect_garbage();
      const int64_t left = count(cleaned);
      if (left < rep.pairs_after) sm = std::move(cleaned), rep.pairs_after = left;
    }
  }
  TriangleMesh out = mesh::detail::to_triangle_mesh(sm, "resolve_self_intersections");
  rep.faces_after = static_cast<int64_t>(out.faces.size());
  rep.resolved = true;
  if (report) *report = rep;
  return out;
}

}  // namespace hdm
