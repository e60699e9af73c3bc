// SPDX-License-Identifier: MIT
#include <hdm/core/error.h>
#include <hdm/harness/voxel_surface.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

namespace hdm {

TriangleMesh voxel_surface(int nx, int ny, int nz, double h, const Vec3& origin,
                           const std::function<bool(int, int, int)>& solid) {
  if (nx < 1 || ny < 1 || nz < 1) throw InvalidInput("voxel_surface: nx, ny and nz must be >= 1");
  if (!(h > 0) || !std::isfinite(h)) throw InvalidInput("voxel_surface: h must be positive and finite");
  TriangleMesh m;
  std::map<std::tuple<int, int, int>, int32_t> id;
  auto vertex = [&](int i, int j, int k) {
    auto [it, added] = id.emplace(std::make_tuple(i, j, k), int32_t(m.vertices.size()));
    if (added) m.vertices.push_back(origin + h * Vec3(i, j, k));
    return it->second;
  };
  auto in = [&](int i, int j, int k) {
    return i >= 0 && j >= 0 && k >= 0 && i < nx && j < ny && k < nz && solid(i, j, k);
  };
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      for (int k = 0; k < nz; ++k) {
        if (!in(i, j, k)) continue;
        for (int axis = 0; axis < 3; ++axis)
          for (int side = 0; side < 2; ++side) {
            int c[3] = {i, j, k};
            c[axis] += side ? 1 : -1;
            if (in(c[0], c[1], c[2])) continue;
            // The face's four corners, counter-clockwise seen from outside.
            int base[3] = {i, j, k};
            base[axis] += side;
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            int q[4][3];
            for (int t = 0; t < 4; ++t) {
              std::copy(base, base + 3, q[t]);
              q[t][u] += (t == 1 || t == 2);
              q[t][v] += (t >= 2);
            }
            int32_t a[4];
            for (int t = 0; t < 4; ++t) a[t] = vertex(q[t][0], q[t][1], q[t][2]);
            if (side) {
              m.faces.push_back({a[0], a[1], a[2]});
              m.faces.push_back({a[0], a[2], a[3]});
            } else {
              m.faces.push_back({a[0], a[2], a[1]});
              m.faces.push_back({a[0], a[3], a[2]});
            }
          }
      }
  return m;
}

}  // namespace hdm
