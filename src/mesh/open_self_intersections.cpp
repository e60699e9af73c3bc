// SPDX-License-Identifier: MIT
// Open sheets that cross each other: corefine them pairwise, drop the interior patches, weld the
// rest. One of the few translation units that include CGAL (heavy templates).
#include <hdm/core/error.h>
#include <hdm/mesh/open_self_intersections.h>
#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/mesh/orient_mesh.h>
#include <hdm/mesh/stitch_seams.h>
#include <hdm/mesh/winding_number.h>

#include "disjoint_sets.h"
#include "retriangulate_tangles.h"
#include "surface_mesh_copy.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/shape_predicates.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <array>
#include <map>
#include <numeric>
#include <set>
#include <vector>

namespace hdm {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using Edge = Mesh::Edge_index;
using Face = Mesh::Face_index;

// Farthest a retriangulated spot may lie from the input, as a fraction of its diagonal.
constexpr double kTangleTolerance = 1e-3;

// Sheets: faces joined by an edge (union-find).
std::vector<int32_t> sheet_of_faces(const TriangleMesh& mesh, int32_t& count) {
  mesh::detail::DisjointSets<> sets(mesh.faces.size());
  std::map<std::pair<int32_t, int32_t>, int32_t> first;
  for (size_t f = 0; f < mesh.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int32_t a = mesh.faces[f][k], b = mesh.faces[f][(k + 1) % 3];
      auto [it, fresh] = first.try_emplace({std::min(a, b), std::max(a, b)}, int32_t(f));
      if (!fresh) sets.unite(int32_t(f), it->second);
    }
  std::vector<int32_t> label(mesh.faces.size());
  std::map<int32_t, int32_t> id;
  for (size_t f = 0; f < mesh.faces.size(); ++f)
    label[f] = id.try_emplace(sets.find(int32_t(f)), int32_t(id.size())).first->second;
  count = int32_t(id.size());
  return label;
}

Mesh sheet_mesh(const TriangleMesh& mesh, const std::vector<int32_t>& sheet, int32_t s) {
  std::vector<Point> points;
  std::vector<std::vector<std::size_t>> polygons;
  std::map<int32_t, std::size_t> local;
  for (size_t f = 0; f < mesh.faces.size(); ++f) {
    if (sheet[f] != s) continue;
    std::vector<std::size_t> poly;
    for (int32_t v : mesh.faces[f]) {
      auto [it, fresh] = local.try_emplace(v, points.size());
      if (fresh) points.emplace_back(mesh.vertices[v].x(), mesh.vertices[v].y(), mesh.vertices[v].z());
      poly.push_back(it->second);
    }
    polygons.push_back(std::move(poly));
  }
  PMP::orient_polygon_soup(points, polygons);  // duplicates pinched vertices; the input is oriented already
  Mesh sm;
  PMP::polygon_soup_to_polygon_mesh(points, polygons, sm);
  return sm;
}

Vec3 to_vec(const Point& p) { return Vec3(p.x(), p.y(), p.z()); }

int64_t crossing_pairs(const Mesh& sm) {
  std::vector<std::pair<Face, Face>> pairs;
  PMP::self_intersections<CGAL::Parallel_if_available_tag>(sm, std::back_inserter(pairs));
  return static_cast<int64_t>(pairs.size());
}

// CGAL's corefinement requires both meshes free of self-intersections, which includes faces of
// zero area (PMP::corefine()'s preconditions); a corefinement can leave such faces where sheets
// touch in one plane, and the next one then dereferences the crossing of two edge lines that do
// not cross. Checked before every corefinement of a sheet changed since its last check.
bool corefinable(const Mesh& m) {
  for (Face f : m.faces())
    if (PMP::is_degenerate_triangle_face(f, m)) return false;
  return !PMP::does_self_intersect<CGAL::Parallel_if_available_tag>(m);
}

// Corefines every pair of sheets whose boxes overlap, marking the crossing curves in @p curve;
// false when CGAL throws (a configuration it does not handle) or a sheet is not corefinable().
bool corefine_sheets(std::vector<Mesh>& sheets, std::vector<Mesh::Property_map<Edge, bool>>& curve) {
  std::vector<uint8_t> changed(sheets.size(), 1);
  try {
    for (size_t i = 0; i < sheets.size(); ++i)
      for (size_t j = i + 1; j < sheets.size(); ++j) {
        if (!CGAL::do_overlap(CGAL::Polygon_mesh_processing::bbox(sheets[i]), PMP::bbox(sheets[j]))) continue;
        for (size_t k : {i, j}) {
          if (changed[k] && !corefinable(sheets[k])) return false;
          changed[k] = 0;
        }
        const auto before_i = sheets[i].number_of_faces(), before_j = sheets[j].number_of_faces();
        PMP::corefine(sheets[i], sheets[j], CGAL::parameters::edge_is_constrained_map(curve[i]),
                      CGAL::parameters::edge_is_constrained_map(curve[j]));
        changed[i] = sheets[i].number_of_faces() != before_i;
        changed[j] = sheets[j].number_of_faces() != before_j;
      }
  } catch (const std::exception&) {
    return false;
  }
  return true;
}

// The faces of the corefined @p sheets that are not inside the solid of @p work (its winding
// number), welded by position; counts the interior ones in the report.
TriangleMesh exposed_patches(std::vector<Mesh>& sheets, const std::vector<Mesh::Property_map<Edge, bool>>& curve,
                             const TriangleMesh& work, SelfIntersectionReport& rep) {
  // Patches: faces joined across edges that are neither a curve nor a border; each is voted
  // interior or exposed as a whole, so a sliver at a curve cannot flip on its own.
  const WindingNumber winding(work);
  const double eps = 1e-5 * bounds(work).diagonal();
  std::map<std::array<double, 3>, int32_t> welded;
  TriangleMesh out;
  auto weld = [&](const Point& p) {
    auto [it, fresh] = welded.try_emplace({p.x(), p.y(), p.z()}, int32_t(out.vertices.size()));
    if (fresh) out.vertices.push_back(to_vec(p));
    return it->second;
  };
  for (size_t s = 0; s < sheets.size(); ++s) {
    Mesh& m = sheets[s];
    auto patch = m.add_property_map<Face, int32_t>("f:hdm_patch", -1).first;
    std::vector<double> interior_area, area;
    for (Face seed : m.faces()) {
      if (patch[seed] >= 0) continue;
      const int32_t id = int32_t(area.size());
      area.push_back(0), interior_area.push_back(0);
      std::vector<Face> stack{seed};
      patch[seed] = id;
      while (!stack.empty()) {
        const Face f = stack.back();
        stack.pop_back();
        std::array<Vec3, 3> c;
        int k = 0;
        for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) c[k++] = to_vec(m.point(v));
        const Vec3 n = 0.5 * (c[1] - c[0]).cross(c[2] - c[0]);
        const double a = n.norm();
        if (a > 0) {
          area[id] += a;
          if (winding.inside((c[0] + c[1] + c[2]) / 3.0 + eps * n / a)) interior_area[id] += a;
        }
        for (auto h : CGAL::halfedges_around_face(m.halfedge(f), m)) {
          if (curve[s][m.edge(h)] || m.is_border(m.opposite(h))) continue;
          const Face g = m.face(m.opposite(h));
          if (patch[g] < 0) patch[g] = id, stack.push_back(g);
        }
      }
    }
    for (Face f : m.faces()) {
      if (2 * interior_area[patch[f]] >= area[patch[f]] && area[patch[f]] > 0) {
        ++rep.interior_faces;
        continue;
      }
      Tri t{};
      int k = 0;
      for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) t[k++] = weld(m.point(v));
      if (t[0] != t[1] && t[1] != t[2] && t[2] != t[0]) out.faces.push_back(t);
    }
  }
  return out;
}

