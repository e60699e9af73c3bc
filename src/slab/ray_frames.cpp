// SPDX-License-Identifier: MIT
// Ray directions of the bake's coarse vertices (docs/design.md#ray-directions).
#include "ray_frames.h"

#include "../mesh/max_min_direction.h"

#include <algorithm>

namespace hdm::slab::detail {

double min_dot(const Vec3& d, const std::vector<Vec3>& normals) {
  double m = 2;
  for (const Vec3& n : normals) m = std::min(m, d.dot(n));
  return m;
}

// The unit direction that maximises the smallest dot product with the incident face normals (the
// centre of the smallest spherical cap holding them). The optimum is fixed by one, two or three
// active normals: try the area-weighted normal, every normal, every pair bisector and every triple
// circumcentre (small one-rings), keep the best.
Vec3 max_min_direction(const Vec3& start, const std::vector<Vec3>& normals) {
  Vec3 best = start;
  double best_val = min_dot(start, normals);
  if (best_val > 0.5) return best;  // the area-weighted normal is good enough: keep it (smooth field)
  mesh::detail::improve_max_min(normals, best_val, &best);
  return best;
}

// Per-vertex directions with a positive dot product against every incident face normal
// (docs/design.md#ray-directions: guarantees a positive Jacobian for a thin enough shell).
VertexFrame vertex_frames(const CoarseMesh& c, int smoothing) {
  const size_t nv = c.vertices.size();
  VertexFrame fr;
  fr.direction.assign(nv, Vec3::Zero());
  fr.edge.assign(nv, 0.0);
  std::vector<int> valence(nv, 0);
  fr.face_normal.resize(c.faces.size());
  fr.offsets.assign(nv + 1, 0);
  for (size_t f = 0; f < c.faces.size(); ++f) {
    const Tri& t = c.faces[f];
    const Vec3 n = (c.vertices[t[1]] - c.vertices[t[0]]).cross(c.vertices[t[2]] - c.vertices[t[0]]);
    fr.face_normal[f] = n.normalized();
    for (int a = 0; a < 3; ++a) {
      fr.direction[t[a]] += n;
      fr.edge[t[a]] += (c.vertices[t[(a + 1) % 3]] - c.vertices[t[a]]).norm() +
                       (c.vertices[t[(a + 2) % 3]] - c.vertices[t[a]]).norm();
      valence[t[a]] += 2;
      ++fr.offsets[t[a] + 1];
    }
  }
  for (size_t v = 0; v < nv; ++v) fr.offsets[v + 1] += fr.offsets[v];
  fr.faces.resize(fr.offsets[nv]);
  std::vector<int32_t> fill(fr.offsets.begin(), fr.offsets.end() - 1);
  for (size_t f = 0; f < c.faces.size(); ++f)
    for (int32_t v : c.faces[f]) fr.faces[fill[v]++] = static_cast<int32_t>(f);
  std::vector<Vec3> normals;
  for (size_t v = 0; v < nv; ++v) {
    fr.edge[v] /= std::max(valence[v], 1);
    normals.clear();
    for (int32_t k = fr.offsets[v]; k < fr.offsets[v + 1]; ++k) normals.push_back(fr.face_normal[fr.faces[k]]);
    fr.direction[v] = max_min_direction(fr.direction[v].normalized(), normals);
  }
  // Smooth the direction field: near-parallel rays on neighbouring vertices keep slabs prism-like,
  // so concave regions can take a thicker shell before an alpha-triangle folds. A smoothed
  // direction is kept only while it still sees every incident face (min dot >= 0.25, or no worse
  // than the max-min direction).
  for (int it = 0; it < smoothing; ++it) {
    std::vector<Vec3> next = fr.direction;
    for (size_t v = 0; v < nv; ++v) {
      Vec3 sum = fr.direction[v];
      for (int32_t k = fr.offsets[v]; k < fr.offsets[v + 1]; ++k)
        for (int32_t u : c.faces[fr.faces[k]]) sum += fr.direction[u];
      const Vec3 cand = sum.normalized();
      double mc = 2, mo = 2;
      for (int32_t k = fr.offsets[v]; k < fr.offsets[v + 1]; ++k)
        mc = std::min(mc, cand.dot(fr.face_normal[fr.faces[k]])),
        mo = std::min(mo, fr.direction[v].dot(fr.face_normal[fr.faces[k]]));
      if (mc >= std::min(0.25, mo)) next[v] = cand;
    }
    fr.direction = std::move(next);
  }
  return fr;
}

}  // namespace hdm::slab::detail
