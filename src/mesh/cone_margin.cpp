// SPDX-License-Identifier: MIT
// The cone margin of a vertex star (the best direction's smallest dot product with its face
// normals; positive when its dual cone is not empty): the decimation's test.
#include "simplifier.h"

#include "max_min_direction.h"

#include <algorithm>
#include <cmath>

namespace hdm::mesh::detail {

double smallest_angle_sine(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double l0 = (b - c).squaredNorm(), l1 = (c - a).squaredNorm(), l2 = (a - b).squaredNorm();
  const double twice_area = (b - a).cross(c - a).norm();
  const double shortest = std::min({l0, l1, l2});
  const double longer = l0 * l1 * l2 / std::max(shortest, 1e-300);  // product of the two longer
  return longer > 0 ? twice_area / std::sqrt(longer) : 0;
}

double cone_margin(const std::vector<Vec3>& normals) {
  Vec3 d = Vec3::Zero();
  for (const Vec3& n : normals) d += n;
  if (!(d.norm() > 0)) return -1;
  d.normalize();
  double best = -2;
  for (int it = 0; it < 8; ++it) {
    double worst = 2;
    Vec3 wn = Vec3::Zero();
    for (const Vec3& n : normals)
      if (const double v = d.dot(n); v < worst) worst = v, wn = n;
    best = std::max(best, worst);
    if (worst > 0.5) break;
    d = (d + 0.5 * wn).normalized();
  }
  return best;
}

double exact_cone_margin(const std::vector<Vec3>& normals) {
  double best = cone_margin(normals);
  if (best <= 0.5) mesh::detail::improve_max_min_figure(normals, best);
  return best;
}

namespace {

// exact_cone_margin() with hull_origin()'s verdict on @p normals known.
double exact_cone_margin(const std::vector<Vec3>& normals, HullOrigin where, const Vec3& x) {
  double best = cone_margin(normals);
  if (best <= 0.5) mesh::detail::improve_max_min_figure(normals, best, where, x);
  return best;
}

}  // namespace

bool cone_margin_kept(const std::vector<Vec3>& after, const std::vector<Vec3>& before, double enough) {
  Vec3 xa, xb;
  const HullOrigin a = hull_origin(after, xa), b = hull_origin(before, xb);
  if (a == HullOrigin::Holds && b == HullOrigin::Outside)
    return false;  // the margin above kHullHoldsOrigin is the larger
  const double will = exact_cone_margin(after, a, xa);
  if (will > enough) return true;
  if (a == HullOrigin::Outside && b == HullOrigin::Holds) return true;
  return will >= exact_cone_margin(before, b, xb);
}

}  // namespace hdm::mesh::detail
