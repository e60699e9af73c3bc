// SPDX-License-Identifier: MIT
// Welding of the triangles hdm's own readers produce: vertices at identical positions become one,
// except where that would join edges the file keeps apart (keep_file_pairing); unused vertices
// dropped, the rest numbered in file order.
#include "weld_vertices.h"
#include "../mesh/disjoint_sets.h"

#include <algorithm>
#include <array>
#include <bit>
#include <numeric>
#include <tuple>

namespace hdm::io::detail {
namespace {

// Exact-position order for welding; +0.0 folds -0 into +0 like operator==.
struct PositionBits {
  uint64_t x, y, z;
  auto operator<=>(const PositionBits&) const = default;
};
PositionBits bits_of(const Vec3& p) {
  return {std::bit_cast<uint64_t>(p.x() + 0.0), std::bit_cast<uint64_t>(p.y() + 0.0),
          std::bit_cast<uint64_t>(p.z() + 0.0)};
}

// The welded classes (by their first vertex) whose welds put more than two faces on an edge whose
// faces the file's own ids pair two by two (keep_file_pairing, below).
std::vector<uint8_t> classes_to_undo(const std::vector<Tri>& triangles, const std::vector<int32_t>& weld_to) {
  // Only edges with a welded end can have gained faces.
  std::vector<uint8_t> welded(weld_to.size(), 0);
  bool any_weld = false;
  for (size_t v = 0; v < weld_to.size(); ++v)
    if (weld_to[v] >= 0 && weld_to[v] != static_cast<int32_t>(v)) welded[v] = welded[weld_to[v]] = 1, any_weld = true;
  std::vector<uint8_t> undo(weld_to.size(), 0);
  if (!any_weld) return undo;
  struct Corner {
    int32_t a, b;    // welded ends, a < b
    int32_t fa, fb;  // the file's ids of the same ends
  };
  std::vector<Corner> edges;
  for (const Tri& t : triangles)
    for (int k = 0; k < 3; ++k) {
      int32_t fa = t[k], fb = t[(k + 1) % 3], a = weld_to[fa], b = weld_to[fb];
      if (a == b || !(welded[fa] || welded[fb])) continue;  // degenerate (left to repair) or unchanged
      if (a > b) std::swap(a, b), std::swap(fa, fb);
      edges.push_back({a, b, std::min(fa, fb), std::max(fa, fb)});
    }
  auto by_welded = [](const Corner& x, const Corner& y) {
    return std::tie(x.a, x.b, x.fa, x.fb) < std::tie(y.a, y.b, y.fa, y.fb);
  };
  std::sort(edges.begin(), edges.end(), by_welded);
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    while (j < edges.size() && edges[j].a == edges[i].a && edges[j].b == edges[i].b) ++j;
    if (j - i > 2) {
      bool paired = true;  // sorted by file ends too: runs of equal (fa, fb) are the file's edges
      for (size_t r = i; r < j && paired;) {
        size_t s = r;
        while (s < j && edges[s].fa == edges[r].fa && edges[s].fb == edges[r].fb) ++s;
        paired = s - r == 2;
        r = s;
      }
      if (paired) undo[edges[i].a] = undo[edges[i].b] = 1;
    }
    i = j;
  }
  return undo;
}

// Redoes the welds of the classes marked in @p undo one file vertex at a time, each only where the
// faces around the welded vertex still form one fan.
void reweld_keeping_fans(const std::vector<Tri>& triangles, std::vector<int32_t>& weld_to,
                         const std::vector<uint8_t>& undo) {
  // The file vertices of the undone classes, each its own class again, and their faces.
  std::vector<std::vector<int32_t>> members(weld_to.size());  // by first vertex, in file order
  for (size_t v = 0; v < weld_to.size(); ++v)
    if (weld_to[v] >= 0 && undo[weld_to[v]]) members[weld_to[v]].push_back(static_cast<int32_t>(v));
  std::vector<std::vector<int32_t>> faces_of(weld_to.size());
  for (size_t f = 0; f < triangles.size(); ++f)
    for (int32_t v : triangles[f])
      if (weld_to[v] >= 0 && undo[weld_to[v]]) faces_of[v].push_back(static_cast<int32_t>(f));
  std::vector<std::vector<int32_t>> groups;
  // A position shared by more than 64 file vertices stays welded (left to repair): re-welding is
  // quadratic in the vertices of one position, and no real file puts that many on one point.
  for (size_t c = 0; c < members.size(); ++c)
    if (undo[c] && members[c].size() > 1 && members[c].size() <= 64) {
      for (int32_t v : members[c]) weld_to[v] = v;
      groups.push_back(std::move(members[c]));
    }
  // Whether classes x and y, made one, keep one fan of faces around them: no edge of more than two
  // faces (no link vertex of degree above two) and a connected link (no pinch).
  std::vector<std::array<int32_t, 2>> link;
  std::vector<int32_t> ends;
  mesh::detail::DisjointSets<> sets;
  auto merge_keeps_manifold = [&](const std::vector<int32_t>& x, const std::vector<int32_t>& y, int32_t cx,
                                  int32_t cy) {
    link.clear();
    for (const auto* cls : {&x, &y})
      for (int32_t v : *cls)
        for (int32_t f : faces_of[v]) {
          const Tri& t = triangles[f];
          const int k = t[0] == v ? 0 : t[1] == v ? 1 : 2;
          const int32_t c1 = weld_to[t[(k + 1) % 3]], c2 = weld_to[t[(k + 2) % 3]];
          if (c1 == cx || c1 == cy || c2 == cx || c2 == cy) return false;  // the face would repeat a vertex
          link.push_back({c1, c2});
        }
    ends.clear();
    for (const auto& e : link) ends.insert(ends.end(), e.begin(), e.end());
    std::sort(ends.begin(), ends.end());
    for (size_t i = 0; i + 2 < ends.size(); ++i)
      if (ends[i] == ends[i + 2]) return false;  // an edge of three or more faces
    ends.erase(std::unique(ends.begin(), ends.end()), ends.end());
    sets.reset(ends.size());
    auto index = [&](int32_t c) {
      return static_cast<int32_t>(std::lower_bound(ends.begin(), ends.end(), c) - ends.begin());
    };
    size_t parts = ends.size();
    for (const auto& e : link)
      if (sets.unite(index(e[0]), index(e[1]))) --parts;
    return parts == 1;
  };
  for (const std::vector<int32_t>& g : groups) {
    std::vector<std::vector<int32_t>> classes;  // of this position, each led by its first vertex
    for (int32_t v : g) {
      const std::vector<int32_t> alone{v};
      bool joined = false;
      for (auto& cls : classes)
        if (merge_keeps_manifold(cls, alone, cls.front(), v)) {
          weld_to[v] = cls.front();
          cls.push_back(v);
          joined = true;
          break;
        }
      if (!joined) classes.push_back(alone);
    }
  }
}

// Welding can join two edges the file keeps apart: a closed surface written with two vertices at
// one position (diplodocus.off of libcgal-demo: a surface touching itself along an edge, two
// parts touching there) becomes an edge of four faces, which repair can only split arbitrarily,
// opening holes. Where every face on such an edge is paired by the file's own vertex ids (each of
// its file edges has exactly two faces), the welds of its two ends are undone and redone one file
// vertex at a time, each only when the faces around the welded vertex still form one fan (no edge
// of more than two faces, no pinch): the surface keeps the pairing the file wrote. Edges the file
// itself leaves unpaired (an STL soup, a non-manifold file) are welded as before, and left to
// repair. @p weld_to maps every used file vertex to the first file vertex of its class (the
// smallest id); it is updated in place. O(k log k) for the k edges with a welded end, plus the
// faces around the undone welds.
void keep_file_pairing(const std::vector<Tri>& triangles, std::vector<int32_t>& weld_to) {
  const std::vector<uint8_t> undo = classes_to_undo(triangles, weld_to);
  if (std::find(undo.begin(), undo.end(), 1) != undo.end()) reweld_keeping_fans(triangles, weld_to, undo);
}

}  // namespace

