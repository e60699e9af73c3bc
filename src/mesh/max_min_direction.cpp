// SPDX-License-Identifier: MIT
#include "max_min_direction.h"

#include <algorithm>

namespace hdm::mesh::detail {

void improve_max_min(const std::vector<Vec3>& normals, double& best_value, Vec3* best_direction) {
  auto consider = [&](Vec3 d) {
    const double len = d.norm();
    if (!(len > 1e-12)) return;
    d /= len;
    double worst = 2;
    for (const Vec3& n : normals)
      if ((worst = std::min(worst, d.dot(n))) <= best_value) return;
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
