// SPDX-License-Identifier: MIT
// Decimation by checked edge collapses: Garland–Heckbert quadrics with feature planes, a lazy
// priority queue, and the link condition, so the coarse mesh keeps the input's topology.
#include <hdm/core/error.h>
#include <hdm/mesh/decimate_mesh.h>

#include "max_min_direction.h"

#include <algorithm>
#include <cmath>
#include <queue>
#include <string>
#include <tuple>
#include <vector>

namespace hdm {
namespace {

// Symmetric 4×4 quadric of weighted squared plane distances, Q(x) = xᵀAx + 2b·x + c, stored as
// the 10 distinct entries (Garland & Heckbert 1997).
struct Quadric {
  double a00 = 0, a01 = 0, a02 = 0, a11 = 0, a12 = 0, a22 = 0, b0 = 0, b1 = 0, b2 = 0, c = 0;

  // Plane n·x + d = 0 (unit n) with weight w.
  void add_plane(const Vec3& n, double d, double w) {
    a00 += w * n.x() * n.x(), a01 += w * n.x() * n.y(), a02 += w * n.x() * n.z();
    a11 += w * n.y() * n.y(), a12 += w * n.y() * n.z(), a22 += w * n.z() * n.z();
    b0 += w * d * n.x(), b1 += w * d * n.y(), b2 += w * d * n.z(), c += w * d * d;
  }
  Quadric operator+(const Quadric& o) const {
    return {a00 + o.a00, a01 + o.a01, a02 + o.a02, a11 + o.a11, a12 + o.a12,
            a22 + o.a22, b0 + o.b0,   b1 + o.b1,   b2 + o.b2,   c + o.c};
  }
  double operator()(const Vec3& x) const {
    const double ax = a00 * x.x() + a01 * x.y() + a02 * x.z(), ay = a01 * x.x() + a11 * x.y() + a12 * x.z(),
                 az = a02 * x.x() + a12 * x.y() + a22 * x.z();
    return std::max(0.0, x.x() * ax + x.y() * ay + x.z() * az + 2 * (b0 * x.x() + b1 * x.y() + b2 * x.z()) + c);
  }
  // The minimiser, pulled towards @p m in the directions the quadric hardly constrains (a flat or
  // straight region): minimises Q(x) + ε|x − m|² with ε a thousandth of A's mean eigenvalue, so
  // the point never runs off along the plane or the crease (after Lindstrom 2000).
  Vec3 minimiser(const Vec3& m) const {
    const double eps = 1e-3 * (a00 + a11 + a22) / 3 + 1e-300;
    // Cholesky of A + εI (symmetric positive definite), then solve for the step from m.
    const double l00 = std::sqrt(a00 + eps);
    const double l10 = a01 / l00, l20 = a02 / l00;
    const double d11 = a11 + eps - l10 * l10;
    if (!(d11 > 0)) return m;
    const double l11 = std::sqrt(d11), l21 = (a12 - l20 * l10) / l11;
    const double d22 = a22 + eps - l20 * l20 - l21 * l21;
    if (!(d22 > 0)) return m;
    const double l22 = std::sqrt(d22);
    // r = −b − A·m: the gradient direction at m.
    const double r0 = -b0 - (a00 * m.x() + a01 * m.y() + a02 * m.z());
    const double r1 = -b1 - (a01 * m.x() + a11 * m.y() + a12 * m.z());
    const double r2 = -b2 - (a02 * m.x() + a12 * m.y() + a22 * m.z());
    const double y0 = r0 / l00, y1 = (r1 - l10 * y0) / l11, y2 = (r2 - l20 * y0 - l21 * y1) / l22;
    const double x2 = y2 / l22, x1 = (y1 - l21 * x2) / l11, x0 = (y0 - l10 * x1 - l20 * x2) / l00;
    return m + Vec3(x0, x1, x2);
  }
};

// Sine of the smallest angle of triangle (a, b, c): the angle opposite the shortest edge, whose
// sine is twice the area over the product of the two longer edges (no trigonometry).
double smallest_angle_sine(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double l0 = (b - c).squaredNorm(), l1 = (c - a).squaredNorm(), l2 = (a - b).squaredNorm();
  const double twice_area = (b - a).cross(c - a).norm();
  const double shortest = std::min({l0, l1, l2});
  const double longer = l0 * l1 * l2 / std::max(shortest, 1e-300);  // product of the two longer
  return longer > 0 ? twice_area / std::sqrt(longer) : 0;
}

// The smallest dot product of @p normals with the best direction found by a few steps from their
// mean towards the worst-seen normal: a lower bound of the max-min cone axis's value, so a refusal
// on it is conservative. -1 when the normals cancel.
double visibility(const std::vector<Vec3>& normals) {
  Vec3 d = Vec3::Zero();
  for (const Vec3& n : normals) d += n;
  if (!(d.norm() > 0)) return -1;
  d.normalize();
  double best = -2;
  for (int it = 0; it < 8; ++it) {
    double worst = 2;
    Vec3 wn = Vec3::Zero();
    for (const Vec3& n : normals)
      if (const double v = d.dot(n); v < worst) worst = v, wn = n;
    best = std::max(best, worst);
    if (worst > 0.5) break;
    d = (d + 0.5 * wn).normalized();
  }
  return best;
}

// visibility(), made exact where it is below 0.5 (improve_max_min()). Whether a star is folded is decided on this: the
// quick estimate took barely seen stars of a resolved union for folded ones, and the "unfolding" collapses then folded
// good stars (bones.off: a star seen at 0.03 merged into one seen at -0.09). The acceptance of ordinary collapses stays
// on the quick, conservative estimate (more collapses near barely seen stars cost fidelity: ChineseDragon-10kv.off
// needed one more round).
double exact_visibility_of(const std::vector<Vec3>& normals) {
  double best = visibility(normals);
  if (best <= 0.5) detail::improve_max_min(normals, best, nullptr);
  return best;
}

// One vertex per fan: a vertex whose faces form several edge-connected fans (a pinch) is split,
// since the link condition is defined on manifold vertices. Faces keep their orientation.
TriangleMesh split_pinched_vertices(const TriangleMesh& mesh) {
  const size_t nv = mesh.vertices.size(), nf = mesh.faces.size();
  std::vector<int32_t> offset(nv + 1, 0);
  for (const Tri& t : mesh.faces)
    for (int32_t v : t) ++offset[v + 1];
  for (size_t v = 0; v < nv; ++v) offset[v + 1] += offset[v];
  // Per vertex: (neighbour, face) for both edges of each incident face; faces that list the same
  // neighbour share the edge (v, neighbour) and belong to one fan.
  std::vector<std::pair<int32_t, int32_t>> spokes(2 * 3 * nf);
  std::vector<int32_t> fill(offset.begin(), offset.end() - 1);
  for (size_t f = 0; f < nf; ++f)
    for (int a = 0; a < 3; ++a) {
      const int32_t v = mesh.faces[f][a];
      spokes[2 * fill[v]] = {mesh.faces[f][(a + 1) % 3], static_cast<int32_t>(f)};
      spokes[2 * fill[v] + 1] = {mesh.faces[f][(a + 2) % 3], static_cast<int32_t>(f)};
      ++fill[v];
    }
  TriangleMesh out = mesh;
  std::vector<int32_t> parent, faces;
  std::vector<std::pair<int32_t, int32_t>> root_copy;
  for (size_t v = 0; v < nv; ++v) {
    auto* b = spokes.data() + 2 * offset[v];
    auto* e = spokes.data() + 2 * offset[v + 1];
    if (e - b < 4) continue;  // one face
    std::sort(b, e);
    faces.clear();
    for (auto* s = b; s != e; ++s) faces.push_back(s->second);
    std::sort(faces.begin(), faces.end());
    faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
    auto slot = [&](int32_t f) { return int32_t(std::lower_bound(faces.begin(), faces.end(), f) - faces.begin()); };
    parent.resize(faces.size());
    for (size_t i = 0; i < faces.size(); ++i) parent[i] = static_cast<int32_t>(i);
    auto find = [&](int32_t x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    for (auto* s = b; s + 1 != e; ++s)
      if (s[0].first == s[1].first) parent[find(slot(s[0].second))] = find(slot(s[1].second));
    // The fan of the first face keeps v; every other fan gets a copy.
    const int32_t keep = find(0);
    root_copy.clear();
    for (size_t i = 0; i < faces.size(); ++i) {
      const int32_t r = find(static_cast<int32_t>(i));
      if (r == keep) continue;
      auto it = std::find_if(root_copy.begin(), root_copy.end(), [&](const auto& rc) { return rc.first == r; });
      if (it == root_copy.end()) {
        root_copy.emplace_back(r, static_cast<int32_t>(out.vertices.size()));
        out.vertices.push_back(mesh.vertices[v]);
        it = root_copy.end() - 1;
      }
      for (int32_t& x : out.faces[faces[i]])
        if (x == static_cast<int32_t>(v)) x = it->second;
    }
  }
  return out;
}

// The mesh being decimated. Each vertex has a singly linked list of its face corners (corner
// 3f+k is vertex k of face f); a collapse of b into a relabels b's corners and splices b's list
// into a's; dead faces' corners stay in the lists and are skipped (and dropped) when walked.
class Simplifier {
 public:
  Simplifier(const TriangleMesh& mesh, const DecimateOptions& o) : o_(o) {
    pos_ = mesh.vertices;
    faces_ = mesh.faces;
    const size_t nv = pos_.size(), nf = faces_.size();
    head_.assign(nv, -1);
    next_.assign(3 * nf, -1);
    for (size_t f = nf; f-- > 0;)
      for (int k = 3; k-- > 0;) {
        const int32_t c = static_cast<int32_t>(3 * f + k), v = faces_[f][k];
        next_[c] = head_[v];
        head_[v] = c;
      }
    alive_face_.assign(nf, 1);
    alive_.assign(nv, 1);
    version_.assign(nv, 0);
    retry_.assign(nv, 0);
    vis_.assign(nv, M_PI);  // unknown: recounted when first needed
    max_angle_ = std::acos(std::clamp(o.min_visibility, -1.0, 1.0));
    faces_left_ = static_cast<int64_t>(nf);
    cos_turn_ = std::cos(o.max_normal_turn_deg * M_PI / 180);
    sin_min_angle_ = std::sin(o.min_angle_deg * M_PI / 180);
    init_quadrics();
    folded_.assign(nv, 0);
    for (int32_t v = 0; v < static_cast<int32_t>(nv); ++v) folded_[v] = exact_visibility(v) <= kFold;
  }

  void run(int64_t target) {
    for (int32_t v = 0; v < static_cast<int32_t>(pos_.size()); ++v) push_edges(v, -1, true);
    while (faces_left_ > target && !heap_.empty()) {
      const Candidate e = heap_.top();
      heap_.pop();
      if (!alive_[e.a] || !alive_[e.b] || version_[e.a] != e.va || version_[e.b] != e.vb) continue;
      if (!collapse(e.a, e.b, e.cost < 0)) retry_[e.a] = retry_[e.b] = 1;
    }
  }

  // Removes vertices whose faces no direction sees (a fold of the input, or one the target left):
  // such a vertex has no valid slab direction at any thickness. Each is merged into a neighbour,
  // beyond the target, by the collapse that most improves its star and keeps the others seen.
  void clean_folds() {
    for (int pass = 0; pass < 4; ++pass) {
      bool any = false;
      for (int32_t v = 0; v < static_cast<int32_t>(pos_.size()); ++v) {
        if (!alive_[v] || exact_visibility(v) > kFold) continue;
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

  // Merges the crumple around folded vertex v into v: the vertices within distance r of v that
  // edges connect to it through such vertices (r = 1/4, 1/2, 1 of v's mean edge length), by
  // collapses that check only the link condition. Kept when the stars around end up with fewer
  // folded ones and none newly folded; undone otherwise. Why: at a crumpled tip (diplodocus.off's
  // tail) every single collapse or removal leaves the merged star as folded as before, while the
  // crumple as a whole is a few tiny faces whose removal leaves a cone seen from its axis.
  bool collapse_cluster(int32_t v) {
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
      for (size_t i = 0; i < region.size(); ++i) before += was[i] = exact_visibility(region[i]) <= kFold;
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
      // with the fewest folded stars around, then the best seen worst star, is kept.
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
          const double seen = exact_visibility(w);
          const bool f = seen <= kFold;
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
        for (int32_t w : near) folded_[w] = exact_visibility(w) <= kFold;
        return true;
      }
      restore(saved);
    }
    return false;
  }

  // What the merges of collapse_cluster() may change, to undo them: they walk and change only the
  // stars of the cluster's and the region's vertices (the heap is not used after run()).
  struct Journal {
    std::vector<int32_t> vertices, faces;
    std::vector<Vec3> pos;
    std::vector<Quadric> quadric;
    std::vector<int32_t> head, next;
    std::vector<uint32_t> version;
    std::vector<double> vis;
    std::vector<uint8_t> alive, folded, retry, alive_face;
    std::vector<Tri> face;
    int64_t faces_left = 0, collapses = 0;
  };
  Journal journal(const std::vector<int32_t>& region) {
    Journal j;
    j.vertices = region;  // the cluster first: collapse_cluster() reads its places
    for (int32_t v : j.vertices) {
      for_faces(v, [&](int32_t f, int) { j.faces.push_back(f); });
      j.pos.push_back(pos_[v]), j.quadric.push_back(quadric_[v]), j.head.push_back(head_[v]);
      j.version.push_back(version_[v]), j.vis.push_back(vis_[v]), j.alive.push_back(alive_[v]);
      j.folded.push_back(folded_[v]), j.retry.push_back(retry_[v]);
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
  void restore(const Journal& j) {
    for (size_t i = 0; i < j.vertices.size(); ++i) {
      const int32_t v = j.vertices[i];
      pos_[v] = j.pos[i], quadric_[v] = j.quadric[i], head_[v] = j.head[i], version_[v] = j.version[i];
      vis_[v] = j.vis[i], alive_[v] = j.alive[i], folded_[v] = j.folded[i], retry_[v] = j.retry[i];
    }
    for (size_t i = 0; i < j.faces.size(); ++i) {
      const int32_t f = j.faces[i];
      faces_[f] = j.face[i], alive_face_[f] = j.alive_face[i];
      for (int k = 0; k < 3; ++k) next_[3 * f + k] = j.next[3 * i + k];
    }
    faces_left_ = j.faces_left, collapses_ = j.collapses;
  }

  // Removes interior vertex v and fills its ring with the fan from one ring vertex (the one whose
  // fan leaves every ring vertex best seen), when that unfolds v's neighbourhood: a crumple that
  // no single edge collapse resolves (its ring twists, so every merged star is folded too).
  bool remove_vertex(int32_t v) {
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
    for (int32_t r : cycle) before = std::min(before, exact_visibility(r));
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
        worst = std::min(worst, visibility(after_));
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
    for (int32_t r : cycle) vis_[r] = M_PI, ++version_[r];
    return true;
  }

  TriangleMesh result() const {
    TriangleMesh out;
    std::vector<int32_t> id(pos_.size(), -1);
    for (size_t f = 0; f < faces_.size(); ++f) {
      if (!alive_face_[f]) continue;
      Tri t;
      for (int k = 0; k < 3; ++k) {
        int32_t& i = id[faces_[f][k]];
        if (i < 0) i = static_cast<int32_t>(out.vertices.size()), out.vertices.push_back(pos_[faces_[f][k]]);
        t[k] = i;
      }
      out.faces.push_back(t);
    }
    return out;
  }

  int64_t feature_edges() const { return features_; }
  int64_t collapses() const { return collapses_; }

 private:
  struct Candidate {
    float cost;
    int32_t a, b;
    uint32_t va, vb;
    bool operator<(const Candidate& o) const { return cost > o.cost; }  // min-heap
  };

  // Live faces around v (drops dead corners from v's list on the way).
  template <class F>
  void for_faces(int32_t v, F&& f) {
    int32_t* link = &head_[v];
    while (*link >= 0) {
      const int32_t c = *link;
      if (!alive_face_[c / 3]) {
        *link = next_[c];
        continue;
      }
      f(c / 3, c % 3);
      link = &next_[c];
    }
  }

  Vec3 face_normal(int32_t f) const {
    const Tri& t = faces_[f];
    return (pos_[t[1]] - pos_[t[0]]).cross(pos_[t[2]] - pos_[t[0]]);
  }

  void init_quadrics() {
    const size_t nf = faces_.size();
    std::vector<Vec3> unit(nf);
    std::vector<double> area(nf);
    for (size_t f = 0; f < nf; ++f) {
      const Vec3 n = face_normal(static_cast<int32_t>(f));
      const double len = n.norm();
      area[f] = 0.5 * len;
      unit[f] = len > 0 ? Vec3(n / len) : Vec3::Zero();
    }
    quadric_.assign(pos_.size(), Quadric{});
    for (size_t f = 0; f < nf; ++f) {
      if (!(area[f] > 0)) continue;
      const double d = -unit[f].dot(pos_[faces_[f][0]]);
      for (int32_t v : faces_[f]) quadric_[v].add_plane(unit[f], d, area[f]);
    }
    // Feature edges (boundary, creases) add the planes through the edge perpendicular to each of
    // their faces, weighted like a face of the edge's squared length (Garland & Heckbert §6).
    // Each edge is seen from the face that has it as (a→b); its twin face has (b→a).
    const double cos_feature = std::cos(o_.feature_angle_deg * M_PI / 180);
    for (size_t f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k) {
        const int32_t a = faces_[f][k], b = faces_[f][(k + 1) % 3];
        int32_t g = -1;
        for (int32_t c = head_[b]; c >= 0; c = next_[c])
          if (faces_[c / 3][(c % 3 + 1) % 3] == a) g = c / 3;
        if (g >= 0 && (a > b || unit[f].dot(unit[g]) >= cos_feature)) continue;  // interior: seen once
        ++features_;
        const Vec3 edge = pos_[b] - pos_[a];
        const double w = o_.feature_weight * edge.squaredNorm();
        for (int side = 0; side < (g >= 0 ? 2 : 1); ++side) {
          const Vec3 m = edge.cross(side ? unit[g] : unit[f]);
          if (!(m.norm() > 0)) continue;
          const Vec3 u = m.normalized();
          for (int32_t v : {a, b}) quadric_[v].add_plane(u, -u.dot(pos_[a]), w);
        }
      }
  }

  // Pushes the edges of v (to every neighbour except @p skip; with @p once only to neighbours of
  // a larger id, so that a sweep over all vertices pushes each edge once), with their cost.
  void push_edges(int32_t v, int32_t skip, bool once) {
    nbr_.clear();
    for_faces(v, [&](int32_t f, int k) {
      nbr_.push_back(faces_[f][(k + 1) % 3]);
      nbr_.push_back(faces_[f][(k + 2) % 3]);
    });
    std::sort(nbr_.begin(), nbr_.end());
    nbr_.erase(std::unique(nbr_.begin(), nbr_.end()), nbr_.end());
    for (int32_t u : nbr_) {
      if (u == skip || (once && u < v)) continue;
      const Quadric q = quadric_[v] + quadric_[u];
      const Vec3 x = place(q, v, u);
      // Folded stars first: they cannot give valid slabs, and at the end of the order (their
      // quadric error is high) they would survive every decimation.
      const float cost = folded_[v] || folded_[u] ? -1.0f : static_cast<float>(q(x));
      heap_.push({cost, v, u, version_[v], version_[u]});
    }
  }

  // Where the merged vertex of edge (a, b) goes: the end of least quadric error (a half-edge
  // collapse: coarse vertices stay input vertices, on the surface, so a slab's corner rays pass
  // through the input), or the quadric's minimiser (DecimateOptions::on_input false).
  Vec3 place(const Quadric& q, int32_t a, int32_t b) const {
    if (!o_.on_input) return q.minimiser(0.5 * (pos_[a] + pos_[b]));
    return q(pos_[a]) <= q(pos_[b]) ? pos_[a] : pos_[b];
  }

  // Sorted distinct neighbours of v, and whether v lies on a boundary (a neighbour met once).
  bool ring(int32_t v, std::vector<int32_t>& out) {
    out.clear();
    for_faces(v, [&](int32_t f, int k) {
      out.push_back(faces_[f][(k + 1) % 3]);
      out.push_back(faces_[f][(k + 2) % 3]);
    });
    std::sort(out.begin(), out.end());
    bool boundary = false;
    size_t w = 0;
    for (size_t i = 0; i < out.size();) {
      size_t j = i;
      while (j < out.size() && out[j] == out[i]) ++j;
      boundary |= j - i == 1;
      out[w++] = out[i];
      i = j;
    }
    out.resize(w);
    return boundary;
  }

  // Collapses edge (a, b) into a at the quadric's minimiser if the link condition and the
  // geometric checks allow it. Returns whether it did.
  bool collapse(int32_t a, int32_t b, bool unfold = false) {
    // Link condition (Dey et al. 1999): the common neighbours of a and b are exactly the apexes of
    // the faces on edge ab; an interior edge may not join two boundary vertices; and two faces
    // (a,c,d), (b,c,d) would become one pair of duplicates.
    const bool ba = ring(a, ra_), bb = ring(b, rb_);
    shared_.clear();
    int32_t apex[2] = {-1, -1};
    int edge_faces = 0;
    for_faces(a, [&](int32_t f, int k) {
      const Tri& t = faces_[f];
      if (t[(k + 1) % 3] == b) {
        if (edge_faces < 2) apex[edge_faces] = t[(k + 2) % 3];
        ++edge_faces;
      } else if (t[(k + 2) % 3] == b) {
        if (edge_faces < 2) apex[edge_faces] = t[(k + 1) % 3];
        ++edge_faces;
      }
    });
    std::set_intersection(ra_.begin(), ra_.end(), rb_.begin(), rb_.end(), std::back_inserter(shared_));
    if (edge_faces < 1 || edge_faces > 2 || static_cast<int>(shared_.size()) != edge_faces) return false;
    if (edge_faces == 2 && ba && bb) return false;
    if (edge_faces == 2) {
      // (a,c,d) and (b,c,d) both faces: the tetrahedron case.
      const int32_t c = apex[0], d = apex[1];
      bool acd = false, bcd = false;
      for_faces(c, [&](int32_t f, int) {
        const Tri& t = faces_[f];
        const bool has_d = t[0] == d || t[1] == d || t[2] == d;
        acd |= has_d && (t[0] == a || t[1] == a || t[2] == a);
        bcd |= has_d && (t[0] == b || t[1] == b || t[2] == b);
      });
      if (acd && bcd) return false;
    }

    const Quadric q = quadric_[a] + quadric_[b];
    if (forced_) return merge(a, b, pos_[a], q, -2, M_PI), true;
    // Geometry: no face of the star turns by more than max_normal_turn or becomes a new sliver;
    // every vertex whose star changes (the new vertex and the link) stays visible. An unfolding
    // collapse may turn faces as it likes, and tries several places for the new vertex.
    double min_cos = 1;  // cosine of the largest normal turn of a moved face
    auto check = [&](int32_t v, const Vec3& x) {
      bool ok = true;
      for_faces(v, [&](int32_t f, int k) {
        if (!ok) return;
        const Tri& t = faces_[f];
        const bool on_edge = t[0] == (v == a ? b : a) || t[1] == (v == a ? b : a) || t[2] == (v == a ? b : a);
        if (on_edge) return;  // removed by the collapse
        const Vec3& p = pos_[t[(k + 1) % 3]];
        const Vec3& r = pos_[t[(k + 2) % 3]];
        const Vec3 nb = (p - pos_[v]).cross(r - pos_[v]), na = (p - x).cross(r - x);
        const double lb = nb.norm(), la = na.norm();
        if (!(la > 0) || (!unfold && lb > 0 && nb.dot(na) < cos_turn_ * lb * la)) return void(ok = false);
        if (lb > 0) min_cos = std::min(min_cos, nb.dot(na) / (lb * la));
        const double sine = smallest_angle_sine(x, p, r);
        if (!unfold && sine < sin_min_angle_ && sine < smallest_angle_sine(pos_[v], p, r)) return void(ok = false);
        after_.push_back(na / la);
      });
      return ok;
    };
    Vec3 x = place(q, a, b);
    double seen = -2;
    {
      Vec3 tries[4] = {x, pos_[a], pos_[b], 0.5 * (pos_[a] + pos_[b])};
      const int count = unfold ? 4 : 1;
      double best_cos = 1;
      for (int k = 0; k < count; ++k) {
        after_.clear();
        min_cos = 1;
        if (!check(a, tries[k]) || !check(b, tries[k])) continue;
        const double v = visibility(after_);
        if (v > seen) seen = v, x = tries[k], best_cos = min_cos;
      }
      if (seen == -2) return false;
      min_cos = best_cos;
    }
    if (!x.allFinite()) return false;

    // The worse seen of the two stars it replaces: the new star must not be seen worse, unless it
    // is seen well enough anyway; an unfolding collapse must do strictly better.
    const bool good = unfold ? seen > kFold : seen >= o_.min_visibility;
    const double was = good ? -2 : std::min(exact_visibility(a), exact_visibility(b));
    if (!good && (unfold ? !(seen > was + 1e-3) : seen < was)) {
      return false;
    }
    const double max_turn = std::acos(std::clamp(min_cos, -1.0, 1.0));
    for (int32_t w : ra_) {
      if (w == b) continue;
      if (!link_visible(w, a, b, x, max_turn)) return false;
    }
    for (int32_t w : rb_) {
      if (w == a || std::binary_search(ra_.begin(), ra_.end(), w)) continue;
      if (!link_visible(w, a, b, x, max_turn)) return false;
    }

    merge(a, b, x, q, seen, max_turn);
    return true;
  }

  // Collapses b into a at x (the checks passed): kills the faces on edge ab, relabels b's corners,
  // splices b's list into a's. @p seen is the new star's visibility (-2: unknown), @p max_turn the
  // largest turn of a link face [rad].
  void merge(int32_t a, int32_t b, const Vec3& x, const Quadric& q, double seen, double max_turn) {
    for_faces(a, [&](int32_t f, int) {
      const Tri& t = faces_[f];
      if (t[0] == b || t[1] == b || t[2] == b) alive_face_[f] = 0, --faces_left_;
    });
    int32_t* tail = &head_[b];
    while (*tail >= 0) {
      const int32_t c = *tail;
      if (!alive_face_[c / 3]) {
        *tail = next_[c];
        continue;
      }
      faces_[c / 3][c % 3] = a;
      tail = &next_[c];
    }
    *tail = head_[a];
    head_[a] = head_[b];
    head_[b] = -1;
    alive_[b] = 0;
    pos_[a] = x;
    quadric_[a] = q;
    ++version_[a];
    ++collapses_;
    // The link's stars lost faces or turned them by at most max_turn: their cone angle bound grows
    // by max_turn; the new vertex's star was just measured.
    for (int32_t w : ra_) vis_[w] += max_turn;
    for (int32_t w : rb_)
      if (!std::binary_search(ra_.begin(), ra_.end(), w)) vis_[w] += max_turn;
    if (seen == -2) seen = exact_visibility(a);
    vis_[a] = std::acos(std::clamp(seen, -1.0, 1.0));
    folded_[a] = seen <= kFold;
    // Folded link vertices may have unfolded: their edges lose the priority (new version).
    for (const std::vector<int32_t>* r : {&ra_, &rb_})
      for (int32_t w : *r)
        if (w != a && w != b && folded_[w] && exact_visibility(w) > kFold) {
          folded_[w] = 0;
          ++version_[w];
          unfolded_.push_back(w);
        }
    push_edges(a, -1, false);
    for (int32_t w : unfolded_) push_edges(w, a, false);
    unfolded_.clear();
    // Edges refused earlier near here may pass now that the neighbourhood changed.
    ring(a, ra_);
    for (int32_t w : ra_)
      if (retry_[w]) retry_[w] = 0, push_edges(w, a, false);
  }

  // Visibility of v's star as it is (exact_visibility_of()).
  double exact_visibility(int32_t v) {
    before_.clear();
    for_faces(v, [&](int32_t f, int) {
      const Vec3 n = face_normal(f);
      if (n.norm() > 0) before_.push_back(n.normalized());
    });
    return exact_visibility_of(before_);
  }

  // Whether link vertex w's faces stay visible (DecimateOptions::min_visibility) with a and b
  // moved to x, or at least no worse seen than before. vis_[w] bounds the angle at which some
  // direction sees all of w's faces; no face turns by more than @p max_turn, so that direction
  // sees the new star within vis_[w] + max_turn: most stars pass on that bound without a recount.
  bool link_visible(int32_t w, int32_t a, int32_t b, const Vec3& x, double max_turn) {
    if (vis_[w] + max_turn <= max_angle_) return true;
    // Recount: the star as it is (tightens the bound), then as it would be.
    before_.clear();
    after_.clear();
    for_faces(w, [&](int32_t f, int) {
      const Tri& t = faces_[f];
      int touches = 0;
      Vec3 c[3];
      for (int k = 0; k < 3; ++k) {
        const bool moved = t[k] == a || t[k] == b;
        touches += moved;
        c[k] = moved ? x : pos_[t[k]];
      }
      const Vec3 nb = face_normal(f);
      if (nb.norm() > 0) before_.push_back(nb.normalized());
      if (touches == 2) return;  // removed
      const Vec3 na = (c[1] - c[0]).cross(c[2] - c[0]);
      if (na.norm() > 0) after_.push_back(na.normalized());
    });
    const double was = visibility(before_);
    vis_[w] = std::acos(std::clamp(was, -1.0, 1.0));
    const double will = visibility(after_);
    if (will >= o_.min_visibility) return true;
    // "No worse seen" on the quick estimate alone let a barely seen star fold (the estimate is a
    // bound, not a measure): the exact values must not fold it either.
    if (!(will >= was)) return false;
    const double will_exact = exact_visibility_of(after_);
    return will_exact > kFold || will_exact >= exact_visibility_of(before_);
  }

  DecimateOptions o_;
  bool forced_ = false;  // collapse() checks only the link condition (collapse_cluster())
  std::vector<Vec3> pos_;
  std::vector<Tri> faces_;
  std::vector<int32_t> head_, next_;
  std::vector<uint8_t> alive_face_, alive_, retry_;
  std::vector<uint32_t> version_;
  std::vector<Quadric> quadric_;
  std::vector<double> vis_;  // per vertex, an upper bound of the angle at which one direction sees its faces [rad]
  double max_angle_ = 0;     // acos(min_visibility)
  std::priority_queue<Candidate> heap_;
  std::vector<int32_t> nbr_, ra_, rb_, shared_, fold_ring_, unfolded_;
  std::vector<uint8_t> folded_;          // stars no direction sees (visibility <= kFold)
  static constexpr double kFold = 0.02;  // a star seen at no better dot than this is folded
  std::vector<Vec3> before_, after_;
  int64_t faces_left_ = 0, features_ = 0, collapses_ = 0;
  double cos_turn_ = 0, sin_min_angle_ = 0;
};

}  // namespace

TriangleMesh decimate_mesh(const TriangleMesh& input, const DecimateOptions& options, DecimateReport* report) {
  validate_mesh_data(input, "decimate_mesh input");
  if (options.target_faces < 1)
    throw InvalidInput("decimate_mesh: target_faces " + std::to_string(options.target_faces) + " must be at least 1");
  const MeshTopology topo = analyze_topology(input);
  if (topo.non_manifold_edges || topo.inconsistent_edges)
    throw InvalidInput("decimate_mesh input: " + std::to_string(topo.non_manifold_edges) + " non-manifold and " +
                       std::to_string(topo.inconsistent_edges) +
                       " inconsistently oriented edges (repair the mesh first)");
  Simplifier s(split_pinched_vertices(input), options);
  s.run(options.target_faces);
  s.clean_folds();
  TriangleMesh out = s.result();
  if (report) {
    report->faces = static_cast<int64_t>(out.faces.size());
    report->vertices = static_cast<int64_t>(out.vertices.size());
    report->feature_edges = s.feature_edges();
    report->collapses = s.collapses();
  }
  return out;
}

}  // namespace hdm
