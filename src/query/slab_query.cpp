// SPDX-License-Identifier: MIT
#include <hdm/query/slab_query.h>
#include <hdm/slab/triangle_grid.h>

#include <algorithm>
#include <cmath>

namespace hdm {

void evaluate_surface(const SlabModel& model, int slab, const SlabCoordinates& c, Contact& out) noexcept {
  const SlabGeometry& g = model.geometry[slab];
  const int n = model.grid_n;
  const double wS = c.bary[1], wT = c.bary[2];
  double hx = std::max(0.0, n * wT), hy = std::max(0.0, n * wS);
  if (hx + hy > n) {  // rounding beyond the hypotenuse
    const double s = n / (hx + hy);
    hx *= s, hy *= s;
  }
  const int i = std::min(static_cast<int>(hx), n - 1);
  const int j = std::min(static_cast<int>(hy), n - 1 - i);
  double fx = hx - i, fy = hy - j;
  const int32_t* ids = &model.samples.ids[static_cast<size_t>(slab) * model.samples.per_slab];
  int32_t a, b, d;
  double wa, wb, wd;
  if (fx + fy > 1 && i + j <= n - 2) {  // "down" triangle (i+1,j+1), (i+1,j), (i,j+1)
    a = ids[grid::index(n, i + 1, j + 1)], b = ids[grid::index(n, i + 1, j)], d = ids[grid::index(n, i, j + 1)];
    wa = fx + fy - 1, wb = 1 - fy, wd = 1 - fx;
  } else {  // "up" triangle (i,j), (i+1,j), (i,j+1)
    if (fx + fy > 1) {
      const double s = 1 / (fx + fy);
      fx *= s, fy *= s;
    }
    a = ids[grid::index(n, i, j)], b = ids[grid::index(n, i + 1, j)], d = ids[grid::index(n, i, j + 1)];
    wa = 1 - fx - fy, wb = fx, wd = fy;
  }
  const float* disp = model.displacement.data();
  const double delta = wa * disp[a] + wb * disp[b] + wd * disp[d];
  const Vec3f nf = static_cast<float>(wa) * model.normals[a] + static_cast<float>(wb) * model.normals[b] +
                   static_cast<float>(wd) * model.normals[d];
  const Vec3 ray = g.dR + wS * g.d1 + wT * g.d2;               // D(w) = Σ wV dV
  const Vec3 p0 = g.R0 + wS * g.e1 + wT * g.e2;                // P0(w) = Σ wV V0
  out.slab = slab;
  out.coords = c;
  out.delta = delta;
  out.ray = ray;
  out.depth = (delta - c.alpha) * ray.norm();                  // paper §3.3: along the ray
  out.surface_point = p0 + delta * ray;
  const double len = nf.norm();
  out.normal = len > 0 ? Vec3(nf.cast<double>() / len) : Vec3(ray.normalized());
}

Contact query(const SlabModel& model, const SlabLocator& locator, const Vec3& p, QueryCache& cache,
              AlphaSolver solver) noexcept {
  Contact out;
  SlabCoordinates c;
  const int slab = locator.find(p, cache.last_slab, solver, c);
  if (slab < 0) return out;
  cache.last_slab = slab;
  evaluate_surface(model, slab, c, out);
  return out;
}

}  // namespace hdm
