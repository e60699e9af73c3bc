// SPDX-License-Identifier: MIT
#include <hdm/core/error.h>
#include <hdm/mesh/flip_slivers.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <unordered_map>
#include <unordered_set>

namespace hdm {
namespace {

uint64_t key(int32_t a, int32_t b) {
  if (a > b) std::swap(a, b);
  return (uint64_t(uint32_t(a)) << 32) | uint32_t(b);
}

// Smallest and largest angle of triangle (a, b, c) [radians].
std::pair<double, double> angles(const Vec3& a, const Vec3& b, const Vec3& c) {
  auto at = [](const Vec3& p, const Vec3& q, const Vec3& r) {
    const Vec3 u = q - p, v = r - p;
    return std::atan2(u.cross(v).norm(), u.dot(v));
  };
  const double x = at(a, b, c), y = at(b, c, a), z = at(c, a, b);
  return {std::min({x, y, z}), std::max({x, y, z})};
}

}  // namespace

int64_t flip_slivers(TriangleMesh& mesh, double min_angle_deg) {
  if (!(min_angle_deg > 0 && min_angle_deg < 60))
    throw InvalidInput("flip_slivers: min_angle_deg " + std::to_string(min_angle_deg) + " must be in (0, 60)");
  const double min_angle = min_angle_deg * std::numbers::pi / 180, cap_angle = 150 * std::numbers::pi / 180;
  const double cos_turn = std::cos(30 * std::numbers::pi / 180);
  const auto& p = mesh.vertices;
  int64_t flips = 0;
  for (int pass = 0; pass < 4; ++pass) {
    // Undirected edge -> the faces on it (two on an interior edge of an edge-manifold mesh).
    std::unordered_map<uint64_t, std::pair<int32_t, int32_t>> faces_of;
    faces_of.reserve(3 * mesh.faces.size());
    for (size_t f = 0; f < mesh.faces.size(); ++f)
      for (int k = 0; k < 3; ++k) {
        auto [it, fresh] = faces_of.try_emplace(key(mesh.faces[f][k], mesh.faces[f][(k + 1) % 3]), int32_t(f), -1);
        if (!fresh) it->second.second = int32_t(f);
      }
    std::vector<uint8_t> touched(mesh.faces.size(), 0);
    std::unordered_set<uint64_t> made;  // edges made in this pass
    int64_t before = flips;
    for (size_t f = 0; f < mesh.faces.size(); ++f) {
      if (touched[f]) continue;
      const Tri t = mesh.faces[f];
      const auto [lo, hi] = angles(p[t[0]], p[t[1]], p[t[2]]);
      if (!(lo < min_angle) || !(hi > cap_angle)) continue;
      // The longest edge (u, v), as ordered in f, and the apex a opposite it.
      int k = 0;
      double longest = -1;
      for (int j = 0; j < 3; ++j)
        if (const double l = (p[t[(j + 1) % 3]] - p[t[j]]).squaredNorm(); l > longest) longest = l, k = j;
      const int32_t u = t[k], v = t[(k + 1) % 3], a = t[(k + 2) % 3];
      const auto it = faces_of.find(key(u, v));
      if (it == faces_of.end() || it->second.second < 0) continue;  // a boundary edge
      const int32_t g = it->second.first == int32_t(f) ? it->second.second : it->second.first;
      if (touched[g]) continue;
      const Tri s = mesh.faces[g];
      int m = 0;
      while (m < 3 && !(s[m] == v && s[(m + 1) % 3] == u)) ++m;
      if (m == 3) continue;  // g runs (u, v) the same way: not consistently oriented
      const int32_t x = s[(m + 2) % 3];
      if (x == a || faces_of.count(key(a, x)) || made.count(key(a, x))) continue;
      // The quad u, x, v, a split by the diagonal (a, x): faces (u, x, a) and (x, v, a).
      const Tri n1{u, x, a}, n2{x, v, a};
      const double old_lo = std::min(lo, angles(p[s[0]], p[s[1]], p[s[2]]).first);
      const double new_lo =
          std::min(angles(p[n1[0]], p[n1[1]], p[n1[2]]).first, angles(p[n2[0]], p[n2[1]], p[n2[2]]).first);
      if (!(new_lo > old_lo)) continue;
      const Vec3 ng = (p[s[1]] - p[s[0]]).cross(p[s[2]] - p[s[0]]).normalized();
      bool turns = false;
      for (const Tri& n : {n1, n2}) {
        const Vec3 nn = (p[n[1]] - p[n[0]]).cross(p[n[2]] - p[n[0]]);
        turns |= !(nn.norm() > 0) || nn.normalized().dot(ng) < cos_turn;
      }
      if (turns) continue;
      mesh.faces[f] = n1;
      mesh.faces[g] = n2;
      touched[f] = touched[g] = 1;
      made.insert(key(a, x));
      ++flips;
    }
    if (flips == before) break;
  }
  return flips;
}

}  // namespace hdm
