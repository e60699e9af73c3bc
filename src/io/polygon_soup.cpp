// SPDX-License-Identifier: MIT
// Polygon soup → TriangleMesh: triangulation (fan or ear clipping), welding of identical
// positions, unused vertices dropped. Shared by hdm's own OFF, PLY, OBJ and STL readers.
#include "polygon_soup.h"
#include "text_cursor.h"

#include <hdm/core/error.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <numeric>
#include <tuple>

namespace hdm::detail {
namespace {

struct Vec2d {
  double x, y;
};

double cross(const Vec2d& o, const Vec2d& a, const Vec2d& b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

// Strictly inside or on the boundary of the counter-clockwise triangle (a, b, c).
bool in_triangle(const Vec2d& p, const Vec2d& a, const Vec2d& b, const Vec2d& c) {
  return cross(a, b, p) >= 0 && cross(b, c, p) >= 0 && cross(c, a, p) >= 0;
}

// Triangulates the polygon `ids` (k >= 4 corners) into `out`, keeping its winding. Convex
// polygons are fanned; concave ones are ear-clipped in the plane of their Newell normal.
// Returns false when the polygon is concave and has more than max_concave_polygon_corners corners.
bool triangulate(const std::vector<Vec3>& positions, const int32_t* ids, size_t k, std::vector<Tri>& out,
                 std::vector<Vec2d>& q, std::vector<size_t>& ring) {
  auto fan = [&] {
    for (size_t i = 1; i + 1 < k; ++i) out.push_back({ids[0], ids[i], ids[i + 1]});
    return true;
  };
  // Newell normal about the centroid (less cancellation than about the origin).
  Vec3 centre = Vec3::Zero();
  for (size_t i = 0; i < k; ++i) centre += positions[ids[i]];
  centre /= double(k);
  Vec3 n = Vec3::Zero();
  for (size_t i = 0; i < k; ++i) n += (positions[ids[i]] - centre).cross(positions[ids[(i + 1) % k]] - centre);
  const double len = n.norm();
  if (!(len > 0) || !std::isfinite(len)) return fan();  // degenerate: every triangle has zero area anyway
  n /= len;
  // A basis (e1, e2) of the plane with e1 × e2 = n, so the polygon runs counter-clockwise in it.
  const Vec3 a = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 e1 = n.cross(a).normalized(), e2 = n.cross(e1);
  q.resize(k);
  for (size_t i = 0; i < k; ++i) {
    const Vec3 d = positions[ids[i]] - centre;
    q[i] = {d.dot(e1), d.dot(e2)};
  }
  size_t reflex = k;
  for (size_t i = 0; i < k; ++i)
    if (cross(q[(i + k - 1) % k], q[i], q[(i + 1) % k]) < 0) {
      if (reflex != k) {
        reflex = k + 1;  // two or more reflex corners
        break;
      }
      reflex = i;
    }
  if (reflex == k) return fan();
  if (k == 4 && reflex < k) {  // one reflex corner: both triangles start there
    const size_t r = reflex;
    out.push_back({ids[r], ids[(r + 1) % 4], ids[(r + 2) % 4]});
    out.push_back({ids[r], ids[(r + 2) % 4], ids[(r + 3) % 4]});
    return true;
  }
  if (k > max_concave_polygon_corners) return false;
  // Ear clipping: O(k²) candidate tests of O(k) each, k <= max_concave_polygon_corners.
  ring.resize(k);
  std::iota(ring.begin(), ring.end(), size_t{0});
  while (ring.size() > 3) {
    const size_t m = ring.size();
    bool clipped = false;
    for (size_t j = 0; j < m && !clipped; ++j) {
      const size_t p = ring[(j + m - 1) % m], c = ring[j], nx = ring[(j + 1) % m];
      if (!(cross(q[p], q[c], q[nx]) > 0)) continue;
      bool ear = true;
      for (size_t r = 0; r < m && ear; ++r) {
        const size_t o = ring[r];
        if (o == p || o == c || o == nx) continue;
        ear = !in_triangle(q[o], q[p], q[c], q[nx]);
      }
      if (!ear) continue;
      out.push_back({ids[p], ids[c], ids[nx]});
      ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(j));
      clipped = true;
    }
    if (!clipped) {  // self-intersecting or numerically flat: fan what is left
      for (size_t j = 1; j + 1 < ring.size(); ++j) out.push_back({ids[ring[0]], ids[ring[j]], ids[ring[j + 1]]});
      return true;
    }
  }
  out.push_back({ids[ring[0]], ids[ring[1]], ids[ring[2]]});
  return true;
}

// Exact-position order for welding; +0.0 folds -0 into +0 like operator==.
struct PositionBits {
  uint64_t x, y, z;
  auto operator<=>(const PositionBits&) const = default;
};
PositionBits bits_of(const Vec3& p) {
  return {std::bit_cast<uint64_t>(p.x() + 0.0), std::bit_cast<uint64_t>(p.y() + 0.0),
          std::bit_cast<uint64_t>(p.z() + 0.0)};
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
  // Only edges with a welded end can have gained faces.
  std::vector<uint8_t> welded(weld_to.size(), 0);
  bool any_weld = false;
  for (size_t v = 0; v < weld_to.size(); ++v)
    if (weld_to[v] >= 0 && weld_to[v] != static_cast<int32_t>(v)) welded[v] = welded[weld_to[v]] = 1, any_weld = true;
  if (!any_weld) return;
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
  std::vector<uint8_t> undo(weld_to.size(), 0);  // welded classes (by their first vertex) to redo
  bool any = false;
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
      if (paired) undo[edges[i].a] = undo[edges[i].b] = 1, any = true;
    }
    i = j;
  }
  if (!any) return;

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
  std::vector<int32_t> ends, parent;
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
    parent.resize(ends.size());
    std::iota(parent.begin(), parent.end(), 0);
    auto root = [&](int32_t i) {
      while (parent[i] != i) i = parent[i] = parent[parent[i]];
      return i;
    };
    auto index = [&](int32_t c) {
      return static_cast<int32_t>(std::lower_bound(ends.begin(), ends.end(), c) - ends.begin());
    };
    size_t parts = ends.size();
    for (const auto& e : link) {
      const int32_t a = root(index(e[0])), b = root(index(e[1]));
      if (a != b) parent[a] = b, --parts;
    }
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

}  // namespace

