// SPDX-License-Identifier: MIT
// Polygon soup → TriangleMesh: triangulation (fan or ear clipping), then welding of identical
// positions and unused vertices dropped (weld_vertices.h). Shared by hdm's own OFF, PLY, OBJ and STL readers.
#include "polygon_soup.h"
#include "text_cursor.h"
#include "weld_vertices.h"

#include <hdm/core/error.h>

#include <algorithm>
#include <cmath>
#include <numeric>

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

}  // namespace

TriangleMesh to_triangle_mesh(PolygonSoup&& soup, const std::string& name) {
  // Coordinates are rounded to float, as hdm has always read them (assimp's ai_real), so a mesh
  // gives the same bake whatever its format; then widened exactly to double. The float goes
  // through a volatile: GCC 12's vectorizer drops a double -> float -> double round trip at -O2
  // (Eigen's cast) and -O3 (a plain loop), which left some coordinates unrounded in release builds
  // only, so builds of the same source baked different models.
  std::vector<Vec3>& positions = soup.positions;
  for (size_t v = 0; v < positions.size(); ++v) {
    for (int a = 0; a < 3; ++a) {
      const volatile float rounded = static_cast<float>(positions[v][a]);
      positions[v][a] = rounded;
    }
    if (!positions[v].allFinite())
      throw InvalidInput(name + ": vertex " + std::to_string(v) + " has a non-finite coordinate");
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

  return weld_vertices(positions, triangles);
}

}  // namespace hdm::detail
