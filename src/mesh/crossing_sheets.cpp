// SPDX-License-Identifier: MIT
// Open sheets that cross each other: corefine them pairwise, drop the buried patches, weld the
// rest. One of the few translation units that include CGAL (heavy templates).
#include <hdm/core/error.h>
#include <hdm/mesh/crossing_sheets.h>
#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/mesh/orient_mesh.h>
#include <hdm/mesh/stitch_seams.h>
#include <hdm/mesh/winding_number.h>

#include "crossing_faces.h"
#include "surface_mesh_copy.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
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

// Most vertex rings grown around a crumpled spot before retriangulate_tangles() gives up.
constexpr int kMaxTangleRings = 6;
// Farthest a retriangulated spot may lie from the input, as a fraction of its diagonal.
constexpr double kTangleTolerance = 1e-3;

// Sheets: faces joined by an edge (union-find).
std::vector<int32_t> sheet_of_faces(const TriangleMesh& mesh, int32_t& count) {
  std::vector<int32_t> parent(mesh.faces.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int32_t f) {
    while (parent[f] != f) f = parent[f] = parent[parent[f]];
    return f;
  };
  std::map<std::pair<int32_t, int32_t>, int32_t> first;
  for (size_t f = 0; f < mesh.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int32_t a = mesh.faces[f][k], b = mesh.faces[f][(k + 1) % 3];
      auto [it, fresh] = first.try_emplace({std::min(a, b), std::max(a, b)}, int32_t(f));
      if (!fresh) parent[find(int32_t(f))] = find(it->second);
    }
  std::vector<int32_t> label(mesh.faces.size());
  std::map<int32_t, int32_t> id;
  for (size_t f = 0; f < mesh.faces.size(); ++f)
    label[f] = id.try_emplace(find(int32_t(f)), int32_t(id.size())).first->second;
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

// The faces within @p rings vertex rings of the crossing faces, plus every island of other faces
// they enclose (a component, across edges, of the remaining faces that holds no border edge and
// is not the largest), so each component of the region is a disc when its boundary is one cycle.
std::vector<char> tangle_region(const TriangleMesh& mesh, const std::vector<char>& crossing, int rings) {
  const size_t nf = mesh.faces.size();
  std::vector<std::vector<int32_t>> vertex_faces(mesh.vertices.size());
  for (size_t f = 0; f < nf; ++f)
    for (int32_t v : mesh.faces[f]) vertex_faces[v].push_back(int32_t(f));
  std::vector<char> region = crossing;
  for (int r = 0; r < rings; ++r) {
    std::vector<char> grown = region;
    for (size_t f = 0; f < nf; ++f)
      if (region[f])
        for (int32_t v : mesh.faces[f])
          for (int32_t g : vertex_faces[v]) grown[g] = 1;
    region.swap(grown);
  }
  std::map<std::pair<int32_t, int32_t>, std::vector<int32_t>> edge_faces;
  for (size_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const int32_t a = mesh.faces[f][k], b = mesh.faces[f][(k + 1) % 3];
      edge_faces[{std::min(a, b), std::max(a, b)}].push_back(int32_t(f));
    }
  for (int round = 0; round < 8; ++round) {
    // Islands: components of the other faces that hold no border edge and are not the largest.
    std::vector<int32_t> component(nf, -1);
    std::vector<size_t> size;
    std::vector<char> on_border;
    for (size_t seed = 0; seed < nf; ++seed) {
      if (region[seed] || component[seed] >= 0) continue;
      const int32_t id = int32_t(size.size());
      size.push_back(0), on_border.push_back(0);
      std::vector<int32_t> stack{int32_t(seed)};
      component[seed] = id;
      while (!stack.empty()) {
        const int32_t f = stack.back();
        stack.pop_back();
        ++size[id];
        for (int k = 0; k < 3; ++k) {
          const int32_t a = mesh.faces[f][k], b = mesh.faces[f][(k + 1) % 3];
          const std::vector<int32_t>& around = edge_faces[{std::min(a, b), std::max(a, b)}];
          if (around.size() < 2) on_border[id] = 1;
          for (int32_t g : around)
            if (!region[g] && component[g] < 0) component[g] = id, stack.push_back(g);
        }
      }
    }
    const size_t largest = size.empty() ? 0 : size_t(std::max_element(size.begin(), size.end()) - size.begin());
    for (size_t f = 0; f < nf; ++f)
      if (!region[f] && component[f] != int32_t(largest) && !on_border[component[f]]) region[f] = 1;
    // Pinches: a vertex the region's boundary passes twice (the region touches itself, or the
    // mesh's border, there) takes all its faces.
    std::set<std::pair<int32_t, int32_t>> inside;
    for (size_t f = 0; f < nf; ++f)
      if (region[f])
        for (int k = 0; k < 3; ++k) inside.insert({mesh.faces[f][k], mesh.faces[f][(k + 1) % 3]});
    std::map<int32_t, int> outgoing;
    for (const auto& e : inside)
      if (!inside.count({e.second, e.first})) ++outgoing[e.first];
    bool grew = false;
    for (const auto& [v, n] : outgoing)
      if (n > 1)
        for (int32_t g : vertex_faces[v]) grew = grew || !region[g], region[g] = 1;
    if (!grew) break;
  }
  return region;
}

// @p mesh with the faces of @p region replaced by a triangulation of each boundary cycle of the
// region (CGAL's triangulate_hole_polyline: no new vertex), or false when a component of the
// region is not a disc away from the mesh's border, or a fill fails or doubles an edge.
bool refill_region(const TriangleMesh& mesh, const std::vector<char>& region, TriangleMesh& out,
                   std::vector<Tri>& fill) {
  using Directed = std::pair<int32_t, int32_t>;
  // The region's faces by their directed edges; its boundary: the edges whose twin is not in it.
  std::map<Directed, int32_t> face_of;
  for (size_t f = 0; f < mesh.faces.size(); ++f)
    if (region[f])
      for (int k = 0; k < 3; ++k) face_of[{mesh.faces[f][k], mesh.faces[f][(k + 1) % 3]}] = int32_t(f);
  auto other_edge_at = [&](int32_t f, int32_t v) {  // the edge of face f leaving v
    const Tri& t = mesh.faces[f];
    for (int k = 0; k < 3; ++k)
      if (t[k] == v) return Directed(v, t[(k + 1) % 3]);
    return Directed(-1, -1);
  };
  // After the boundary edge a -> b comes the boundary edge leaving b in the same fan of b (so a
  // vertex where the input's own border touches itself is passed once per fan).
  std::map<Directed, Directed> next;
  for (const auto& [e, f] : face_of) {
    if (face_of.count({e.second, e.first})) continue;
    int32_t g = f;
    Directed out_edge = other_edge_at(g, e.second);
    for (size_t guard = 0; face_of.count({out_edge.second, out_edge.first}); ++guard) {
      if (guard > face_of.size()) return false;
      g = face_of.at({out_edge.second, out_edge.first});
      out_edge = other_edge_at(g, e.second);
    }
    next[e] = out_edge;
  }
  // Each component of the region must be a disc (its pinches split): V - E + F = number of cycles.
  std::vector<std::vector<int32_t>> cycles;
  std::set<Directed> seen;
  for (const auto& [start, unused] : next) {
    if (seen.count(start)) continue;
    std::vector<int32_t> cycle;
    for (Directed e = start; !seen.count(e);) {
      if (!next.count(e)) return false;
      seen.insert(e);
      cycle.push_back(e.first);
      e = next.at(e);
    }
    cycles.push_back(std::move(cycle));
  }
  // A cycle through a pinch is split there into simple loops, each filled on its own.
  {
    std::vector<std::vector<int32_t>> loops;
    for (const std::vector<int32_t>& cycle : cycles) {
      std::vector<int32_t> stack;
      std::map<int32_t, size_t> at;
      for (int32_t v : cycle) {
        auto it = at.find(v);
        if (it != at.end()) {
          loops.emplace_back(stack.begin() + std::ptrdiff_t(it->second), stack.end());
          for (size_t i = it->second + 1; i < stack.size(); ++i) at.erase(stack[i]);
          stack.resize(it->second + 1);
          continue;
        }
        at[v] = stack.size();
        stack.push_back(v);
      }
      loops.push_back(std::move(stack));
    }
    cycles.swap(loops);
  }
  std::set<Directed> directed;
  for (const Tri& t : mesh.faces)
    for (int k = 0; k < 3; ++k) directed.insert({t[k], t[(k + 1) % 3]});
  fill.clear();
  for (const std::vector<int32_t>& cycle : cycles) {
    // A loop of the input's own border (a hole the region surrounds) stays open.
    bool border = true;
    for (size_t i = 0; i < cycle.size(); ++i)
      border = border && !directed.count({cycle[(i + 1) % cycle.size()], cycle[i]});
    if (border) continue;
    if (cycle.size() < 3) return false;
    std::vector<Point> polyline;
    for (int32_t v : cycle) polyline.emplace_back(mesh.vertices[v].x(), mesh.vertices[v].y(), mesh.vertices[v].z());
    std::vector<CGAL::Triple<int, int, int>> triangles;
    PMP::triangulate_hole_polyline(polyline, std::back_inserter(triangles));
    if (triangles.size() != cycle.size() - 2) return false;
    // The fill keeps the region's orientation: the boundary edge cycle[0] -> cycle[1] in order.
    bool flip = false;
    for (const auto& t : triangles) {
      const int c[3] = {t.first, t.second, t.third};
      for (int k = 0; k < 3; ++k) {
        if (c[k] == 0 && c[(k + 1) % 3] == 1) flip = false;
        if (c[k] == 1 && c[(k + 1) % 3] == 0) flip = true;
      }
    }
    for (const auto& t : triangles) {
      Tri tri{cycle[t.first], cycle[t.second], cycle[t.third]};
      if (flip) std::swap(tri[1], tri[2]);
      fill.push_back(tri);
    }
  }
  // Compact: the faces outside the region and the fills, unused vertices dropped.
  out = TriangleMesh{};
  std::vector<int32_t> index(mesh.vertices.size(), -1);
  auto add = [&](Tri t) {
    for (int32_t& v : t) {
      if (index[v] < 0) index[v] = int32_t(out.vertices.size()), out.vertices.push_back(mesh.vertices[v]);
      v = index[v];
    }
    out.faces.push_back(t);
  };
  for (size_t f = 0; f < mesh.faces.size(); ++f)
    if (!region[f]) add(mesh.faces[f]);
  for (const Tri& t : fill) add(t);
  std::map<std::pair<int32_t, int32_t>, int> uses;
  for (const Tri& t : out.faces)
    for (int k = 0; k < 3; ++k)
      if (t[k] == t[(k + 1) % 3] || ++uses[{t[k], t[(k + 1) % 3]}] > 1) return false;
  for (Tri& t : fill)
    for (int32_t& v : t) v = index[v];
  return true;
}

// A sheet crumpled in a few places (faces folded over their neighbours, overlapping triangles of
// a bad triangulation: the surface is there, only its triangulation crosses itself): each
// crumpled spot, grown by a few rings, is cut out and its boundary polygon triangulated again,
// with the fewest rings that leave no crossing. Accepted only if every removed input vertex lies
// within @p tolerance of the new faces and every new face (corners, edge midpoints, centroid)
// within @p tolerance of the input: the surface a user sees is unchanged.
bool retriangulate_tangles(const TriangleMesh& mesh, double tolerance, TriangleMesh& out, int64_t& removed_faces) {
  const std::vector<char> crossing = detail::crossing_faces(mesh);
  const ExactMeshQuery input(mesh);
  for (int rings = 1; rings <= kMaxTangleRings; ++rings) {
    const std::vector<char> region = tangle_region(mesh, crossing, rings);
    TriangleMesh candidate;
    std::vector<Tri> fill;
    if (!refill_region(mesh, region, candidate, fill)) continue;
    int64_t left = 0;
    detail::crossing_faces(candidate, &left);
    if (left > 0) continue;
    TriangleMesh fill_mesh;
    fill_mesh.vertices = candidate.vertices;
    fill_mesh.faces = fill;
    if (fill.empty()) continue;
    const ExactMeshQuery patch(fill_mesh);
    bool close = true;
    std::vector<char> kept_vertex(mesh.vertices.size(), 0);
    for (size_t f = 0; f < mesh.faces.size(); ++f)
      if (!region[f])
        for (int32_t v : mesh.faces[f]) kept_vertex[v] = 1;
    for (size_t f = 0; f < mesh.faces.size() && close; ++f)
      if (region[f])
        for (int32_t v : mesh.faces[f])
          if (!kept_vertex[v]) close = close && patch.closest_point(mesh.vertices[v]).distance <= tolerance;
    for (const Tri& t : fill) {
      if (!close) break;
      const Vec3 a = candidate.vertices[t[0]], b = candidate.vertices[t[1]], c = candidate.vertices[t[2]];
      for (const Vec3& p : {Vec3((a + b) / 2), Vec3((b + c) / 2), Vec3((c + a) / 2), Vec3((a + b + c) / 3)})
        close = close && input.closest_point(p).distance <= tolerance;
    }
    if (!close) continue;
    removed_faces = std::count(region.begin(), region.end(), char(1));
    out = std::move(candidate);
    return true;
  }
  return false;
}

}  // namespace

