// SPDX-License-Identifier: MIT
// Crumpled spots of a sheet cut out and triangulated again (see retriangulate_tangles.h). A CGAL
// translation unit (heavy templates).
#include "retriangulate_tangles.h"

#include <hdm/mesh/exact_mesh_query.h>

#include "self_intersecting_faces.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>

#include <algorithm>
#include <map>
#include <set>
#include <vector>

namespace hdm::mesh::detail {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Point = CGAL::Exact_predicates_inexact_constructions_kernel::Point_3;

// Most vertex rings grown around a crumpled spot before retriangulate_tangles() gives up.
constexpr int kMaxTangleRings = 6;

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

using Directed = std::pair<int32_t, int32_t>;

// The boundary cycles of @p region (vertex loops in border order), or false when the boundary is
// not a set of cycles (a component of the region is no disc with its pinches split).
bool region_cycles(const TriangleMesh& mesh, const std::vector<char>& region,
                   std::vector<std::vector<int32_t>>& cycles) {
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
  return true;
}

// A cycle through a pinch is split there into simple loops, each filled on its own.
std::vector<std::vector<int32_t>> simple_loops(const std::vector<std::vector<int32_t>>& cycles) {
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
  return loops;
}

// A triangulation of each loop (CGAL's triangulate_hole_polyline: no new vertex) in the region's
// orientation, appended to @p fill; loops of the input's own border (a hole the region surrounds)
// stay open. False when a fill fails.
bool fill_loops(const TriangleMesh& mesh, const std::vector<std::vector<int32_t>>& cycles, std::vector<Tri>& fill) {
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
  return true;
}

// @p mesh with the faces of @p region replaced by @p fill, unused vertices dropped, in @p out;
// @p fill renumbered to @p out's vertices. False when an edge would have two faces in one direction.
bool replace_region(const TriangleMesh& mesh, const std::vector<char>& region, std::vector<Tri>& fill,
                    TriangleMesh& out) {
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

// @p mesh with the faces of @p region replaced by a triangulation of each boundary cycle of the
// region (CGAL's triangulate_hole_polyline: no new vertex), or false when a component of the
// region is not a disc away from the mesh's border, or a fill fails or doubles an edge.
bool refill_region(const TriangleMesh& mesh, const std::vector<char>& region, TriangleMesh& out,
                   std::vector<Tri>& fill) {
  std::vector<std::vector<int32_t>> cycles;
  if (!region_cycles(mesh, region, cycles)) return false;
  return fill_loops(mesh, simple_loops(cycles), fill) && replace_region(mesh, region, fill, out);
}

}  // namespace

bool retriangulate_tangles(const TriangleMesh& mesh, double tolerance, TriangleMesh& out, int64_t& removed_faces) {
  const std::vector<char> crossing = mesh::detail::self_intersecting_faces(mesh);
  const ExactMeshQuery input(mesh);
  for (int rings = 1; rings <= kMaxTangleRings; ++rings) {
    const std::vector<char> region = tangle_region(mesh, crossing, rings);
    TriangleMesh candidate;
    std::vector<Tri> fill;
    if (!refill_region(mesh, region, candidate, fill)) continue;
    int64_t left = 0;
    mesh::detail::self_intersecting_faces(candidate, &left);
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

}  // namespace hdm::mesh::detail
