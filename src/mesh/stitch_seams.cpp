// SPDX-License-Identifier: MIT
// T-junction seams: insert boundary vertices into the boundary edges they lie on, then weld.
#include <hdm/mesh/stitch_seams.h>
#include "disjoint_sets.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <tuple>
#include <unordered_map>
#include <vector>

namespace hdm {
namespace {

using EdgeKey = std::pair<int32_t, int32_t>;

// Faces on welded vertices (one id per exact position), degenerate ones dropped.
TriangleMesh weld(const TriangleMesh& mesh) {
  TriangleMesh out;
  std::map<std::array<double, 3>, int32_t> id;
  std::vector<int32_t> map(mesh.vertices.size(), -1);
  for (const Tri& t : mesh.faces)
    for (int32_t v : t) {
      if (map[v] >= 0) continue;
      const Vec3& p = mesh.vertices[v];
      auto [it, fresh] = id.try_emplace({p.x(), p.y(), p.z()}, int32_t(out.vertices.size()));
      if (fresh) out.vertices.push_back(p);
      map[v] = it->second;
    }
  for (const Tri& t : mesh.faces) {
    const Tri w{map[t[0]], map[t[1]], map[t[2]]};
    if (w[0] != w[1] && w[1] != w[2] && w[2] != w[0]) out.faces.push_back(w);
  }
  return out;
}

std::map<EdgeKey, int> edge_uses(const TriangleMesh& m) {
  std::map<EdgeKey, int> uses;
  for (const Tri& t : m.faces)
    for (int k = 0; k < 3; ++k) ++uses[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}];
  return uses;
}

int64_t count_boundary(const std::map<EdgeKey, int>& uses) {
  return std::count_if(uses.begin(), uses.end(), [](const auto& u) { return u.second == 1; });
}

bool edge_manifold(const std::map<EdgeKey, int>& uses) {
  return std::all_of(uses.begin(), uses.end(), [](const auto& u) { return u.second <= 2; });
}

// Boundary vertices of different sheets (faces joined by edges) that nearly coincide, within
// kSnap of the shorter boundary edge at either, become one vertex (at the position of the one
// with the lower index). Pairs are taken nearest first; a cluster never holds two vertices of one
// sheet, so no face collapses. @p snapped counts the vertices merged away.
constexpr double kSnap = 0.05;

TriangleMesh snap_near_vertices(const TriangleMesh& m, const std::map<EdgeKey, int>& uses, int64_t& snapped) {
  snapped = 0;
  const size_t nv = m.vertices.size();
  std::vector<double> shortest(nv, INFINITY);
  std::vector<double> lengths;
  for (const auto& [e, n] : uses) {
    if (n != 1) continue;
    const double l = (m.vertices[e.first] - m.vertices[e.second]).norm();
    shortest[e.first] = std::min(shortest[e.first], l);
    shortest[e.second] = std::min(shortest[e.second], l);
    lengths.push_back(l);
  }
  if (lengths.empty()) return m;
  std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
  const double cell = lengths[lengths.size() / 2];
  if (!(cell > 0)) return m;
  // Sheet of each vertex (union-find over vertices joined by a face).
  mesh::detail::DisjointSets<> sets(nv);
  for (const Tri& t : m.faces) sets.unite(t[1], t[0]), sets.unite(t[2], t[0]);
  std::vector<int32_t> sheet(nv);
  for (size_t i = 0; i < nv; ++i) sheet[i] = sets.find(int32_t(i));
  // Candidate pairs from a grid of median-length cells (the snap distance is capped at one cell).
  auto key = [&](const Vec3& p) {
    const Vec3 q = (p / cell).array().floor();
    return std::array<int64_t, 3>{int64_t(q.x()), int64_t(q.y()), int64_t(q.z())};
  };
  std::map<std::array<int64_t, 3>, std::vector<int32_t>> grid;
  for (size_t v = 0; v < nv; ++v)
    if (std::isfinite(shortest[v])) grid[key(m.vertices[v])].push_back(int32_t(v));
  std::vector<std::tuple<double, int32_t, int32_t>> pairs;
  for (size_t v = 0; v < nv; ++v) {
    if (!std::isfinite(shortest[v])) continue;
    const auto k = key(m.vertices[v]);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = grid.find({k[0] + dx, k[1] + dy, k[2] + dz});
          if (it == grid.end()) continue;
          for (int32_t u : it->second) {
            if (u <= int32_t(v) || sheet[u] == sheet[v]) continue;
            const double d = (m.vertices[u] - m.vertices[v]).norm();
            if (d <= std::min(cell, kSnap * std::min(shortest[u], shortest[v]))) pairs.emplace_back(d, int32_t(v), u);
          }
        }
  }
  if (pairs.empty()) return m;
  std::sort(pairs.begin(), pairs.end());
  // Clusters: a representative and the sheets it holds.
  std::vector<int32_t> rep(nv);
  for (size_t i = 0; i < nv; ++i) rep[i] = int32_t(i);
  std::vector<std::vector<int32_t>> sheets(nv);
  for (size_t i = 0; i < nv; ++i) sheets[i] = {sheet[i]};
  auto root = [&](int32_t v) {
    while (rep[v] != v) v = rep[v] = rep[rep[v]];
    return v;
  };
  for (const auto& [d, v, u] : pairs) {
    int32_t a = root(v), b = root(u);
    if (a == b) continue;
    bool shared = false;
    for (int32_t s : sheets[b]) shared |= std::find(sheets[a].begin(), sheets[a].end(), s) != sheets[a].end();
    if (shared) continue;
    if (b < a) std::swap(a, b);
    rep[b] = a;
    sheets[a].insert(sheets[a].end(), sheets[b].begin(), sheets[b].end());
    ++snapped;
  }
  TriangleMesh out;
  out.vertices = m.vertices;
  for (const Tri& t : m.faces) {
    const Tri w{root(t[0]), root(t[1]), root(t[2])};
    if (w[0] != w[1] && w[1] != w[2] && w[2] != w[0]) out.faces.push_back(w);
  }
  return out;
}

