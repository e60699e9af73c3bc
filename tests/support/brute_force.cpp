// SPDX-License-Identifier: MIT
#include "support/brute_force.h"

#include <algorithm>

namespace hdm::test {

Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;  // vertex region a
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;  // vertex region b
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;  // edge region ab
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;  // vertex region c
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;  // edge region ac
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)  // edge region bc
    return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double v = vb / (va + vb + vc), w = vc / (va + vb + vc);  // face region: barycentric
  return a + v * ab + w * ac;
}

double brute_distance(const Vec3& p, const TriangleMesh& m) {
  double best = 1e300;
  for (const Tri& t : m.faces)
    best = std::min(best, (closest_on_triangle(p, m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]) - p).norm());
  return best;
}


}  // namespace hdm::test
