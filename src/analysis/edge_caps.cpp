// SPDX-License-Identifier: MIT
// Where a slab model is faulty, the longest coarse edge the next decimation may leave.
#include "edge_caps.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace hdm::analysis::detail {

void tighten_edge_caps(const SlabModel& model, const TriangleMesh& in, const std::vector<int32_t>& faulty,
                       const std::vector<Vec3>& far_points, std::vector<double>& max_edge) {
  if (max_edge.size() != in.vertices.size()) max_edge.assign(in.vertices.size(), INFINITY);
  // The shell's mid-surface: one triangle per slab, halfway between its inner and outer corners,
  // so a point near the surface finds the slab whose columns sample it.
  TriangleMesh mid;
  mid.vertices.resize(model.inner.size());
  for (size_t v = 0; v < model.inner.size(); ++v) mid.vertices[v] = 0.5 * (model.inner[v] + model.outer[v]);
  mid.faces = model.slabs;
  const ExactMeshQuery shell(std::move(mid));
  const TriangleMesh& m = shell.mesh();
  std::vector<uint8_t> flagged(m.faces.size(), 0);
  for (int32_t s : faulty) flagged[s] = 1;
  for (const Vec3& p : far_points) {
    const ClosestPoint c = shell.closest_point(p);
    if (c.face >= 0) flagged[c.face] = 1;
  }
  // The flagged slabs alone, with their longest edges: every source vertex within half that
  // length of one (its corners, and the input it samples) gets half that length as its cap.
  TriangleMesh bad;
  bad.vertices = m.vertices;
  std::vector<double> longest;
  for (size_t s = 0; s < m.faces.size(); ++s) {
    if (!flagged[s]) continue;
    const Tri& t = m.faces[s];
    double l = 0;
    for (int k = 0; k < 3; ++k) l = std::max(l, (m.vertices[t[k]] - m.vertices[t[(k + 1) % 3]]).norm());
    bad.faces.push_back(t);
    longest.push_back(l);
  }
  if (bad.faces.empty()) return;
  const double reach = 0.5 * *std::max_element(longest.begin(), longest.end());
  const ExactMeshQuery faulty_shell(std::move(bad));
  tbb::parallel_for(size_t(0), in.vertices.size(), [&](size_t v) {
    const ClosestPoint c = faulty_shell.closest_point(in.vertices[v], reach);
    if (c.face >= 0 && c.distance <= 0.5 * longest[c.face]) max_edge[v] = std::min(max_edge[v], 0.5 * longest[c.face]);
  });
}

}  // namespace hdm::analysis::detail
