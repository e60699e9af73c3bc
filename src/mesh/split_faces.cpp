// SPDX-License-Identifier: MIT
#include <hdm/mesh/split_faces.h>

#include <algorithm>
#include <cstdint>
#include <unordered_map>

namespace hdm {

TriangleMesh split_faces(const TriangleMesh& mesh, std::vector<double>* vertex_values) {
  TriangleMesh out;
  out.vertices = mesh.vertices;
  out.faces.reserve(4 * mesh.faces.size());
  std::unordered_map<uint64_t, int32_t> midpoint;
  midpoint.reserve(2 * mesh.faces.size());
  auto mid = [&](int32_t a, int32_t b) {
    const auto [lo, hi] = std::minmax(a, b);
    const uint64_t key = (uint64_t(uint32_t(lo)) << 32) | uint32_t(hi);
    const auto [it, added] = midpoint.try_emplace(key, static_cast<int32_t>(out.vertices.size()));
    if (added) {
      // From the smaller id, so both faces of the edge get the same point, bit for bit.
      out.vertices.push_back(0.5 * (mesh.vertices[lo] + mesh.vertices[hi]));
      if (vertex_values) {
        const double v = std::min((*vertex_values)[lo], (*vertex_values)[hi]);
        vertex_values->push_back(v);
      }
    }
    return it->second;
  };
  for (const Tri& t : mesh.faces) {
    const int32_t ab = mid(t[0], t[1]), bc = mid(t[1], t[2]), ca = mid(t[2], t[0]);
    out.faces.push_back({t[0], ab, ca});
    out.faces.push_back({ab, t[1], bc});
    out.faces.push_back({ca, bc, t[2]});
    out.faces.push_back({ab, bc, ca});
  }
  return out;
}

}  // namespace hdm
