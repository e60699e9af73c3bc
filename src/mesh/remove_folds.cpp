// SPDX-License-Identifier: MIT
// Rim flaps, crumples and empty-cone rim vertices of an open sheet removed (see remove_folds.h).
#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/mesh/remove_folds.h>
#include <hdm/mesh/fix_empty_dual_cones.h>

#include "max_min_direction.h"
#include "disjoint_sets.h"

#include <algorithm>
#include <unordered_map>
#include <vector>

namespace hdm {
namespace {

constexpr double kFlapTurn = -0.5;       // cos 120°: faces joined across an edge turning less
constexpr size_t kMaxFlapFaces = 6;      // largest rim flap removed
constexpr double kMaxFlapExtent = 0.05;  // ... and its largest extent, as a fraction of the diagonal
constexpr int kRimRounds = 8;
constexpr double kRimSeen = 0.1;  // a rim vertex of no better cone margin than this (84°) counts as empty
constexpr double kEmptyCone =
    0.02;  // a star of no better cone margin than this has an empty dual cone (as in the decimation)

// The mesh's faces with removal: which are left, and which faces meet at each edge and vertex.
class Sheet {
 public:
  explicit Sheet(TriangleMesh& mesh) : m_(mesh), alive_(mesh.faces.size(), 1), vertex_faces_(mesh.vertices.size()) {
    for (size_t f = 0; f < m_.faces.size(); ++f) {
      const Tri& t = m_.faces[f];
      for (int k = 0; k < 3; ++k) {
        edge_faces_[key(t[k], t[(k + 1) % 3])].push_back(int32_t(f));
        vertex_faces_[t[k]].push_back(int32_t(f));
      }
    }
  }
  static uint64_t key(int32_t a, int32_t b) {
    if (a > b) std::swap(a, b);
    return (uint64_t(uint32_t(a)) << 32) | uint32_t(b);
  }
  bool alive(int32_t f) const { return alive_[f]; }
  // The live faces on edge ab.
  int live_on_edge(int32_t a, int32_t b, int32_t* other_than = nullptr, int32_t f = -1) const {
    int n = 0;
    for (int32_t g : edge_faces_.at(key(a, b)))
      if (alive_[g]) {
        ++n;
        if (other_than && g != f) *other_than = g;
      }
    return n;
  }
  const std::vector<int32_t>& faces_at(int32_t v) const { return vertex_faces_[v]; }
  bool on_boundary(int32_t v) const {
    for (int32_t f : vertex_faces_[v]) {
      if (!alive_[f]) continue;
      const Tri& t = m_.faces[f];
      for (int k = 0; k < 3; ++k)
        if ((t[k] == v || t[(k + 1) % 3] == v) && live_on_edge(t[k], t[(k + 1) % 3]) == 1) return true;
    }
    return false;
  }
  // Removes face f unless a corner of it would end up in more fans of faces than it has now
  // (at least one): removing faces never makes a pinch. False (kept) otherwise.
  bool remove(int32_t f) { return remove_all({f}); }
  void restore(int32_t f) { alive_[f] = 1; }
  // Removes all of @p faces under the same rule; false (none removed) otherwise.
  bool remove_all(const std::vector<int32_t>& faces) {
    corners_.clear();
    for (int32_t f : faces) corners_.insert(corners_.end(), m_.faces[f].begin(), m_.faces[f].end());
    std::sort(corners_.begin(), corners_.end());
    corners_.erase(std::unique(corners_.begin(), corners_.end()), corners_.end());
    fans_before_.clear();
    for (int32_t v : corners_) fans_before_.push_back(std::max(1, fans(v)));
    for (int32_t f : faces) alive_[f] = 0;
    for (size_t i = 0; i < corners_.size(); ++i)
      if (fans(corners_[i]) > fans_before_[i]) {
        for (int32_t f : faces) alive_[f] = 1;
        return false;
      }
    return true;
  }
  // Faces left, in their order; unused vertices dropped.
  void compact() {
    std::vector<int32_t> index(m_.vertices.size(), -1);
    std::vector<Tri> faces;
    for (size_t f = 0; f < m_.faces.size(); ++f)
      if (alive_[f]) {
        faces.push_back(m_.faces[f]);
        for (int32_t v : m_.faces[f]) index[v] = 0;
      }
    if (faces.size() == m_.faces.size()) return;
    std::vector<Vec3> vertices;
    for (size_t v = 0; v < index.size(); ++v)
      if (index[v] == 0) index[v] = int32_t(vertices.size()), vertices.push_back(m_.vertices[v]);
    for (Tri& t : faces)
      for (int32_t& v : t) v = index[v];
    m_.vertices.swap(vertices);
    m_.faces.swap(faces);
  }

