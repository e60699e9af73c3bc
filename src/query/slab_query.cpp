// SPDX-License-Identifier: MIT
#include <hdm/query/slab_query.h>

#include <hdm/query/detail/surface_eval.h>

#include <algorithm>
#include <cmath>

namespace hdm {

void evaluate_surface(const SlabModel& model, int slab, const SlabCoordinates& c, Contact& out) noexcept {
  const double wS = c.bary[1], wT = c.bary[2];
  const slab_query::detail::LocalCell cell = slab_query::detail::local_cell(model.grid_n, wS, wT);
  double delta;
  Vec3 ray;
  out.surface_point = slab_query::detail::surface_point(model, slab, wS, wT, cell, delta, ray);
  const Vec3f nf = slab_query::detail::interpolated_normal(model, slab, cell);
  out.slab = slab;
  out.coords = c;
  out.delta = delta;
  out.ray = ray;
  // The square root and the division end the query's chain of dependent operations: one division
  // for the three components, and the ray's projection on the normal, (D·nf)/|nf|, dotted with the
  // unnormalised nf beside them rather than after them.
  const Vec3 nd = nf.cast<double>();
  const double len = nf.norm(), along = ray.dot(nd);
  double projection;
  if (len > 0) {
    const double inv = 1.0 / len;
    out.normal = nd * inv;
    projection = along * inv;
  } else {
    out.normal = ray.normalized();
    projection = ray.dot(out.normal);
  }
  // The paper (§3.3) measures depth along the ray; projecting on the normal gives the distance to
  // the surface's tangent plane, a first-order exact distance also where rays slant. The floor on
  // the projection keeps the sign of δ - α where the interpolated normal turns away from the ray.
  out.depth = (delta - c.alpha) * std::max(projection, 0.1 * ray.norm());
}

Contact query(const SlabModel& model, const SlabLocator& locator, const Vec3& p, QueryCache& cache,
              AlphaSolver solver) noexcept {
  Contact out;
  SlabCoordinates c;
  const int slab = slab_query::detail::find_cached(locator, p, cache, solver, c);
  if (slab >= 0) evaluate_surface(model, slab, c, out);
  return out;
}

}  // namespace hdm