TriangleMesh resolve_crossing_sheets(const TriangleMesh& mesh, SelfIntersectionReport* report) {
  validate_mesh_data(mesh, "resolve_crossing_sheets input");
  SelfIntersectionReport rep;
  rep.faces_before = rep.faces_after = static_cast<int64_t>(mesh.faces.size());
  auto keep = [&] {
    if (report) *report = rep;
    return mesh;
  };
  if (analyze_topology(mesh).boundary_edges == 0) return keep();
  rep.pairs_before = rep.pairs_after = crossing_pairs(detail::to_surface_mesh<Mesh>(mesh));
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
    // One closed surface now. What still crosses (folds inside a patch: pig.stl has three) is
    // left as the input has it; the closed union's refinement is not tried on it (CGAL 5.5's
    // autorefine crashes on some such surfaces).
    rep.pairs_after = crossing_pairs(detail::to_surface_mesh<Mesh>(stitched));
    if (rep.pairs_after >= rep.pairs_before) {
      rep.pairs_after = rep.pairs_before;
      return keep();
    }
    rep.faces_after = static_cast<int64_t>(stitched.faces.size());
    rep.resolved = true;
    if (report) *report = rep;
    return stitched;
  }
  int32_t count = 0;
  const std::vector<int32_t> sheet = sheet_of_faces(work, count);
  std::vector<Mesh> sheets;
  for (int32_t s = 0; s < count; ++s) sheets.push_back(sheet_mesh(work, sheet, s));
  for (const Mesh& m : sheets)
    if (PMP::does_self_intersect<CGAL::Parallel_if_available_tag>(m)) {
      // A sheet that crosses itself. CGAL 5.5's autorefine() would split it along its own curves,
      // but crashes on some real sheets (polygon_mesh.off with its holes filled): instead, its
      // crumpled spots are triangulated again, when that resolves every crossing within the
      // tolerance; else the input is kept.
      TriangleMesh untangled;
      if (!retriangulate_tangles(work, kTangleTolerance * bounds(work).diagonal(), untangled, rep.retriangulated_faces))
        return keep();
      rep.pairs_after = 0;
      rep.faces_after = static_cast<int64_t>(untangled.faces.size());
      rep.resolved = true;
      if (report) *report = rep;
      return untangled;
    }
  std::vector<Mesh::Property_map<Edge, bool>> curve;
  for (Mesh& m : sheets) curve.push_back(m.add_property_map<Edge, bool>("e:hdm_curve", false).first);
  try {
    for (size_t i = 0; i < sheets.size(); ++i)
      for (size_t j = i + 1; j < sheets.size(); ++j) {
        if (!CGAL::do_overlap(CGAL::Polygon_mesh_processing::bbox(sheets[i]), PMP::bbox(sheets[j]))) continue;
        PMP::corefine(sheets[i], sheets[j], CGAL::parameters::edge_is_constrained_map(curve[i]),
                      CGAL::parameters::edge_is_constrained_map(curve[j]));
      }
  } catch (const std::exception&) {
    return keep();  // a configuration CGAL does not handle: bake the input as it is
  }
  // Patches: faces joined across edges that are neither a curve nor a border; each is voted
  // buried or exposed as a whole, so a sliver at a curve cannot flip on its own.
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
    std::vector<double> buried_area, area;
    for (Face seed : m.faces()) {
      if (patch[seed] >= 0) continue;
      const int32_t id = int32_t(area.size());
      area.push_back(0), buried_area.push_back(0);
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
          if (winding.inside((c[0] + c[1] + c[2]) / 3.0 + eps * n / a)) buried_area[id] += a;
        }
        for (auto h : CGAL::halfedges_around_face(m.halfedge(f), m)) {
          if (curve[s][m.edge(h)] || m.is_border(m.opposite(h))) continue;
          const Face g = m.face(m.opposite(h));
          if (patch[g] < 0) patch[g] = id, stack.push_back(g);
        }
      }
    }
    for (Face f : m.faces()) {
      if (2 * buried_area[patch[f]] >= area[patch[f]] && area[patch[f]] > 0) {
        ++rep.buried_faces;
        continue;
      }
      Tri t{};
      int k = 0;
      for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) t[k++] = weld(m.point(v));
      if (t[0] != t[1] && t[1] != t[2] && t[2] != t[0]) out.faces.push_back(t);
    }
  }
  if (out.faces.empty()) return keep();
  // The kept patches must meet two by two along the curves, front to back.
  {
    std::map<std::pair<int32_t, int32_t>, int> uses;
    for (const Tri& t : out.faces)
      for (int k = 0; k < 3; ++k) ++uses[{t[k], t[(k + 1) % 3]}];
    for (const auto& [e, n] : uses)
      if (n > 1) return keep();
  }
  // Patches that touch at a point leave a pinch: one copy of the vertex per fan (CGAL's soup
  // orientation splits them), each moved 1% towards its own fan's ring so the copies do not
  // coincide (the bake finds no room for a shell between coincident corners), as
  // resolve_self_intersections() does for closed unions.
  std::vector<Point> soup_points;
  std::vector<std::vector<std::size_t>> polygons;
  detail::to_polygon_soup(out, soup_points, polygons);
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
  rep.pairs_after = crossing_pairs(result);
  if (rep.pairs_after > 0) {
    rep.pairs_after = rep.pairs_before;
    return keep();
  }
  TriangleMesh resolved = detail::to_triangle_mesh(result, "resolve_crossing_sheets");
  rep.faces_after = static_cast<int64_t>(resolved.faces.size());
  rep.resolved = true;
  if (report) *report = rep;
  return resolved;
}

}  // namespace hdm