 private:
  // Fans of live faces at v: groups of its faces joined across their edges at v.
  int fans(int32_t v) {
    star_.clear();
    for (int32_t f : vertex_faces_[v])
      if (alive_[f]) star_.push_back(f);
    sets_.reset(star_.size());
    int groups = int(star_.size());
    for (size_t i = 0; i < star_.size(); ++i)
      for (size_t j = i + 1; j < star_.size(); ++j) {
        int shared = 0;
        for (int32_t a : m_.faces[star_[i]])
          for (int32_t b : m_.faces[star_[j]]) shared += a == b;
        if (shared >= 2 && sets_.unite(int32_t(i), int32_t(j))) --groups;
      }
    return groups;
  }

  TriangleMesh& m_;
  std::vector<char> alive_;
  std::vector<std::vector<int32_t>> vertex_faces_;
  std::unordered_map<uint64_t, std::vector<int32_t>> edge_faces_;
  std::vector<int32_t> star_, corners_;
  mesh::detail::DisjointSets<> sets_;
  std::vector<int> fans_before_;
};

Vec3 unit_normal(const TriangleMesh& m, const Tri& t) {
  const Vec3 n = (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]);
  return n.norm() > 0 ? Vec3(n.normalized()) : Vec3(Vec3::Zero());
}

// Step 1: rim flaps (see the header). Returns the faces removed.
int64_t remove_rim_flaps(TriangleMesh& mesh) {
  const auto nf = int32_t(mesh.faces.size());
  Sheet sheet(mesh);
  std::vector<Vec3> normal(static_cast<size_t>(nf), Vec3::Zero());
  for (int32_t f = 0; f < nf; ++f) normal[f] = unit_normal(mesh, mesh.faces[f]);
  mesh::detail::DisjointSets<> group(static_cast<size_t>(nf)), part(static_cast<size_t>(nf));
  std::vector<char> on_rim(static_cast<size_t>(nf), 0);
  for (int32_t f = 0; f < nf; ++f) {
    const Tri& t = mesh.faces[f];
    for (int k = 0; k < 3; ++k) {
      int32_t g = -1;
      const int n = sheet.live_on_edge(t[k], t[(k + 1) % 3], &g, f);
      if (n == 1) on_rim[f] = 1;
      if (g < 0 || g < f) continue;
      part.unite(f, g);
      if (n == 2 && normal[f].dot(normal[g]) > kFlapTurn) group.unite(f, g);
    }
  }
  std::unordered_map<int32_t, std::vector<int32_t>> members;
  std::unordered_map<int32_t, size_t> part_size;
  for (int32_t f = 0; f < nf; ++f) members[group.find(f)].push_back(f), ++part_size[part.find(f)];
  const double limit = kMaxFlapExtent * bounds(mesh).diagonal();
  int64_t removed = 0;
  for (auto& [id, faces] : members) {
    if (faces.size() > kMaxFlapFaces || faces.size() == part_size[part.find(faces[0])]) continue;
    Aabb box;
    bool rim = false;
    for (int32_t f : faces) {
      rim = rim || on_rim[f];
      for (int32_t v : mesh.faces[f])
        box.min = box.min.cwiseMin(mesh.vertices[v]), box.max = box.max.cwiseMax(mesh.vertices[v]);
    }
    if (!rim || box.diagonal() > limit) continue;
    if (sheet.remove_all(faces)) {
      removed += static_cast<int64_t>(faces.size());
      continue;
    }
    // Else face by face: removing one may free the next without leaving a pinch.
    for (bool progress = true; progress;) {
      progress = false;
      for (int32_t& f : faces)
        if (f >= 0 && sheet.remove(f)) ++removed, f = -1, progress = true;
    }
  }
  sheet.compact();
  return removed;
}

// Step 3: empty-cone rim vertices (see the header). Returns the faces removed.
int64_t trim_empty_cone_rim(TriangleMesh& mesh) {
  int64_t removed = 0;
  std::vector<Vec3> normals;
  std::vector<int32_t> star;
  std::vector<size_t> order;
  for (int round = 0; round < kRimRounds; ++round) {
    Sheet sheet(mesh);
    // The live star of v: its faces' unit normals (degenerate faces left out) and the best
    // direction's smallest dot product with them.
    Vec3 direction;
    auto seen = [&](int32_t v) {
      normals.clear(), star.clear();
      Vec3 mean = Vec3::Zero();
      for (int32_t f : sheet.faces_at(v)) {
        const Vec3 n = sheet.alive(f) ? unit_normal(mesh, mesh.faces[f]) : Vec3(Vec3::Zero());
        if (n.squaredNorm() == 0) continue;
        normals.push_back(n), star.push_back(f), mean += n;
      }
      if (normals.size() < 2) return 1.0;
      direction = mean.norm() > 0 ? Vec3(mean.normalized()) : normals[0];
      double best = 2;
      for (const Vec3& n : normals) best = std::min(best, direction.dot(n));
      if (best > kRimSeen) return best;  // seen well enough from the mean normal: no search needed
      mesh::detail::improve_max_min(normals, best, &direction);
      return best;
    };
    int64_t now = 0;
    for (int32_t v = 0; v < int32_t(mesh.vertices.size()); ++v) {
      const double margin = seen(v);
      if (margin > (sheet.on_boundary(v) ? kRimSeen : kEmptyCone)) continue;
      const bool deep = margin <= kEmptyCone;
      // The most turned faces first; one goes if that leaves fewer empty-cone vertices among its corners
      // and folds none that was not (a cut in a pleat would only move the fold).
      const std::vector<int32_t> faces = star;
      std::vector<double> dots(normals.size());
      for (size_t i = 0; i < normals.size(); ++i) dots[i] = direction.dot(normals[i]);
      order.resize(faces.size());
      for (size_t i = 0; i < order.size(); ++i) order[i] = i;
      std::sort(order.begin(), order.end(), [&](size_t i, size_t j) { return dots[i] < dots[j]; });
      for (size_t i : order) {
        const Tri corners = mesh.faces[faces[i]];
        bool was[3];
        int before = 0, after = 0;
        for (int k = 0; k < 3; ++k) before += was[k] = seen(corners[k]) <= kRimSeen;
        if (!sheet.remove(faces[i])) continue;
        bool newly = false;
        for (int k = 0; k < 3; ++k) {
          const bool f = seen(corners[k]) <= kRimSeen;
          after += f, newly = newly || (f && !was[k]);
        }
        if (deep || (after < before && !newly)) {
          ++now;
          break;
        }
        sheet.restore(faces[i]);
      }
    }
    if (now == 0) break;
    removed += now;
    sheet.compact();
  }
  return removed;
}

// Largest distance from a vertex or face centroid of either mesh to the other mesh's surface.
double sampled_distance(const TriangleMesh& a, const TriangleMesh& b) {
  double worst = 0;
  for (int pass = 0; pass < 2; ++pass) {
    const TriangleMesh& from = pass ? b : a;
    const ExactMeshQuery to(pass ? a : b);
    for (const Tri& t : from.faces) {
      const Vec3 centroid = (from.vertices[t[0]] + from.vertices[t[1]] + from.vertices[t[2]]) / 3;
      worst = std::max(worst, to.closest_point(centroid).distance);
      for (int32_t v : t) worst = std::max(worst, to.closest_point(from.vertices[v]).distance);
    }
  }
  return worst;
}

}  // namespace

FoldReport remove_folds(TriangleMesh& mesh) {
  validate_mesh_data(mesh, "remove_folds input");
  FoldReport report;
  const TriangleMesh input = mesh;
  report.flap_faces = remove_rim_flaps(mesh);
  auto fix_cones = [&] {
    const std::vector<Vec3> before = mesh.vertices;
    const DualConeReport r = fix_empty_dual_cones(mesh, kEmptyCone, 4);
    for (size_t v = 0; v < before.size(); ++v) {
      const double d = (mesh.vertices[v] - before[v]).norm();
      report.moved += d > 0;
      report.max_move = std::max(report.max_move, d);
    }
    return r;
  };
  report.empty_cones_before = fix_cones().empty_cones_before;
  report.rim_faces = trim_empty_cone_rim(mesh);
  report.empty_cones_after = fix_cones().empty_cones_after;  // the trim may have freed folds for the discs
  if (report.flap_faces + report.rim_faces + report.moved > 0) report.max_deviation = sampled_distance(input, mesh);
  return report;
}

}  // namespace hdm