TriangleMesh weld_vertices(const std::vector<Vec3>& positions, const std::vector<Tri>& triangles) {
  // Sort the used vertices by exact position; each group maps to its first vertex in file order.
  std::vector<int32_t> used;
  {
    std::vector<uint8_t> is_used(positions.size(), 0);
    for (const Tri& t : triangles)
      for (int32_t v : t) is_used[v] = 1;
    for (size_t v = 0; v < positions.size(); ++v)
      if (is_used[v]) used.push_back(static_cast<int32_t>(v));
  }
  std::vector<PositionBits> key(used.size());
  for (size_t i = 0; i < used.size(); ++i) key[i] = bits_of(positions[used[i]]);
  std::vector<int32_t> order(used.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](int32_t a, int32_t b) { return key[a] < key[b] || (key[a] == key[b] && a < b); });
  std::vector<int32_t> first(used.size());  // index (into used) of the first vertex with the same position
  for (size_t i = 0; i < order.size(); ++i)
    first[order[i]] = (i > 0 && key[order[i]] == key[order[i - 1]]) ? first[order[i - 1]] : order[i];

  std::vector<int32_t> weld_to(positions.size(), -1);  // file vertex -> the file vertex it is welded to
  for (size_t i = 0; i < used.size(); ++i) weld_to[used[i]] = used[first[i]];
  keep_file_pairing(triangles, weld_to);

  TriangleMesh mesh;
  std::vector<int32_t> new_id(positions.size(), -1);
  for (int32_t v : used) {
    if (weld_to[v] == v) {
      new_id[v] = static_cast<int32_t>(mesh.vertices.size());
      mesh.vertices.push_back(positions[v]);
    } else {
      new_id[v] = new_id[weld_to[v]];  // weld_to[v] < v: already numbered
    }
  }
  mesh.faces.resize(triangles.size());
  for (size_t f = 0; f < triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) mesh.faces[f][k] = new_id[triangles[f][k]];
  return mesh;
}

}  // namespace hdm::io::detail
