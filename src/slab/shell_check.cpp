// SPDX-License-Identifier: MIT
#include <hdm/slab/shell_check.h>
#include <hdm/core/error.h>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <string>

namespace hdm {

int count_invalid_slabs(const SlabModel& m) {
  int bad = 0;
  for (int s = 0; s < m.slab_count(); ++s) {
    const Tri& t = m.slabs[s];
    bad += slab_min_jacobian(m.geometry[s], m.outer[t[1]] - m.inner[t[1]], m.outer[t[2]] - m.inner[t[2]]) <= 0;
  }
  return bad;
}

namespace {

using Pair = std::pair<int32_t, int32_t>;

// Boundary pairs among the slabs listed in `set` (see count_overlapping_pairs()): the boundary
// triangles of those slabs in one BVH, each of their boundary edges cast against it once (an edge
// on several slabs' boundaries, such as a coarse vertex's ray or an inner edge, for all of them:
// about 6.5 casts per slab instead of 24). A pair is kept when `keep(a, b)` holds. Sorted, unique.
template <class Keep>
std::vector<Pair> pairs_among(const SlabModel& m, const std::vector<int32_t>& set, Keep keep) {
  // Boundary triangles of every listed slab; vertex ids: inner v -> v, outer v -> C + v.
  const int C = m.coarse_vertex_count();
  TriangleMesh shell;
  shell.vertices = m.inner;
  shell.vertices.insert(shell.vertices.end(), m.outer.begin(), m.outer.end());
  shell.faces.reserve(8 * set.size());
  std::vector<int32_t> owner;
  owner.reserve(8 * set.size());
  for (int32_t s : set) {
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
  if (shell.faces.empty()) return {};
  const ExactMeshQuery bvh(shell, BvhQuality::medium);  // about three segments per triangle
  auto shares_vertex = [&](int a, int b) {
    for (int32_t x : m.slabs[a])
      for (int32_t y : m.slabs[b])
        if (x == y) return true;
    return false;
  };
  // (edge, slab) for every boundary edge: sorted, each edge's slabs are one run.
  std::vector<std::pair<uint64_t, int32_t>> edges;
  edges.reserve(3 * shell.faces.size());
  for (size_t f = 0; f < shell.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const auto [lo, hi] = std::minmax(shell.faces[f][k], shell.faces[f][(k + 1) % 3]);
      edges.emplace_back(uint64_t(uint32_t(lo)) << 32 | uint32_t(hi), owner[f]);
    }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  std::vector<size_t> run;  // start of each edge's run, and the end
  for (size_t e = 0; e < edges.size(); ++e)
    if (e == 0 || edges[e].first != edges[e - 1].first) run.push_back(e);
  run.push_back(edges.size());
  tbb::enumerable_thread_specific<std::vector<Pair>> found;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, run.size() - 1, 256), [&](const tbb::blocked_range<size_t>& r) {
    std::vector<Pair>& acc = found.local();
    std::vector<SegmentHit> hits;
    for (size_t k = r.begin(); k < r.end(); ++k) {
      const uint64_t key = edges[run[k]].first;
      bvh.segment_hits(shell.vertices[key >> 32], shell.vertices[key & 0xffffffffu], hits);
      for (const SegmentHit& h : hits)
        for (size_t e = run[k]; e < run[k + 1]; ++e) {
          const int a = edges[e].second, b = owner[h.face];
          if (a != b && !shares_vertex(a, b) && keep(a, b)) acc.push_back(std::minmax(a, b));
        }
    }
  });
  std::vector<Pair> pairs;
  for (const std::vector<Pair>& v : found) pairs.insert(pairs.end(), v.begin(), v.end());
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

}  // namespace

std::vector<std::pair<int32_t, int32_t>> overlapping_pairs(const SlabModel& m) {
  std::vector<int32_t> all(m.slab_count());
  for (int s = 0; s < m.slab_count(); ++s) all[s] = s;
  return pairs_among(m, all, [](int, int) { return true; });
}

void update_overlapping_pairs(const SlabModel& m, const std::vector<uint8_t>& moved, std::vector<Pair>& pairs) {
  const int S = m.slab_count();
  if (moved.size() != static_cast<size_t>(S))
    throw InvalidInput("update_overlapping_pairs: " + std::to_string(moved.size()) + " moved flags for " +
                       std::to_string(S) + " slabs");
  std::vector<int32_t> moved_ids;
  for (int s = 0; s < S; ++s)
    if (moved[s]) moved_ids.push_back(s);
  if (moved_ids.empty()) return;
  if (moved_ids.size() > static_cast<size_t>(S) / 8) {
    pairs = overlapping_pairs(m);
    return;
  }
  // Box of each slab's six corners: its boundary triangles have their vertices among the corners,
  // so they lie in it, and two slabs whose boundaries cross have overlapping boxes.
  std::vector<Aabb> box(S);
  tbb::parallel_for(0, S, [&](int s) {
    for (int32_t v : m.slabs[s]) box[s].extend(m.inner[v]), box[s].extend(m.outer[v]);
  });
  auto overlap = [](const Aabb& a, const Aabb& b) {
    return (a.min.array() <= b.max.array()).all() && (b.min.array() <= a.max.array()).all();
  };
  std::vector<uint8_t> in_set(S, 0);
  tbb::parallel_for(0, S, [&](int s) {
    if (moved[s]) {
      in_set[s] = 1;
      return;
    }
    for (int32_t k : moved_ids)
      if (overlap(box[s], box[k])) {
        in_set[s] = 1;
        return;
      }
  });
  std::vector<int32_t> set;
  for (int s = 0; s < S; ++s)
    if (in_set[s]) set.push_back(s);
  std::vector<Pair> fresh = pairs_among(m, set, [&](int a, int b) { return moved[a] || moved[b]; });
  std::erase_if(pairs, [&](const Pair& p) { return moved[p.first] || moved[p.second]; });
  pairs.insert(pairs.end(), fresh.begin(), fresh.end());
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
}

int64_t count_overlapping_pairs(const SlabModel& m) { return static_cast<int64_t>(overlapping_pairs(m).size()); }

int64_t count_undercut_columns(const SlabModel& m, const ExactMeshQuery& input) {
  return tbb::parallel_reduce(
      tbb::blocked_range<int>(0, m.samples.count, 512), int64_t(0),
      [&](const tbb::blocked_range<int>& r, int64_t n) {
        std::vector<SegmentHit> hits;
        for (int s = r.begin(); s < r.end(); ++s) {
          Vec3 p0, p1;
          projection_line(m, m.samples.home(s).slab, m.samples.home(s).index, p0, p1);
          input.segment_hits(p1, p0, hits);
          n += hits.size() > 1;
        }
        return n;
      },
      [](int64_t a, int64_t b) { return a + b; });
}

}  // namespace hdm
