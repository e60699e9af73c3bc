// SPDX-License-Identifier: MIT
// Stars no direction sees, after the queue: merged into a neighbour, a crumple merged whole, or the vertex removed.
#include "simplifier.h"

#include "max_min_direction.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <tuple>

namespace hdm::mesh::detail {

void Simplifier::clean_folds() {
  for (int pass = 0; pass < 4; ++pass) {
    bool any = false;
    for (int32_t v = 0; v < static_cast<int32_t>(pos_.size()); ++v) {
      if (!alive_[v] || vertex_cone_margin(v) > kEmptyCone) continue;
      ring(v, fold_ring_);
      const std::vector<int32_t> around = fold_ring_;
      bool done = false;
      for (int32_t u : around)
        if (alive_[u] && collapse(u, v, true)) {
          done = true;
          break;
        }
      if (!done) done = remove_vertex(v);
      if (!done) done = collapse_cluster(v);
      any |= done;
    }
    if (!any) break;
  }
}

bool Simplifier::collapse_cluster(int32_t v) {
  std::vector<int32_t> around, cluster, region, near;
  ring(v, around);
  if (around.empty()) return false;
  double mean = 0;
  for (int32_t u : around) mean += (pos_[u] - pos_[v]).norm();
  mean /= double(around.size());
  auto has = [](const std::vector<int32_t>& s, int32_t x) { return std::find(s.begin(), s.end(), x) != s.end(); };
  for (const double r : {0.25 * mean, 0.5 * mean, mean}) {
    cluster.assign(1, v);
    for (size_t i = 0; i < cluster.size() && cluster.size() <= 32; ++i) {
      ring(cluster[i], near);
      for (int32_t w : near)
        if ((pos_[w] - pos_[v]).norm() < r && !has(cluster, w)) cluster.push_back(w);
    }
    if (cluster.size() < 2) continue;
    if (cluster.size() > 32) break;
    region = cluster;
    for (int32_t c : cluster) {
      ring(c, near);
      for (int32_t w : near)
        if (!has(region, w)) region.push_back(w);
    }
    std::vector<uint8_t> was(region.size());
    int64_t before = 0;
    for (size_t i = 0; i < region.size(); ++i) before += was[i] = vertex_cone_margin(region[i]) <= kEmptyCone;
    const Journal saved = journal(region);  // region starts with the cluster
    forced_ = true;
    for (bool merged = true; merged;) {
      merged = false;
      for (size_t i = 1; i < cluster.size(); ++i) {
        if (!alive_[cluster[i]]) continue;
        ring(v, near);
        if (std::binary_search(near.begin(), near.end(), cluster[i]) && collapse(v, cluster[i])) merged = true;
      }
    }
    forced_ = false;
    bool all = true;
    for (size_t i = 1; i < cluster.size(); ++i) all &= !alive_[cluster[i]];
    ring(v, near);
    near.push_back(v);
    // The merged vertex at each cluster vertex's place and at the cluster's centroid; the place
    // with the fewest empty-cone vertices around, then the best seen worst star, is kept.
    std::vector<Vec3> places;
    Vec3 centroid = Vec3::Zero();
    for (size_t i = 0; i < cluster.size(); ++i) places.push_back(saved.pos[i]), centroid += saved.pos[i];
    places.push_back(centroid / double(cluster.size()));
    int64_t after = 0;
    bool newly = false;
    double worst = -2;
    Vec3 best_place = pos_[v];
    for (size_t p = 0; p < places.size(); ++p) {
      pos_[v] = places[p];
      int64_t count = 0;
      bool fresh = false;
      double low = 2;
      for (int32_t w : near) {
        const double seen = vertex_cone_margin(w);
        const bool f = seen <= kEmptyCone;
        count += f;
        low = std::min(low, seen);
        const auto it = std::find(region.begin(), region.end(), w);
        fresh |= f && (it == region.end() || !was[it - region.begin()]);
      }
      if (p > 0 && std::make_tuple(fresh, count, -low) >= std::make_tuple(newly, after, -worst)) continue;
      after = count, newly = fresh, worst = low, best_place = places[p];
    }
    pos_[v] = best_place;
    if (all && after < before && !newly) {
      for (int32_t w : near) empty_cone_[w] = vertex_cone_margin(w) <= kEmptyCone;
      return true;
    }
    restore(saved);
  }
  return false;
}

Simplifier::Journal Simplifier::journal(const std::vector<int32_t>& region) {
  Journal j;
  j.vertices = region;  // the cluster first: collapse_cluster() reads its places
  for (int32_t v : j.vertices) {
    for_faces(v, [&](int32_t f, int) { j.faces.push_back(f); });
    j.pos.push_back(pos_[v]), j.quadric.push_back(quadric_[v]), j.head.push_back(head_[v]);
    j.version.push_back(version_[v]), j.cone_angle.push_back(cone_angle_[v]), j.alive.push_back(alive_[v]);
    j.empty_cone.push_back(empty_cone_[v]), j.retry.push_back(retry_[v]);
  }
  std::sort(j.faces.begin(), j.faces.end());
  j.faces.erase(std::unique(j.faces.begin(), j.faces.end()), j.faces.end());
  for (int32_t f : j.faces) {
    j.face.push_back(faces_[f]), j.alive_face.push_back(alive_face_[f]);
    for (int k = 0; k < 3; ++k) j.next.push_back(next_[3 * f + k]);
  }
  j.faces_left = faces_left_, j.collapses = collapses_;
  return j;
}

void Simplifier::restore(const Journal& j) {
  for (size_t i = 0; i < j.vertices.size(); ++i) {
    const int32_t v = j.vertices[i];
    pos_[v] = j.pos[i], quadric_[v] = j.quadric[i], head_[v] = j.head[i], version_[v] = j.version[i];
    cone_angle_[v] = j.cone_angle[i], alive_[v] = j.alive[i], empty_cone_[v] = j.empty_cone[i], retry_[v] = j.retry[i];
  }
  for (size_t i = 0; i < j.faces.size(); ++i) {
    const int32_t f = j.faces[i];
    faces_[f] = j.face[i], alive_face_[f] = j.alive_face[i];
    for (int k = 0; k < 3; ++k) next_[3 * f + k] = j.next[3 * i + k];
  }
  faces_left_ = j.faces_left, collapses_ = j.collapses;
}

bool Simplifier::remove_vertex(int32_t v) {
  // The ring in order: faces (v, r_j, r_j+1) counter-clockwise.
  std::vector<std::pair<int32_t, int32_t>> spokes;  // (r_j, r_j+1) of each face of v
  std::vector<int32_t> star;
  for_faces(v, [&](int32_t f, int k) {
    spokes.emplace_back(faces_[f][(k + 1) % 3], faces_[f][(k + 2) % 3]);
    star.push_back(f);
  });
  const size_t k = spokes.size();
  if (k < 3) return false;
  std::vector<int32_t> cycle{spokes[0].first};
  for (size_t step = 0; step < k; ++step) {
    const int32_t last = cycle.back();
    auto it = std::find_if(spokes.begin(), spokes.end(), [&](const auto& sp) { return sp.first == last; });
    if (it == spokes.end()) return false;  // a boundary vertex, or not a disc
    cycle.push_back(it->second);
  }
  if (cycle.back() != cycle.front()) return false;
  cycle.pop_back();
  if (cycle.size() != k) return false;
  std::vector<int32_t> sorted = cycle;
  std::sort(sorted.begin(), sorted.end());
  if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return false;
  // Stars of the ring vertices without v's faces, and how well they are seen now.
  double before = 2;
  for (int32_t r : cycle) before = std::min(before, vertex_cone_margin(r));
  int best_root = -1;
  double best = -2;
  std::vector<int32_t> around;
  for (size_t root = 0; root < k; ++root) {
    // Fan from cycle[root]: diagonals (root, j) must not be edges already.
    const int32_t r0 = cycle[root];
    ring(r0, around);
    bool ok = true;
    for (size_t j = 2; j + 1 < k && ok; ++j)
      ok = !std::binary_search(around.begin(), around.end(), cycle[(root + j) % k]);
    if (!ok) continue;
    double worst = 2;
    for (size_t i = 0; i < k && worst > best; ++i) {
      const int32_t r = cycle[i];
      after_.clear();
      for_faces(r, [&](int32_t f, int) {
        const Tri& t = faces_[f];
        if (t[0] == v || t[1] == v || t[2] == v) return;
        const Vec3 n = face_normal(f);
        if (n.norm() > 0) after_.push_back(n.normalized());
      });
      for (size_t j = 1; j + 1 < k; ++j) {
        const int32_t p = cycle[(root + j) % k], q = cycle[(root + j + 1) % k];
        if (r != r0 && r != p && r != q) continue;
        const Vec3 n = (pos_[p] - pos_[r0]).cross(pos_[q] - pos_[r0]);
        if (!(n.norm() > 0))
          after_.push_back(Vec3::Zero());
        else
          after_.push_back(n.normalized());
      }
      worst = std::min(worst, cone_margin(after_));
    }
    if (worst > best) best = worst, best_root = static_cast<int>(root);
  }
  if (best_root < 0 || !(best > before + 1e-3)) return false;
  for (int32_t f : star) alive_face_[f] = 0, --faces_left_;
  const int32_t r0 = cycle[best_root];
  for (size_t j = 1; j + 1 < k; ++j) {
    const Tri t{r0, cycle[(best_root + j) % k], cycle[(best_root + j + 1) % k]};
    const auto f = static_cast<int32_t>(faces_.size());
    faces_.push_back(t);
    alive_face_.push_back(1);
    ++faces_left_;
    for (int c = 0; c < 3; ++c) {
      next_.push_back(head_[t[c]]);
      head_[t[c]] = 3 * f + c;
    }
  }
  alive_[v] = 0;
  head_[v] = -1;
  for (int32_t r : cycle) cone_angle_[r] = std::numbers::pi, ++version_[r];
  return true;
}

}  // namespace hdm::mesh::detail
