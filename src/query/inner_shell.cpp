// SPDX-License-Identifier: MIT
#include <hdm/query/inner_shell.h>

#include <algorithm>
#include <cmath>

namespace hdm {

InnerShell::InnerShell(const SlabModel& model) {
  closed_ = !model.edge_neighbour.empty();
  for (const auto& e : model.edge_neighbour)
    for (int32_t s : e) closed_ &= s >= 0;
  const int ns = model.slab_count();
  tris_.resize(ns);
  std::vector<Vec3> centres(ns);
  for (int s = 0; s < ns; ++s) {
    const Tri& t = model.slabs[s];
    tris_[s] = {model.inner[t[0]], model.inner[t[1]], model.inner[t[2]]};
    centres[s] = (tris_[s][0] + tris_[s][1] + tris_[s][2]) / 3;
  }
  nodes_.reserve(2 * ns);
  build(0, ns, centres);
}

// Median split on the longest axis of the centres' box; leaves of up to 4 triangles.
int InnerShell::build(int32_t begin, int32_t end, std::vector<Vec3>& centres) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.push_back({});
  Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY), clo = lo, chi = hi;
  for (int32_t k = begin; k < end; ++k) {
    for (const Vec3& v : tris_[k]) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    clo = clo.cwiseMin(centres[k]), chi = chi.cwiseMax(centres[k]);
  }
  for (int a = 0; a < 3; ++a) {
    nodes_[index].lo[a] = std::nextafter(static_cast<float>(lo[a]), -INFINITY);
    nodes_[index].hi[a] = std::nextafter(static_cast<float>(hi[a]), INFINITY);
  }
  if (end - begin <= 4) {
    nodes_[index].first = begin;
    nodes_[index].count = end - begin;
    return index;
  }
  int axis;
  (chi - clo).maxCoeff(&axis);
  const int32_t mid = (begin + end) / 2;
  // Sort triangles and their centres together through an index permutation.
  std::vector<int32_t> perm(end - begin);
  for (int32_t k = begin; k < end; ++k) perm[k - begin] = k;
  std::nth_element(perm.begin(), perm.begin() + (mid - begin), perm.end(),
                   [&](int32_t a, int32_t b) { return centres[a][axis] < centres[b][axis]; });
  std::vector<std::array<Vec3, 3>> t(end - begin);
  std::vector<Vec3> c(end - begin);
  for (int32_t k = 0; k < end - begin; ++k) t[k] = tris_[perm[k]], c[k] = centres[perm[k]];
  std::copy(t.begin(), t.end(), tris_.begin() + begin);
  std::copy(c.begin(), c.end(), centres.begin() + begin);
  build(begin, mid, centres);
  const int right = build(mid, end, centres);
  nodes_[index].first = right;
  nodes_[index].count = 0;
  return index;
}

// Crossings of the ray p + t·d (t > 0) with the shell: slab-test traversal, Möller-Trumbore
// (Möller & Trumbore 1997) in double precision.
int InnerShell::crossings(const Vec3& p, const Vec3& d) const noexcept {
  const Vec3 inv = d.cwiseInverse();
  int32_t stack[128];
  int top = 0, count = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[stack[--top]];
    double t0 = 0, t1 = INFINITY;
    for (int a = 0; a < 3; ++a) {
      double ta = (n.lo[a] - p[a]) * inv[a], tb = (n.hi[a] - p[a]) * inv[a];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta), t1 = std::min(t1, tb);
    }
    if (t0 > t1) continue;
    if (n.count > 0) {
      for (int32_t k = n.first; k < n.first + n.count; ++k) {
        const auto& t = tris_[k];
        const Vec3 e1 = t[1] - t[0], e2 = t[2] - t[0], q = d.cross(e2);
        const double det = e1.dot(q);
        if (det == 0) continue;
        const double f = 1 / det;
        const Vec3 s = p - t[0];
        const double u = f * s.dot(q);
        if (u < 0 || u > 1) continue;
        const Vec3 r = s.cross(e1);
        const double v = f * d.dot(r);
        if (v < 0 || u + v > 1) continue;
        count += f * e2.dot(r) > 0;
      }
    } else if (top < 126) {
      stack[top++] = n.first;
      stack[top++] = static_cast<int32_t>(&n - nodes_.data()) + 1;
    }
  }
  return count;
}

bool InnerShell::encloses(const Vec3& p) const noexcept {
  if (nodes_.empty() || !p.allFinite()) return false;
  const Node& root = nodes_[0];
  for (int a = 0; a < 3; ++a)
    if (p[a] < root.lo[a] || p[a] > root.hi[a]) return false;
  static const Vec3 dirs[3] = {Vec3(0.5773, 0.5774, 0.5771).normalized(), Vec3(-0.3141, 0.8523, -0.4182).normalized(),
                               Vec3(0.7071, -0.1234, -0.6963).normalized()};
  int votes = 0;
  for (const Vec3& d : dirs) votes += crossings(p, d) % 2;
  return votes >= 2;
}

size_t InnerShell::memory_bytes() const noexcept {
  return tris_.capacity() * sizeof(tris_[0]) + nodes_.capacity() * sizeof(Node);
}

}  // namespace hdm
