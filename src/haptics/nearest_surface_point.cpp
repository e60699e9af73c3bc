// SPDX-License-Identifier: MIT
#include "nearest_surface_point.h"

#include <hdm/query/detail/surface_eval.h>
#include <hdm/slab/triangle_grid.h>

#include <algorithm>
#include <cmath>

namespace hdm::haptics_detail {
namespace {

// Closest point of triangle abc to p (Ericson, Real-Time Collision Detection, 2005, §5.1.5), with
// its barycentrics w on a, b, c (a zero weight: the point is on the opposite edge).
Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, double w[3]) noexcept {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  auto set = [&](double wa, double wb, double wc) { w[0] = wa, w[1] = wb, w[2] = wc; };
  if (d1 <= 0 && d2 <= 0) return set(1, 0, 0), a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return set(0, 1, 0), b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double t = d1 / (d1 - d3);
    return set(1 - t, t, 0), a + t * ab;
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return set(0, 0, 1), c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double t = d2 / (d2 - d6);
    return set(1 - t, 0, t), a + t * ac;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return set(0, 1 - t, t), b + t * (c - b);
  }
  const double denom = 1 / (va + vb + vc);
  set(1 - (vb + vc) * denom, vb * denom, vc * denom);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

// Grid point (i, j) of a slab on the displaced surface [model units]: the renderer's vertex.
Vec3 grid_point(int n, const SlabGeometry& g, const SlabSample* v, int i, int j) noexcept {
  const double wT = double(i) / n, wS = double(j) / n;
  const double delta = v[grid::index(n, i, j)].delta;
  return g.R0 + wS * g.e1 + wT * g.e2 + delta * (g.dR + wS * g.d1 + wT * g.d2);
}

// Nearest point found on one slab's grid: the point, its squared distance, its triangle.
struct SlabNearest {
  Vec3 point;
  double d2;
  int i, j;
  bool down;  // the "down" triangle (i+1,j+1), (i+1,j), (i,j+1) of cell (i, j), else the "up" one
};

// The corners of grid triangle (i, j, down) as grid coordinates.
void corners_of(int i, int j, bool down, int gi[3], int gj[3]) noexcept {
  if (down)
    gi[0] = i + 1, gj[0] = j + 1, gi[1] = i + 1, gj[1] = j, gi[2] = i, gj[2] = j + 1;
  else
    gi[0] = i, gj[0] = j, gi[1] = i + 1, gj[1] = j, gi[2] = i, gj[2] = j + 1;
}

// Walks one slab's grid triangles from the one under (wS, wT) to the nearest point of @p c: from a
// triangle whose nearest point is on an edge to the triangle across it, from a corner to the
// triangles around it, while that is nearer. A nearest point inside a triangle is a minimum.
// Usually one to three triangle tests when the start is the last tick's.
SlabNearest slab_nearest(const SlabModel& m, int slab, double wS, double wT, const Vec3& c) noexcept {
  const int n = m.grid_n;
  const SlabGeometry& g = m.geometry[slab];
  const SlabSample* v = slab_query::detail::slab_block(m, slab);
  auto valid = [n](int i, int j, bool down) { return i >= 0 && j >= 0 && i + j <= n - (down ? 2 : 1); };
  auto test = [&](int i, int j, bool down, double w[3]) {
    int gi[3], gj[3];
    corners_of(i, j, down, gi, gj);
    const Vec3 q = closest_on_triangle(c, grid_point(n, g, v, gi[0], gj[0]), grid_point(n, g, v, gi[1], gj[1]),
                                       grid_point(n, g, v, gi[2], gj[2]), w);
    return SlabNearest{q, (q - c).squaredNorm(), i, j, down};
  };
  // The start triangle, as local_cell() picks it.
  double hx = std::max(0.0, n * wT), hy = std::max(0.0, n * wS);
  if (hx + hy > n) hx *= n / (hx + hy), hy *= n / (hx + hy);
  int i = std::min(static_cast<int>(hx), n - 1);
  int j = std::min(static_cast<int>(hy), n - 1 - i);
  double w[3];
  SlabNearest best = test(i, j, (hx - i) + (hy - j) > 1 && i + j <= n - 2, w);
  for (int step = 0; step < 4 * n; ++step) {
    const double eps = 1e-12;
    const int zeros = (w[0] <= eps) + (w[1] <= eps) + (w[2] <= eps);
    if (zeros == 0) break;  // inside the triangle: a minimum
    int gi[3], gj[3];
    corners_of(best.i, best.j, best.down, gi, gj);
    SlabNearest next = best;
    double wn[3], wbest[3] = {w[0], w[1], w[2]};
    // Candidates: every triangle that shares the nearest point's edge (the one across it) or
    // corner (the six around it), found among the cells around that edge or corner.
    int ci = 0, cj = 0, k = 0;
    for (int a = 0; a < 3; ++a) ci += gi[a] * (w[a] > eps), cj += gj[a] * (w[a] > eps), k += w[a] > eps;
    const int lo_i = (zeros == 2 ? ci : ci / std::max(k, 1)) - 1, lo_j = (zeros == 2 ? cj : cj / std::max(k, 1)) - 1;
    auto shares = [&](int a, int b, bool d) {  // has every corner of the current one with weight > 0
      int ti[3], tj[3];
      corners_of(a, b, d, ti, tj);
      for (int x = 0; x < 3; ++x) {
        if (!(w[x] > eps)) continue;
        bool has = false;
        for (int y = 0; y < 3; ++y) has |= ti[y] == gi[x] && tj[y] == gj[x];
        if (!has) return false;
      }
      return true;
    };
    for (int a = lo_i; a <= lo_i + 1; ++a)
      for (int b = lo_j; b <= lo_j + 1; ++b)
        for (int d = 0; d < 2; ++d) {
          if (!valid(a, b, d != 0) || (a == best.i && b == best.j && (d != 0) == best.down)) continue;
          if (!shares(a, b, d != 0)) continue;
          const SlabNearest t = test(a, b, d != 0, wn);
          if (t.d2 < next.d2) next = t, wbest[0] = wn[0], wbest[1] = wn[1], wbest[2] = wn[2];
        }
    if (!(next.d2 < best.d2)) break;
    best = next, w[0] = wbest[0], w[1] = wbest[1], w[2] = wbest[2];
  }
  return best;
}

// The force-shading normals of the grid points around one grid triangle of cell (i0 + 1, j0 + 1),
// its corners and their neighbours in the slab (a 4 × 4 window of grid indices), each decoded once.
struct ShadingWindow {
  const SlabSample* v;
  int n, i0, j0;
  Vec3f h[16];
  bool have[16] = {};
  const Vec3f& at(int i, int j) noexcept {
    const int k = 4 * (i - i0) + (j - j0);
    if (!have[k]) h[k] = v[grid::index(n, i, j)].shading(), have[k] = true;
    return h[k];
  }
};

// How fast the force-shading field turns at grid point (i, j) [rad per model unit, as chords]:
// the largest |h_u − h| over its grid neighbours u in the slab, over the slab's mean grid spacing
// (@p per_spacing is its inverse). A property of the grid point, not of a triangle, so that
// interpolated over the triangles around the point it is continuous within the slab.
double point_turn(ShadingWindow& w, int i, int j, double per_spacing) noexcept {
  static constexpr int di[6] = {1, -1, 0, 0, 1, -1}, dj[6] = {0, 0, 1, -1, -1, 1};
  const Vec3f h = w.at(i, j);
  float most = 0;
  for (int k = 0; k < 6; ++k) {
    const int a = i + di[k], b = j + dj[k];
    if (a < 0 || b < 0 || a + b > w.n) continue;
    most = std::max(most, (w.at(a, b) - h).squaredNorm());
  }
  return std::sqrt(double(most)) * per_spacing;
}

// The mean grid spacing of @p g's mid-surface (δ = 1/2) [model units].
double mid_spacing(int n, const SlabGeometry& g) noexcept {
  const Vec3 s = g.e1 + 0.5 * g.d1, t = g.e2 + 0.5 * g.d2;
  return (s.norm() + t.norm() + (s - t).norm()) / (3.0 * n);
}

// The force-shading normal at @p b (and in @p facet its grid triangle's, in @p corner its
// barycentrics there): the per-sample normals (SlabSample::h) interpolated by the point's
// barycentrics in its grid triangle, as the point proxy shades its force (Morgenbesser &
// Srinivasan 1996).
Vec3 shaded_normal(const SlabModel& m, int slab, const SlabNearest& b, Vec3& facet, float corner[3]) noexcept {
  const int n = m.grid_n;
  const SlabGeometry& g = m.geometry[slab];
  const SlabSample* v = slab_query::detail::slab_block(m, slab);
  const int ia = b.down ? b.i + 1 : b.i, ja = b.down ? b.j + 1 : b.j;
  const int ids[3] = {grid::index(n, ia, ja), grid::index(n, b.i + 1, b.j), grid::index(n, b.i, b.j + 1)};
  const Vec3 p0 = grid_point(n, g, v, ia, ja), p1 = grid_point(n, g, v, b.i + 1, b.j),
             p2 = grid_point(n, g, v, b.i, b.j + 1);
  const Vec3 face = (p1 - p0).cross(p2 - p0);
  const double area = face.squaredNorm();
  // Grid index i runs along wT and j along wS: the up triangle's (p1 − p0) × (p2 − p0) is
  // e_T × e_S, inward; the down triangle's (−e_S) × (−e_T), outward.
  facet = area > 0 ? Vec3((b.down ? 1.0 : -1.0) * face / std::sqrt(area)) : Vec3::UnitZ();
  double w1 = area > 0 ? (b.point - p0).cross(p2 - p0).dot(face) / area : 1.0 / 3;
  double w2 = area > 0 ? (p1 - p0).cross(b.point - p0).dot(face) / area : 1.0 / 3;
  w1 = std::clamp(w1, 0.0, 1.0), w2 = std::clamp(w2, 0.0, 1.0 - w1);
  const double w[3] = {1 - w1 - w2, w1, w2};
  Vec3 sum = Vec3::Zero();
  for (int k = 0; k < 3; ++k) sum += w[k] * v[ids[k]].shading().cast<double>(), corner[k] = float(w[k]);
  const double len = sum.norm();
  return len > 0 ? Vec3(sum / len) : facet;
}

// Carries (wS, wT) of @p from to @p to by their shared coarse vertices (the others get 0).
void carry_barycentrics(const SlabModel& m, int from, double wS, double wT, int to, double& oS, double& oT) noexcept {
  const double w[3] = {1 - wS - wT, wS, wT};
  double wn[3] = {0, 0, 0}, sum = 0;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      if (m.slabs[to][a] == m.slabs[from][b]) wn[a] = std::max(0.0, w[b]), sum += wn[a];
  oS = sum > 0 ? wn[1] / sum : 1.0 / 3, oT = sum > 0 ? wn[2] / sum : 1.0 / 3;
}

}  // namespace