// A boundary edge with its face and the corner it starts at (face order a -> b).
struct BoundaryEdge {
  int32_t face, corner, a, b;
};

std::vector<BoundaryEdge> boundary_edges(const TriangleMesh& m, const std::map<EdgeKey, int>& uses) {
  std::vector<BoundaryEdge> edges;
  for (size_t f = 0; f < m.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int32_t a = m.faces[f][k], b = m.faces[f][(k + 1) % 3];
      if (uses.at({std::min(a, b), std::max(a, b)}) == 1) edges.push_back({int32_t(f), k, a, b});
    }
  return edges;
}

// Uniform grid over the boundary edges, cells of the median boundary edge length; each edge is
// listed in every cell its box grown by a quarter of its length meets (the farthest a vertex
// stitched into it can be), so a vertex looks in its own cell only. An edge that would cover
// more than 4,096 cells (far longer than its neighbours) is not stitched into.
struct EdgeGrid {
  struct Hash {
    size_t operator()(const std::array<int64_t, 3>& k) const {
      return size_t(k[0] * 73856093) ^ size_t(k[1] * 19349663) ^ size_t(k[2] * 83492791);
    }
  };
  double cell = 0;
  std::unordered_map<std::array<int64_t, 3>, std::vector<int32_t>, Hash> cells;

  std::array<int64_t, 3> key(const Vec3& p) const {
    const Vec3 q = (p / cell).array().floor();
    return std::array<int64_t, 3>{int64_t(q.x()), int64_t(q.y()), int64_t(q.z())};
  }
  // The edges listed in p's cell, or null.
  const std::vector<int32_t>* near(const Vec3& p) const {
    const auto it = cells.find(key(p));
    return it == cells.end() ? nullptr : &it->second;
  }
};

// The grid, with cell 0 when the median edge has no length.
EdgeGrid edge_grid(const TriangleMesh& m, const std::vector<BoundaryEdge>& edges) {
  EdgeGrid g;
  std::vector<double> lengths;
  for (const BoundaryEdge& e : edges) lengths.push_back((m.vertices[e.b] - m.vertices[e.a]).norm());
  std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
  g.cell = lengths[lengths.size() / 2];
  if (!(g.cell > 0)) return g;
  for (size_t i = 0; i < edges.size(); ++i) {
    const Vec3 &a = m.vertices[edges[i].a], &b = m.vertices[edges[i].b];
    const Vec3 grow = Vec3::Constant(0.25 * (b - a).norm());
    const auto lo = g.key(a.cwiseMin(b) - grow), hi = g.key(a.cwiseMax(b) + grow);
    if ((hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1) > 4096) continue;
    for (int64_t x = lo[0]; x <= hi[0]; ++x)
      for (int64_t y = lo[1]; y <= hi[1]; ++y)
        for (int64_t z = lo[2]; z <= hi[2]; ++z) g.cells[{x, y, z}].push_back(int32_t(i));
  }
  return g;
}

