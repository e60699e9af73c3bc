// SPDX-License-Identifier: MIT
#include <hdm/analysis/shell_check.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <set>

namespace hdm {

int count_invalid_slabs(const SlabModel& m) {
  int bad = 0;
  for (int s = 0; s < m.slab_count(); ++s) {
    const Tri& t = m.slabs[s];
    bad += slab_min_jacobian(m.geometry[s], m.outer[t[1]] - m.inner[t[1]], m.outer[t[2]] - m.inner[t[2]]) <= 0;
  }
  return bad;
}

std::vector<std::pair<int32_t, int32_t>> overlapping_pairs(const SlabModel& m) {
  // Boundary triangles of every slab; vertex ids: inner v -> v, outer v -> C + v.
  const int C = m.coarse_vertex_count();
  TriangleMesh shell;
  shell.vertices = m.inner;
  shell.vertices.insert(shell.vertices.end(), m.outer.begin(), m.outer.end());
  std::vector<int32_t> owner;
  for (int s = 0; s < m.slab_count(); ++s) {
    const Tri& t = m.slabs[s];
    shell.faces.push_back({t[0], t[2], t[1]});
    shell.faces.push_back({C + t[0], C + t[1], C + t[2]});
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      shell.faces.push_back({a, b, C + b});
      shell.faces.push_back({a, C + b, C + a});
    }
    owner.insert(owner.end(), 8, s);
  }
  const ExactMeshQuery bvh(shell);
  auto shares_vertex = [&](int a, int b) {
    for (int32_t x : m.slabs[a])
      for (int32_t y : m.slabs[b])
        if (x == y) return true;
    return false;
  };
  using Pairs = std::set<std::pair<int32_t, int32_t>>;
  const Pairs pairs = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, shell.faces.size(), 256), Pairs{},
      [&](const tbb::blocked_range<size_t>& r, Pairs acc) {
        std::vector<SegmentHit> hits;
        for (size_t f = r.begin(); f < r.end(); ++f)
          for (int k = 0; k < 3; ++k) {
            bvh.segment_hits(shell.vertices[shell.faces[f][k]], shell.vertices[shell.faces[f][(k + 1) % 3]], hits);
            for (const SegmentHit& h : hits) {
              const int a = owner[f], b = owner[h.face];
              if (a != b && !shares_vertex(a, b)) acc.insert(std::minmax(a, b));
            }
          }
        return acc;
      },
      [](Pairs a, const Pairs& b) {
        a.insert(b.begin(), b.end());
        return a;
      });
  return {pairs.begin(), pairs.end()};
}

int64_t count_overlapping_pairs(const SlabModel& m) { return static_cast<int64_t>(overlapping_pairs(m).size()); }

int64_t count_undercut_columns(const SlabModel& m, const ExactMeshQuery& input) {
  return tbb::parallel_reduce(
      tbb::blocked_range<int>(0, m.samples.count, 512), int64_t(0),
      [&](const tbb::blocked_range<int>& r, int64_t n) {
        std::vector<SegmentHit> hits;
        for (int s = r.begin(); s < r.end(); ++s) {
          Vec3 p0, p1;
          projection_line(m, m.samples.home_slab[s], m.samples.home_index[s], p0, p1);
          input.segment_hits(p1, p0, hits);
          n += hits.size() > 1;
        }
        return n;
      },
      [](int64_t a, int64_t b) { return a + b; });
}

}  // namespace hdm
