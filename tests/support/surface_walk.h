// SPDX-License-Identifier: MIT
#pragma once
// Query points near the displaced surface for the query tests: single points, and a coherent walk
// over the surface (the servo loop's case) from slab to neighbouring slab.

#include <hdm/query/slab_locator.h>
#include <hdm/slab/slab_model.h>

#include <algorithm>
#include <random>

namespace hdm::test {

/// A point near the surface of slab @p s: one of its grid samples, at random, moved along the
/// sample's normal by a uniform amount in ±@p offset times the model's diagonal [model units].
inline Vec3 near_surface_point(const SlabModel& m, int s, double offset, std::mt19937& rng) {
  std::uniform_real_distribution<double> off(-offset, offset);
  std::uniform_int_distribution<int> grid_point(0, m.samples.per_slab - 1);
  const int32_t id = m.samples.id(s, grid_point(rng));
  return sample_position(m, id) + off(rng) * m.source_diagonal * sample_normal(m, id).cast<double>();
}

/// Calls @p visit(p) on @p steps points of a coherent walk from slab @p start: straight steps of
/// about 1e-4 of the diagonal towards near_surface_point() of a random slab of the current one's
/// neighbourhood, and on from there. Stops early when @p visit returns false.
template <class Visit>
void surface_walk(const SlabModel& m, const SlabLocator& loc, int start, int steps, double offset, std::mt19937& rng,
                  Visit&& visit) {
  int slab = start;
  Vec3 from = near_surface_point(m, slab, offset, rng);
  for (int done = 0; done < steps;) {
    int count = 0;
    const int32_t* ring = loc.neighbourhood(slab, count);
    slab = count > 0 ? ring[rng() % count] : slab;
    const Vec3 to = near_surface_point(m, slab, offset, rng);
    const int n = std::max(1, static_cast<int>((to - from).norm() / (1e-4 * m.source_diagonal)));
    for (int k = 1; k <= n && done < steps; ++k, ++done)
      if (!visit(Vec3(from + (to - from) * (double(k) / n)))) return;
    from = to;
  }
}

}  // namespace hdm::test
