// SPDX-License-Identifier: MIT
#include "max_min_direction.h"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>

namespace hdm::mesh::detail {
namespace {

// The point of the affine hull of @p p[0 .. s) nearest the origin, as weights @p w summing to 1:
// x = p0 + B·b with B's columns p[i] - p0, and BᵀB b = -Bᵀp0. False when the points are affinely
// dependent to within rounding (the corral of Wolfe's algorithm never is in exact arithmetic).
bool affine_nearest(const Vec3* p, int s, double* w) {
  if (s == 1) {
    w[0] = 1;
    return true;
  }
  Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, 3> b(3, s - 1);
  for (int i = 1; i < s; ++i) b.col(i - 1) = p[i] - p[0];
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3, 3> g = b.transpose() * b;
  const Eigen::LDLT<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3, 3>> ldlt(g);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 1e-14 * g.trace())) return false;
  const Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 3, 1> c = ldlt.solve(-(b.transpose() * p[0]));
  w[0] = 1 - c.sum();
  for (int i = 1; i < s; ++i) w[i] = c[i - 1];
  return true;
}

}  // namespace

bool nearest_hull_point(const std::vector<Vec3>& points, Vec3& x) {
  // Wolfe, "Finding the nearest point in a polytope", Math. Programming 11 (1976): a corral S of
  // affinely independent points (at most 4 in 3D) with positive weights λ; each major cycle adds
  // the point most against x, each minor cycle moves towards S's affine nearest point and drops
  // the points whose weight reaches 0.
  if (points.empty()) return false;
  Vec3 s[4];
  double lambda[4], alpha[4];
  int n = 1;
  s[0] = *std::min_element(points.begin(), points.end(),
                           [](const Vec3& a, const Vec3& b) { return a.squaredNorm() < b.squaredNorm(); });
  lambda[0] = 1;
  x = s[0];
  double scale = 0;
  for (const Vec3& p : points) scale = std::max(scale, p.squaredNorm());
  const double origin = kHullHoldsOrigin * kHullHoldsOrigin * scale, gap = 1e-14 * scale;
  for (int major = 0; major < 64; ++major) {
    if (x.squaredNorm() <= origin) return true;  // the hull holds the origin
    const Vec3* far = &points[0];
    for (const Vec3& p : points)
      if (p.dot(x) < far->dot(x)) far = &p;
    if (far->dot(x) >= x.squaredNorm() - gap) return true;           // no point is beyond x's plane: x is nearest
    if (n == 4 || std::find(s, s + n, *far) != s + n) return false;  // rounding: no progress
    s[n] = *far, lambda[n] = 0, ++n;
    for (int minor = 0;; ++minor) {
      if (minor > 8 || !affine_nearest(s, n, alpha)) return false;
      if (*std::min_element(alpha, alpha + n) > 0) {
        std::copy(alpha, alpha + n, lambda);
        break;
      }
      double theta = 1;  // the furthest step from λ towards α that keeps every weight >= 0
      for (int i = 0; i < n; ++i)
        if (alpha[i] <= 0 && lambda[i] - alpha[i] > 0) theta = std::min(theta, lambda[i] / (lambda[i] - alpha[i]));
      int kept = 0;
      for (int i = 0; i < n; ++i) {
        const double w = theta * alpha[i] + (1 - theta) * lambda[i];
        if (w > 1e-15) s[kept] = s[i], lambda[kept] = w, ++kept;
      }
      n = kept;
      if (n == 0) return false;
    }
    x = Vec3::Zero();
    for (int i = 0; i < n; ++i) x += lambda[i] * s[i];
  }
  return false;
}

HullOrigin hull_origin(const std::vector<Vec3>& normals, Vec3& x) {
  if (!nearest_hull_point(normals, x)) return HullOrigin::Undecided;
  return x.norm() <= kHullHoldsOrigin ? HullOrigin::Holds : HullOrigin::Outside;
}

void improve_max_min_figure(const std::vector<Vec3>& normals, double& best_value, HullOrigin where, const Vec3& x) {
  // Where a direction sees every normal (the origin outside their hull), the optimum is the hull's
  // nearest point to the origin, normalised: max over unit d of min d·n = min over the hull of |p|
  // (von Neumann's minimax theorem), found in a few O(k) cycles instead of O(k^3) candidates. Up
  // to 24 normals, where the candidates give the optimum too: above, they give the best normal or
  // pair, and the decimation's collapses follow that figure (the exact one changed them, making a
  // printer bed 6 times the slabs).
  if (normals.size() <= 24 && where == HullOrigin::Outside) {
    const Vec3 d = x.normalized();
    double worst = 2;
    for (const Vec3& n : normals) worst = std::min(worst, d.dot(n));
    best_value = std::max(best_value, worst);
    return;
  }
  improve_max_min(normals, best_value, nullptr);
}

void improve_max_min_figure(const std::vector<Vec3>& normals, double& best_value) {
  Vec3 x = Vec3::Zero();
  const HullOrigin where = normals.size() <= 24 ? hull_origin(normals, x) : HullOrigin::Undecided;
  improve_max_min_figure(normals, best_value, where, x);
}

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
