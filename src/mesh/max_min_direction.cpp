// SPDX-License-Identifier: MIT
#include "max_min_direction.h"

#include <algorithm>

namespace hdm::mesh::detail {

void improve_max_min(const std::vector<Vec3>& normals, double& best_value, Vec3* best_direction) {
  // The normals in the order the candidates are checked against them: one that rules a candidate
  // out moves to the front, since it likely rules out the next (a star's few extreme normals do).
  // The smallest dot product does not depend on that order, nor does whether it is above the best:
  // the result is the same, bit for bit, with far fewer products on stars of hundreds of faces.
  thread_local std::vector<Vec3> check;
  check.assign(normals.begin(), normals.end());
  // Whether the unit direction along @p d is surely no better than the best: its product with the
  // front normal is below the best by a margin far above rounding (1e-9, against ~1e-16), decided
  // without normalising (no root, no division), so the exact test below would rule it out too.
  auto surely_worse = [&](const Vec3& d, double len2) {
    const double b = best_value - 1e-9, p = d.dot(check[0]);
    if (b >= 0) return p <= 0 || p * p <= b * b * len2;
    return p < 0 && p * p >= b * b * len2;
  };
  auto consider = [&](Vec3 d) {
    const double len2 = d.squaredNorm();
    if (len2 > 1e-24 && surely_worse(d, len2)) return;
    const double len = d.norm();
    if (!(len > 1e-12)) return;
    d /= len;
    double worst = 2;
    for (size_t i = 0; i < check.size(); ++i)
      if ((worst = std::min(worst, d.dot(check[i]))) <= best_value) {
        std::swap(check[i], check[0]);
        return;
      }
    best_value = worst;
    if (best_direction) *best_direction = d;
  };
  const size_t k = normals.size();
  for (size_t a = 0; a < k; ++a) {
    consider(normals[a]);
    for (size_t b = a + 1; b < k; ++b) {
      consider(normals[a] + normals[b]);
      if (k > 24) continue;
      for (size_t c = b + 1; c < k; ++c) {
        Vec3 d = (normals[a] - normals[b]).cross(normals[a] - normals[c]);
        if (d.dot(normals[a]) < 0) d = -d;
        consider(d);
      }
    }
  }
}

}  // namespace hdm::mesh::detail