// Whether the faces meet two by two along every edge, front to back (no directed edge twice).
bool meet_in_pairs(const TriangleMesh& out) {
  std::map<std::pair<int32_t, int32_t>, int> uses;
  for (const Tri& t : out.faces)
    for (int k = 0; k < 3; ++k) ++uses[{t[k], t[(k + 1) % 3]}];
  for (const auto& [e, n] : uses)
    if (n > 1) return false;
  return true;
}

// @p out as a CGAL mesh with its pinches split, counted in the report's split_pinches.
Mesh with_pinches_split(const TriangleMesh& out, SelfIntersectionReport& rep) {
  // Patches that touch at a point leave a pinch: one copy of the vertex per fan (CGAL's soup
  // orientation splits them), each moved 1% towards its own fan's ring so the copies do not
  // coincide (the bake finds no room for a shell between coincident corners), as
  // resolve_self_intersections() does for closed unions.
  std::vector<Point> soup_points;
  std::vector<std::vector<std::size_t>> polygons;
  mesh::detail::to_polygon_soup(out, soup_points, polygons);
  const size_t welded_count = soup_points.size();
  PMP::orient_polygon_soup(soup_points, polygons);
  if (soup_points.size() > welded_count) {
    std::map<std::array<double, 3>, std::vector<size_t>> copies;
    for (size_t i = 0; i < soup_points.size(); ++i)
      copies[{soup_points[i].x(), soup_points[i].y(), soup_points[i].z()}].push_back(i);
    std::vector<Vec3> ring(soup_points.size(), Vec3::Zero());
    std::vector<int> ring_n(soup_points.size(), 0);
    for (const auto& poly : polygons)
      for (size_t k = 0; k < 3; ++k)
        for (size_t j = 1; j < 3; ++j) ring[poly[k]] += to_vec(soup_points[poly[(k + j) % 3]]), ++ring_n[poly[k]];
    for (const auto& [p, group] : copies) {
      if (group.size() < 2) continue;
      ++rep.split_pinches;
      for (size_t i : group) {
        const Vec3 q = to_vec(soup_points[i]);
        const Vec3 moved = ring_n[i] ? Vec3(q + 0.01 * (ring[i] / ring_n[i] - q)) : q;
        soup_points[i] = Point(moved.x(), moved.y(), moved.z());
      }
    }
  }
  Mesh result;
  PMP::polygon_soup_to_polygon_mesh(soup_points, polygons, result);
  return result;
}

}  // namespace