SurfacePoint nearest_surface_point(const SlabModel& m, int slab, double wS, double wT, const Vec3& c) noexcept {
  const int n = m.grid_n;
  SlabNearest best = slab_nearest(m, slab, wS, wT, c);
  // A ball's nearest point near a slab's border may lie in a slab that no sample hit: go on to
  // the neighbour across each edge the best cell touches and, in a corner cell, to every slab
  // around that coarse vertex, while one has a nearer point.
  int from = -1;
  const bool fans = m.samples.corner_slot_offsets.size() == m.inner.size() + 1;
  for (int hop = 0; hop < 6 && !m.edge_neighbour.empty(); ++hop) {
    const double bS = (best.j + 1.0 / 3) / n, bT = (best.i + 1.0 / 3) / n;
    int candidate[64], count = 0;
    // Only a point on the slab's border can have a nearer one beyond it (a minimum inside the
    // slab is a minimum): an up triangle's edge on RS (i = 0), ST (i + j = n − 1) or TR (j = 0),
    // or a corner.
    const SlabGeometry& g = m.geometry[slab];
    const SlabSample* v = slab_query::detail::slab_block(m, slab);
    const double tiny = 1e-9 * (g.e1.norm() + g.e2.norm());
    auto on = [&](int i0, int j0, int i1, int j1) {
      const Vec3 a = grid_point(n, g, v, i0, j0), b = grid_point(n, g, v, i1, j1);
      const double t = std::clamp((best.point - a).dot(b - a) / std::max((b - a).squaredNorm(), 1e-300), 0.0, 1.0);
      return (a + t * (b - a) - best.point).norm() <= tiny;
    };
    const int i = best.i, j = best.j;
    const bool touches[3] = {!best.down && i == 0 && on(0, j, 0, j + 1),              // RS
                             !best.down && i + j == n - 1 && on(i + 1, j, i, j + 1),  // ST
                             !best.down && j == 0 && on(i, 0, i + 1, 0)};             // TR
    for (int edge = 0; edge < 3; ++edge)
      if (touches[edge] && m.edge_neighbour[slab][edge] >= 0) candidate[count++] = m.edge_neighbour[slab][edge];
    // A coarse vertex: R = grid (0, 0), S = (0, n), T = (n, 0), a corner of the up triangles of
    // cells (0, 0), (0, n − 1) and (n − 1, 0).
    const int corner = best.down ? -1 : i == 0 && j == 0 ? 0 : i == 0 && j == n - 1 ? 1 : i == n - 1 && j == 0 ? 2 : -1;
    static constexpr int ci[3] = {0, 0, 1}, cj[3] = {0, 1, 0};
    if (corner >= 0 && fans && (grid_point(n, g, v, n * ci[corner], n * cj[corner]) - best.point).norm() <= tiny) {
      const int vtx = m.slabs[slab][corner];
      m.samples.for_each_vertex_slab(vtx, [&](int32_t f) noexcept {
        if (count < 64) candidate[count++] = f;
      });
    }
    SlabNearest step = best;
    int to = -1;
    for (int k = 0; k < count; ++k) {
      const int next = candidate[k];
      if (next == slab || next == from) continue;
      double oS, oT;
      carry_barycentrics(m, slab, bS, bT, next, oS, oT);
      const SlabNearest there = slab_nearest(m, next, oS, oT, c);
      if (there.d2 < step.d2) step = there, to = next;
    }
    if (to < 0) break;
    best = step, from = slab, slab = to;
  }
  SurfacePoint out;
  out.point = best.point;
  out.normal = shaded_normal(m, slab, best, out.facet, out.corner);
  out.slab = slab;
  out.cell_i = best.i, out.cell_j = best.j, out.down = best.down;
  // The centroid of its grid triangle, so that a search from (wS, wT) starts on that triangle: an
  // up triangle's centroid for a down one started the next search on its neighbour, whose own
  // nearest point, inside it on a concave spot, ended that search farther than where it began.
  const double third = (best.down ? 2.0 : 1.0) / 3;
  out.wS = (best.j + third) / n;
  out.wT = (best.i + third) / n;
  return out;
}

double shading_turn(const SlabModel& m, const SurfacePoint& p) noexcept {
  const int n = m.grid_n;
  const SlabGeometry& g = m.geometry[p.slab];
  const double spacing = mid_spacing(n, g), per_spacing = spacing > 0 ? 1 / spacing : 0;
  ShadingWindow around{slab_query::detail::slab_block(m, p.slab), n, p.cell_i - 1, p.cell_j - 1};
  const int ia = p.down ? p.cell_i + 1 : p.cell_i, ja = p.down ? p.cell_j + 1 : p.cell_j;
  const int ci[3] = {ia, p.cell_i + 1, p.cell_i}, cj[3] = {ja, p.cell_j, p.cell_j + 1};
  double turn = 0;
  for (int k = 0; k < 3; ++k) turn += p.corner[k] * point_turn(around, ci[k], cj[k], per_spacing);
  return turn;
}

}  // namespace hdm::haptics_detail
