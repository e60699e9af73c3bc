// SPDX-License-Identifier: MIT
// Hole filling for repair_mesh(): which boundary cycles to close, a flat minimal-area fill of each,
// refined and faired, kept only where it crosses nothing. A CGAL translation unit (heavy templates).
#include "fill_holes.h"
#include "disjoint_sets.h"

#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/fair.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/refine.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <vector>

namespace hdm::mesh::detail {

namespace PMP = CGAL::Polygon_mesh_processing;
using Mesh = SurfaceMesh;

namespace {

// A component whose every boundary cycle spans at most this fraction of the component's diagonal is
// a closed model with holes cut into it (elephant-with-holes.off: 106 holes, the largest 23 % of the
// diagonal): all its holes are filled. A real open boundary (a bust's neck, a face mask's rim, a
// terrain's edge) spans 30 % to 100 % of its model.
constexpr double kClosedButForHoles = 0.25;

// A boundary cycle of the soup: its vertices in border order (the faces' own edges run the other way).
struct Hole {
  std::vector<std::size_t> loop;
  double extent = 0;  // bounding-box diagonal of the loop [model units]
  std::size_t component = 0;
  bool fillable = true;  // false: the border is not a single walk there
};

Vec3 vec(const Point& p) { return Vec3(p.x(), p.y(), p.z()); }

// Boundary cycles of a consistently oriented, vertex-manifold soup (orient_polygon_soup() split each
// pinched vertex into one copy per fan, at the same position). At a position split into exactly two
// border copies, the cycle goes on from the sibling copy: it follows the gap between the two fans
// (the hole) instead of going round a fan into the next hole, so that once both holes are filled the
// two copies are one manifold vertex again (elephant-with-holes.off: 65 such pinches).
std::vector<Hole> boundary_holes(const std::vector<Point>& points, const Soup& polygons,
                                 std::vector<std::size_t>& component) {
  std::vector<std::pair<std::size_t, std::size_t>> edges;
  edges.reserve(3 * polygons.size());
  for (const auto& f : polygons)
    for (std::size_t k = 0; k < f.size(); ++k) edges.emplace_back(f[k], f[(k + 1) % f.size()]);
  std::sort(edges.begin(), edges.end());
  std::map<std::size_t, std::size_t> out;  // border edge start -> end
  std::set<std::size_t> ambiguous;
  for (const auto& [a, b] : edges)
    if (!std::binary_search(edges.begin(), edges.end(), std::make_pair(b, a)))
      if (!out.emplace(b, a).second) ambiguous.insert(b);
  // Siblings: the two border copies of a split position.
  std::map<Point, std::vector<std::size_t>> at;
  for (const auto& [v, w] : out) at[points[v]].push_back(v);
  std::map<std::size_t, std::size_t> sibling;
  for (const auto& [p, vs] : at)
    if (vs.size() == 2) sibling[vs[0]] = vs[1], sibling[vs[1]] = vs[0];
  // Components, joined at split positions.
  DisjointSets<std::size_t> sets(points.size());
  for (const auto& f : polygons)
    for (std::size_t k = 1; k < f.size(); ++k) sets.unite(f[k], f[0]);
  std::map<Point, std::size_t> first_at;
  for (std::size_t v = 0; v < points.size(); ++v) {
    const auto [it, fresh] = first_at.emplace(points[v], v);
    if (!fresh) sets.unite(v, it->second);
  }
  component.resize(points.size());
  for (std::size_t v = 0; v < points.size(); ++v) component[v] = sets.find(v);

  std::vector<Hole> holes;
  std::set<std::size_t> seen;
  for (const auto& [start, unused] : out) {
    if (seen.count(start)) continue;
    Hole h;
    h.component = component[start];
    Aabb box;
    std::size_t cur = start;
    do {
      seen.insert(cur);
      h.loop.push_back(cur);
      if (ambiguous.count(cur)) h.fillable = false;
      box.extend(vec(points[cur]));
      const std::size_t end = out.at(cur);
      const auto s = sibling.find(end);
      cur = s != sibling.end() ? s->second : end;
      if (!out.count(cur)) {  // cannot happen in a vertex-manifold soup; do not fill what we cannot walk
        h.fillable = false;
        break;
      }
    } while (cur != start && !seen.count(cur));
    if (cur != start) h.fillable = false;
    h.extent = box.diagonal();
    holes.push_back(std::move(h));
  }
  return holes;
}

// @p loop split at the positions it passes twice (a hole that touches itself at a pinch) into
// loops that pass each position once.
std::vector<std::vector<std::size_t>> simple_loops(const std::vector<Point>& points,
                                                   const std::vector<std::size_t>& loop) {
  std::map<Point, std::size_t> at;
  for (std::size_t j = 0; j < loop.size(); ++j) {
    const auto [it, fresh] = at.emplace(points[loop[j]], j);
    if (fresh) continue;
    const std::size_t i = it->second;
    std::vector<std::size_t> inner(loop.begin() + i, loop.begin() + j), outer(loop.begin(), loop.begin() + i);
    outer.insert(outer.end(), loop.begin() + j, loop.end());
    auto a = simple_loops(points, inner), b = simple_loops(points, outer);
    a.insert(a.end(), b.begin(), b.end());
    return a;
  }
  return {loop};
}

// Appends to @p patch a minimal-area triangulation of @p loop (triangulate_hole_polyline, Liepa
// 2003), oriented as the faces around it: it runs along each border edge (loop[k], loop[k+1]).
// False when there is none.
bool triangulate_loop(const std::vector<Point>& points, const std::vector<std::size_t>& loop, Soup& patch) {
  if (loop.size() < 3) return false;
  std::vector<Point> line;
  for (std::size_t v : loop) line.push_back(points[v]);
  std::vector<CGAL::Triple<int, int, int>> tris;
  PMP::triangulate_hole_polyline(line, std::back_inserter(tris));
  if (tris.empty()) return false;
  const int n = static_cast<int>(loop.size());
  bool flip = false;
  for (const auto& t : tris) {
    const int c[3] = {t.first, t.second, t.third};
    bool found = false;
    for (int k = 0; k < 3 && !found; ++k) {
      if (c[(k + 1) % 3] == (c[k] + 1) % n)
        found = true;  // along the border: kept
      else if (c[k] == (c[(k + 1) % 3] + 1) % n)
        found = flip = true;  // against it
    }
    if (found) break;
  }
  for (const auto& t : tris) {
    if (flip)
      patch.push_back({loop[t.first], loop[t.third], loop[t.second]});
    else
      patch.push_back({loop[t.first], loop[t.second], loop[t.third]});
  }
  return true;
}

// True when @p loop lies in a plane, to 1 % of its extent: when its fill in the soup crossed, such a
// hole (the cut end of an extruded part) is tried flat first in the mesh, a curved one faired first.
bool planar(const std::vector<Point>& loop) {
  Vec3 c = Vec3::Zero();
  Aabb box;
  for (const Point& p : loop) c += vec(p) / double(loop.size()), box.extend(vec(p));
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const Point& p : loop) cov += (vec(p) - c) * (vec(p) - c).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  const Vec3 n = eig.eigenvectors().col(0);  // the smallest eigenvalue's: the plane's normal
  double off = 0;
  for (const Point& p : loop) off = std::max(off, std::abs((vec(p) - c).dot(n)));
  return off <= 0.01 * box.diagonal();
}

// True when a face of @p patch crosses another face of @p sm (exact predicates; faces sharing a
// vertex or an edge cross only where they meet elsewhere). O(#F) to gather the faces near the patch,
// then CGAL's box intersection on those.
bool patch_crosses(const Mesh& sm, const std::vector<Mesh::Face_index>& patch) {
  std::vector<uint8_t> in_patch(sm.num_faces(), 0);
  CGAL::Bbox_3 box;
  for (Mesh::Face_index f : patch) {
    in_patch[f] = 1;
    for (Mesh::Vertex_index v : CGAL::vertices_around_face(sm.halfedge(f), sm)) box += sm.point(v).bbox();
  }
  std::vector<Mesh::Face_index> near(patch);
  for (Mesh::Face_index f : sm.faces()) {
    if (in_patch[f]) continue;
    CGAL::Bbox_3 fb;
    for (Mesh::Vertex_index v : CGAL::vertices_around_face(sm.halfedge(f), sm)) fb += sm.point(v).bbox();
    if (CGAL::do_overlap(fb, box)) near.push_back(f);
  }
  std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> pairs;
  PMP::self_intersections(near, sm, std::back_inserter(pairs));
  for (const auto& [f, g] : pairs)
    if (in_patch[f] || in_patch[g]) return true;
  return false;
}

// Where holes could not be filled, the copies of a pinched vertex (one per fan) still coincide, so
// the fans touch and each copy's slab has no room: each copy moves by 1 % towards the centroid of
// its own fan's ring, as resolve_self_intersections() does for the pinches of a union.
void separate_pinches(Mesh& sm) {
  std::map<Point, std::vector<Mesh::Vertex_index>> at;
  for (Mesh::Vertex_index v : sm.vertices()) at[sm.point(v)].push_back(v);
  std::vector<std::pair<Mesh::Vertex_index, Point>> moved;
  for (const auto& [p, copies] : at) {
    if (copies.size() < 2) continue;
    for (Mesh::Vertex_index v : copies) {
      Vec3 r = Vec3::Zero();
      int n = 0;
      for (Mesh::Vertex_index w : CGAL::vertices_around_target(sm.halfedge(v), sm)) r += vec(sm.point(w)), ++n;
      if (n == 0) continue;
      const Vec3 q = vec(p) + 0.01 * (r / n - vec(p));
      moved.emplace_back(v, Point(q.x(), q.y(), q.z()));
    }
  }
  for (const auto& [v, q] : moved) sm.point(v) = q;
}

// The flat fill of each hole to close (a minimal-area triangulation of each simple loop, Liepa
// 2003): small holes (RepairOptions::max_hole_edges, max_hole_size of @p diag) and every hole of a
// component that is closed but for holes; the outline of a patch with no interior vertex is no
// hole. @p wanted gets the positions on every hole to close, fillable flat or not.
std::vector<Soup> flat_patches(const std::vector<Point>& points, const Soup& polygons, const std::vector<Hole>& holes,
                               const std::vector<std::size_t>& component, double diag, const RepairOptions& options,
                               std::set<Point>& wanted) {
  // The largest hole of each component against the component's size.
  std::map<std::size_t, Aabb> component_box;
  for (const auto& f : polygons)
    for (std::size_t v : f) component_box[component[v]].extend(vec(points[v]));
  std::map<std::size_t, double> largest;
  for (const Hole& h : holes) largest[h.component] = std::max(largest[h.component], h.extent);
  // Vertices of each component, to tell a hole from a patch's outline.
  std::map<std::size_t, std::size_t> component_vertices;
  std::vector<uint8_t> used(points.size(), 0);
  for (const auto& f : polygons)
    for (std::size_t v : f)
      if (!used[v]) used[v] = 1, ++component_vertices[component[v]];
  std::vector<Soup> patches;
  for (const Hole& h : holes) {
    // A cycle through every vertex of its component is the outline of a patch with no interior
    // vertex (a lone triangle, a strip), not a hole in a surface: its fill would be a second copy of
    // the patch, back to back with it, enclosing nothing (b9_mesh.off's stray triangles), and such a
    // closed part of no thickness has no valid slab. The patch stays an open sheet.
    if (std::set<std::size_t>(h.loop.begin(), h.loop.end()).size() == component_vertices[h.component]) continue;
    const bool small =
        static_cast<int>(h.loop.size()) <= options.max_hole_edges && h.extent <= options.max_hole_size * diag;
    const bool closed_model = largest[h.component] <= kClosedButForHoles * component_box[h.component].diagonal();
    if (options.max_hole_edges <= 0 || !(small || closed_model) || h.loop.size() < 3) continue;
    // Wanted: if no flat fill makes it, a faired fill in the mesh is tried (fill_in_mesh()).
    for (std::size_t v : h.loop) wanted.insert(points[v]);
    if (!h.fillable) continue;
    Soup patch;
    for (const auto& loop : simple_loops(points, h.loop))
      if (!triangulate_loop(points, loop, patch)) patch.clear();
    if (patch.empty()) continue;
    patches.push_back(std::move(patch));
  }
  return patches;
}

// One vertex per position again: copies whose holes are all filled are manifold once merged;
// orient_polygon_soup splits the others anew.
void merge_copies(const std::vector<Point>& points, Soup& polygons, std::vector<Soup>& patches) {
  std::map<Point, std::size_t> first_at;
  std::vector<std::size_t> merged(points.size());
  for (std::size_t v = 0; v < points.size(); ++v) merged[v] = first_at.emplace(points[v], v).first->second;
  for (auto& f : polygons)
    for (auto& v : f) v = merged[v];
  for (auto& p : patches)
    for (auto& f : p)
      for (auto& v : f) v = merged[v];
}

// Marks in @p rejected the patches of @p sm (patch i: faces first[i] ..) that cross another face,
// or whose refinement (refine, to the surrounding density) does; fairs the others (fair, undone
// where the faired patch crosses). Returns whether it rejected one (the mesh is then rebuilt).
bool reject_crossing_patches(Mesh& sm, const std::vector<Soup>& patches, const std::vector<std::size_t>& first,
                             std::vector<uint8_t>& rejected) {
  auto faces_of = [&](std::size_t i) {
    std::vector<Mesh::Face_index> fs;
    for (std::size_t k = 0; k < patches[i].size(); ++k) fs.push_back(Mesh::Face_index(Mesh::size_type(first[i] + k)));
    return fs;
  };
  bool again = false;
  for (std::size_t i = 0; i < patches.size(); ++i)
    if (!rejected[i] && patch_crosses(sm, faces_of(i))) rejected[i] = again = true;
  if (again) return true;
  for (std::size_t i = 0; i < patches.size(); ++i) {
    if (rejected[i]) continue;
    std::vector<Mesh::Face_index> fs = faces_of(i), new_faces;
    std::vector<Mesh::Vertex_index> new_vertices;
    PMP::refine(sm, std::vector<Mesh::Face_index>(fs), std::back_inserter(new_faces), std::back_inserter(new_vertices),
                CGAL::parameters::density_control_factor(std::sqrt(2.0)));
    fs.insert(fs.end(), new_faces.begin(), new_faces.end());
    if (patch_crosses(sm, fs)) {  // refinement flips edges: the patch is no longer the flat one
      rejected[i] = true;
      return true;
    }
    if (new_vertices.empty()) continue;
    std::vector<Point> flat;
    for (Mesh::Vertex_index v : new_vertices) flat.push_back(sm.point(v));
    if (PMP::fair(sm, new_vertices) && patch_crosses(sm, fs))
      for (std::size_t k = 0; k < new_vertices.size(); ++k) sm.point(new_vertices[k]) = flat[k];
  }
  return false;
}

// A hole whose flat fill crosses the mesh (it cuts through a curved part) or that has no flat
// fill (it touches itself): a refined and faired fill in the mesh, kept when it crosses nothing.
// Only boundary cycles all of whose positions are in @p wanted. Returns the holes filled.
int fill_in_mesh(Mesh& sm, const std::set<Point>& wanted) {
  int filled = 0;
  std::vector<Mesh::Halfedge_index> cycles;
  PMP::extract_boundary_cycles(sm, std::back_inserter(cycles));
  for (Mesh::Halfedge_index h : cycles) {
    bool all = true;
    for (Mesh::Halfedge_index k : CGAL::halfedges_around_face(h, sm)) all = all && wanted.count(sm.point(sm.target(k)));
    if (!all) continue;
    // A planar hole first flat (a constrained Delaunay triangulation, which the polyline search
    // misses on concave outlines: blade.off's ends), a curved one first faired.
    std::vector<Point> line;
    for (Mesh::Halfedge_index k : CGAL::halfedges_around_face(h, sm)) line.push_back(sm.point(sm.target(k)));
    const bool flat_first = planar(line);
    for (int attempt = 0; attempt < 2; ++attempt) {
      const bool faired = (attempt == 0) != flat_first;
      std::vector<Mesh::Face_index> fs;
      std::vector<Mesh::Vertex_index> vs;
      if (faired)
        PMP::triangulate_refine_and_fair_hole(sm, h, std::back_inserter(fs), std::back_inserter(vs));
      else
        PMP::triangulate_and_refine_hole(sm, h, std::back_inserter(fs), std::back_inserter(vs));
      if (fs.empty()) continue;
      if (!patch_crosses(sm, fs)) {
        ++filled;
        break;
      }
      for (Mesh::Face_index f : fs) CGAL::Euler::remove_face(sm.halfedge(f), sm);
    }
  }
  return filled;
}

}  // namespace