TriangleMesh resolve_open_self_intersections(const TriangleMesh& mesh, SelfIntersectionReport* report) {
  validate_mesh_data(mesh, "resolve_open_self_intersections input");
  SelfIntersectionReport rep;
  rep.faces_before = rep.faces_after = static_cast<int64_t>(mesh.faces.size());
  auto keep = [&] {
    if (report) *report = rep;
    return mesh;
  };
  if (analyze_topology(mesh).boundary_edges == 0) return keep();
  rep.pairs_before = rep.pairs_after = crossing_pairs(mesh::detail::to_surface_mesh<Mesh>(mesh));
  if (rep.pairs_before == 0) return keep();
  // Patches that meet with T-junctions are one surface: stitch them first, and orient the result
  // again (orient_outward() oriented the patches one by one).
  SeamReport seams;
  TriangleMesh stitched = stitch_seams(mesh, &seams);
  const bool joined = seams.inserted > 0 || seams.snapped > 0;
  if (joined) orient_outward(stitched);
  rep.seam_vertices = seams.inserted + seams.snapped;
  const TriangleMesh& work = joined ? stitched : mesh;
  if (joined && seams.boundary_edges_after == 0) {
    // One closed surface now: resolved as a closed input is, into the solid it bounds.
    SelfIntersectionReport closed;
    TriangleMesh out = resolve_self_intersections(stitched, &closed);
    if (closed.pairs_before == 0) closed.resolved = true;  // the seams were all that crossed
    if (!closed.resolved || closed.pairs_after >= rep.pairs_before) return keep();
    closed.pairs_before = rep.pairs_before;
    closed.faces_before = rep.faces_before;
    closed.seam_vertices = rep.seam_vertices;
    if (report) *report = closed;
    return out;
  }
  int32_t count = 0;
  const std::vector<int32_t> sheet = sheet_of_faces(work, count);
  std::vector<Mesh> sheets;
  for (int32_t s = 0; s < count; ++s) sheets.push_back(sheet_mesh(work, sheet, s));
  for (const Mesh& m : sheets)
    if (PMP::does_self_intersect<CGAL::Parallel_if_available_tag>(m)) {
      // A sheet that crosses itself (a crumpled scan): its crumpled spots are triangulated
      // again, when that resolves every crossing within the tolerance; else the input is kept.
      TriangleMesh untangled;
      if (!mesh::detail::retriangulate_tangles(work, kTangleTolerance * bounds(work).diagonal(), untangled,
                                               rep.retriangulated_faces))
        return keep();
      rep.pairs_after = 0;
      rep.faces_after = static_cast<int64_t>(untangled.faces.size());
      rep.resolved = true;
      if (report) *report = rep;
      return untangled;
    }
  std::vector<Mesh::Property_map<Edge, bool>> curve;
  for (Mesh& m : sheets) curve.push_back(m.add_property_map<Edge, bool>("e:hdm_curve", false).first);
  if (!corefine_sheets(sheets, curve)) return keep();  // bake the input as it is
  const TriangleMesh out = exposed_patches(sheets, curve, work, rep);
  if (out.faces.empty()) return keep();
  // The kept patches must meet two by two along the curves, front to back.
  if (!meet_in_pairs(out)) return keep();
  const Mesh result = with_pinches_split(out, rep);
  rep.pairs_after = crossing_pairs(result);
  if (rep.pairs_after > 0) {
    rep.pairs_after = rep.pairs_before;
    return keep();
  }
  TriangleMesh resolved = mesh::detail::to_triangle_mesh(result, "resolve_open_self_intersections");
  rep.faces_after = static_cast<int64_t>(resolved.faces.size());
  rep.resolved = true;
  if (report) *report = rep;
  return resolved;
}

}  // namespace hdm