// Each boundary vertex goes into the nearest boundary edge it lies on: per edge, the inserted
// vertices with their parameters along it. @p inserted counts them.
std::vector<std::vector<std::pair<double, int32_t>>> seam_inserts(const TriangleMesh& m,
                                                                  const std::vector<BoundaryEdge>& edges,
                                                                  const EdgeGrid& grid, int64_t& inserted) {
  std::vector<uint8_t> on_boundary(m.vertices.size(), 0);
  for (const BoundaryEdge& e : edges) on_boundary[e.a] = on_boundary[e.b] = 1;
  std::vector<std::vector<std::pair<double, int32_t>>> inserts(edges.size());
  for (size_t v = 0; v < m.vertices.size(); ++v) {
    if (!on_boundary[v]) continue;
    const Vec3& p = m.vertices[v];
    double best = INFINITY, best_t = 0;
    int32_t best_e = -1;
    if (const std::vector<int32_t>* near = grid.near(p))
      for (int32_t i : *near) {
        const BoundaryEdge& e = edges[i];
        if (e.a == int32_t(v) || e.b == int32_t(v)) continue;
        const Vec3 &a = m.vertices[e.a], &b = m.vertices[e.b];
        const Vec3 d = b - a;
        const double len2 = d.squaredNorm(), t = (p - a).dot(d) / len2;
        if (!(t > 0 && t < 1)) continue;
        const double dist = (p - (a + t * d)).norm();
        if (dist > 0.25 * std::sqrt(len2) || dist >= 0.5 * std::min((p - a).norm(), (p - b).norm())) continue;
        if (dist < best) best = dist, best_t = t, best_e = i;
      }
    if (best_e >= 0) inserts[best_e].push_back({best_t, int32_t(v)}), ++inserted;
  }
  return inserts;
}

// Faces with inserted vertices become fans; a face with inserts on two or three edges gets a
// vertex at its centroid (rare: a corner of a seam).
TriangleMesh split_at_inserts(const TriangleMesh& m, const std::vector<BoundaryEdge>& edges,
                              std::vector<std::vector<std::pair<double, int32_t>>>& inserts) {
  std::vector<std::array<std::vector<int32_t>, 3>> along(m.faces.size());
  for (size_t i = 0; i < edges.size(); ++i) {
    if (inserts[i].empty()) continue;
    std::sort(inserts[i].begin(), inserts[i].end());
    for (const auto& [t, v] : inserts[i]) along[edges[i].face][edges[i].corner].push_back(v);
  }
  TriangleMesh out;
  out.vertices = m.vertices;
  for (size_t f = 0; f < m.faces.size(); ++f) {
    const Tri& t = m.faces[f];
    int split = 0, corner = 0;
    for (int k = 0; k < 3; ++k)
      if (!along[f][k].empty()) ++split, corner = k;
    if (split == 0) {
      out.faces.push_back(t);
      continue;
    }
    std::vector<int32_t> ring;  // the face's boundary with its inserted vertices, in order
    for (int k = 0; k < 3; ++k) {
      ring.push_back(t[k]);
      ring.insert(ring.end(), along[f][k].begin(), along[f][k].end());
    }
    int32_t apex = t[(corner + 2) % 3];
    if (split > 1) {
      apex = int32_t(out.vertices.size());
      out.vertices.push_back((m.vertices[t[0]] + m.vertices[t[1]] + m.vertices[t[2]]) / 3.0);
    }
    for (size_t i = 0; i < ring.size(); ++i) {
      const int32_t a = ring[i], b = ring[(i + 1) % ring.size()];
      if (a != apex && b != apex) out.faces.push_back({a, b, apex});
    }
  }
  return out;
}

}  // namespace

TriangleMesh stitch_seams(const TriangleMesh& input, SeamReport* report) {
  validate_mesh_data(input, "stitch_seams input");
  SeamReport rep;
  const TriangleMesh welded = weld(input);
  const std::map<EdgeKey, int> welded_uses = edge_uses(welded);
  rep.boundary_edges_before = rep.boundary_edges_after = count_boundary(welded_uses);
  // Seams whose vertices nearly coincide first; kept only if every edge still has at most two faces.
  TriangleMesh m = snap_near_vertices(welded, welded_uses, rep.snapped);
  std::map<EdgeKey, int> uses = edge_uses(m);
  if (rep.snapped > 0 && (!edge_manifold(uses) || m.faces.size() != welded.faces.size()))
    m = welded, uses = welded_uses, rep.snapped = 0;
  if (rep.snapped > 0) m = weld(m), uses = edge_uses(m);
  rep.boundary_edges_after = count_boundary(uses);
  auto done = [&](TriangleMesh r) {
    if (report) *report = rep;
    return r;
  };
  const std::vector<BoundaryEdge> edges = boundary_edges(m, uses);
  if (edges.empty()) return done(m);
  const EdgeGrid grid = edge_grid(m, edges);
  if (!(grid.cell > 0)) return done(m);
  auto inserts = seam_inserts(m, edges, grid, rep.inserted);
  if (rep.inserted == 0) return done(m);
  TriangleMesh out = split_at_inserts(m, edges, inserts);
  const std::map<EdgeKey, int> after = edge_uses(out);
  for (const auto& [e, n] : after)
    if (n > 2) return done(m);
  rep.boundary_edges_after = count_boundary(after);
  return done(out);
}

}  // namespace hdm