// Fills the chosen boundary cycles of the soup: a minimal-area triangulation of each (Liepa 2003,
// triangulate_hole_polyline), refined to the surrounding density (refine) and faired (fair:
// tangent-continuous), each step kept only when the patch crosses no other face; a cycle no fill
// leaves uncrossed stays open. Returns the mesh.
SurfaceMesh fill_holes(std::vector<Point>& points, Soup& polygons, double diag, const RepairOptions& options,
                       RepairReport& rep) {
  std::vector<std::size_t> component;
  const std::vector<Hole> holes = boundary_holes(points, polygons, component);
  std::set<Point> wanted;  // positions on the holes to fill
  std::vector<Soup> patches = flat_patches(points, polygons, holes, component, diag, options, wanted);
  rep.open_boundaries = static_cast<int>(holes.size() - patches.size());
  merge_copies(points, polygons, patches);
  std::vector<uint8_t> rejected(patches.size(), 0);
  for (;;) {
    std::vector<Point> pts = points;
    Soup polys = polygons;
    std::vector<std::size_t> first(patches.size(), 0);
    for (std::size_t i = 0; i < patches.size(); ++i) {
      first[i] = polys.size();
      if (!rejected[i]) polys.insert(polys.end(), patches[i].begin(), patches[i].end());
    }
    PMP::remove_isolated_points_in_polygon_soup(pts, polys);
    const std::size_t before_split = pts.size();
    PMP::orient_polygon_soup(pts, polys);
    SurfaceMesh sm;
    PMP::polygon_soup_to_polygon_mesh(pts, polys, sm);
    separate_pinches(sm);  // else a fill through a pinch would touch the other copy
    if (reject_crossing_patches(sm, patches, first, rejected)) continue;
    int filled = 0;
    for (uint8_t r : rejected) filled += !r;
    rep.open_boundaries += static_cast<int>(patches.size()) - filled;
    if (rep.open_boundaries > 0) {
      const int in_mesh = fill_in_mesh(sm, wanted);
      filled += in_mesh;
      rep.open_boundaries -= in_mesh;
    }
    rep.filled_holes = filled;
    rep.added_faces = static_cast<int64_t>(sm.number_of_faces()) - static_cast<int64_t>(polygons.size());
    rep.split_vertices = static_cast<int64_t>(pts.size() - before_split);
    return sm;
  }
}

}  // namespace hdm::mesh::detail