TriangleMesh to_triangle_mesh(PolygonSoup&& soup, const std::string& name) {
  // Coordinates are rounded to float, as hdm has always read them (assimp's ai_real), so a mesh
  // gives the same bake whatever its format; then widened exactly to double. The float goes
  // through a volatile: GCC 12's vectorizer drops a double -> float -> double round trip at -O2
  // (Eigen's cast) and -O3 (a plain loop), which left some coordinates unrounded in release builds
  // only, so builds of the same source baked different models.
  std::vector<Vec3>& positions = soup.positions;
  for (size_t v = 0; v < positions.size(); ++v) {
    if (!positions[v].allFinite())
      throw InvalidInput(name + ": vertex " + std::to_string(v) + " has a non-finite coordinate");
    for (int a = 0; a < 3; ++a) {
      const volatile float rounded = static_cast<float>(positions[v][a]);
      positions[v][a] = rounded;
    }
    if (!positions[v].allFinite())  // finite as read, beyond float's range once rounded
      throw InvalidInput(name + ": vertex " + std::to_string(v) +
                         " has a coordinate out of range (beyond ±3.4e38, the largest float hdm stores)");
  }

  std::vector<Tri> triangles;
  triangles.reserve(soup.corners.size() / 3 + 1);
  std::vector<Vec2d> q;
  std::vector<size_t> ring;
  uint64_t other = soup.points_and_lines;
  for (size_t p = 0; p < soup.polygon_count(); ++p) {
    const int32_t* ids = soup.corners.data() + soup.polygon_end[p];
    const size_t k = soup.polygon_end[p + 1] - soup.polygon_end[p];
    if (k < 3) {
      ++other;
    } else if (k == 3) {
      triangles.push_back({ids[0], ids[1], ids[2]});
    } else if (!triangulate(positions, ids, k, triangles, q, ring)) {
      throw InvalidInput(name + ": polygon " + std::to_string(p) + " has " + with_commas(k) +
                         " corners and is not convex; hdm triangulates concave polygons of up to " +
                         std::to_string(max_concave_polygon_corners) + " corners (triangulate it first)");
    }
  }
  if (other > 0)
    throw InvalidInput(name + ": " + with_commas(other) + " of " +
                       with_commas(soup.polygon_count() + soup.points_and_lines) +
                       " faces are points or line segments, not triangles");
  if (triangles.empty()) throw InvalidInput(name + ": holds no triangles");

  // Weld: sort the used vertices by exact position; each group maps to its first vertex in file order.
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

}  // namespace hdm::detail
