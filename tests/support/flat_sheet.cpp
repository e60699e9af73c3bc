// SPDX-License-Identifier: MIT
#include "flat_sheet.h"

#include <algorithm>
#include <cmath>

namespace hdm::test {

SlabModel flat_sheet() {
  SlabModel m;
  m.grid_n = 16;
  m.texel_density = 1;
  for (int j = 0; j <= kSheetQuads; ++j)
    for (int i = 0; i <= kSheetQuads; ++i) {
      const double x = -kSheetHalf + 2 * kSheetHalf * i / kSheetQuads,
                   y = -kSheetHalf + 2 * kSheetHalf * j / kSheetQuads;
      m.inner.emplace_back(x, y, -1.0);
      m.outer.emplace_back(x, y, 1.0);
    }
  auto v = [](int i, int j) { return j * (kSheetQuads + 1) + i; };
  for (int j = 0; j < kSheetQuads; ++j)
    for (int i = 0; i < kSheetQuads; ++i) {
      m.slabs.push_back({v(i, j), v(i + 1, j), v(i + 1, j + 1)});
      m.slabs.push_back({v(i, j), v(i + 1, j + 1), v(i, j + 1)});
    }
  const int64_t C = (kSheetQuads + 1) * (kSheetQuads + 1),
                E = 2 * kSheetQuads * (kSheetQuads + 1) + kSheetQuads * kSheetQuads, S = 2 * kSheetQuads * kSheetQuads,
                k = m.grid_n;
  m.displacement.assign(size_t(C + E * (k - 1) + S * (k - 1) * (k - 2) / 2), 0.5f);
  rebuild_derived(m);
  return m;
}

void locate_on_sheet(double x, double y, int32_t& slab, Vec3& bary) {
  const double qx = (x + kSheetHalf) / (2 * kSheetHalf) * kSheetQuads,
               qy = (y + kSheetHalf) / (2 * kSheetHalf) * kSheetQuads;
  const int i = std::clamp(int(qx), 0, kSheetQuads - 1), j = std::clamp(int(qy), 0, kSheetQuads - 1);
  const double u = qx - i, w = qy - j;
  const bool lower = u >= w;
  slab = 2 * (j * kSheetQuads + i) + (lower ? 0 : 1);
  bary = lower ? Vec3(1 - u, u - w, w) : Vec3(1 - w, u, w - u);
}

double removed_volume(const SlabModel& m, const std::vector<Vec3>& before) {
  std::vector<Vec3> after;
  std::vector<Tri> faces;
  displaced_surface(m, after, faces);
  double v = 0;
  for (const Tri& f : faces) {
    const Vec3 &a = before[f[0]], &b = before[f[1]], &c = before[f[2]];
    const double area = 0.5 * std::abs((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
    double drop = 0;
    for (int k = 0; k < 3; ++k) drop += before[f[k]].z() - after[f[k]].z();
    v += area * drop / 3;
  }
  return v;
}

}  // namespace hdm::test
