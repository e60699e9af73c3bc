// SPDX-License-Identifier: MIT
// Empty-cone vertices of a coarse mesh replaced by harmonic discs (see fix_empty_dual_cones.h).
#include <hdm/core/error.h>
#include <hdm/mesh/fix_empty_dual_cones.h>

#include "max_min_direction.h"

#include <algorithm>
#include <string>
#include <vector>

namespace hdm {
namespace {

// The mesh's adjacency: vertex -> faces (CSR), vertex -> sorted distinct neighbours (CSR), and the
// vertices on the mesh's boundary (a neighbour met once: an edge with one face).
struct Stars {
  std::vector<int32_t> offset, faces;
  std::vector<int32_t> nbr_offset, nbr;
  std::vector<uint8_t> boundary;
};

Stars stars_of(const TriangleMesh& mesh) {
  const auto nv = static_cast<int32_t>(mesh.vertices.size());
  Stars s;
  s.offset.assign(nv + 1, 0);
  for (const Tri& t : mesh.faces)
    for (int32_t v : t) ++s.offset[v + 1];
  for (int32_t v = 0; v < nv; ++v) s.offset[v + 1] += s.offset[v];
  s.faces.resize(s.offset[nv]);
  std::vector<int32_t> fill(s.offset.begin(), s.offset.end() - 1);
  for (size_t f = 0; f < mesh.faces.size(); ++f)
    for (int32_t v : mesh.faces[f]) s.faces[fill[v]++] = static_cast<int32_t>(f);
  s.boundary.assign(nv, 0);
  s.nbr_offset.assign(nv + 1, 0);
  std::vector<int32_t> ring;
  for (int32_t v = 0; v < nv; ++v) {
    ring.clear();
    for (int32_t k = s.offset[v]; k < s.offset[v + 1]; ++k) {
      const Tri& t = mesh.faces[s.faces[k]];
      for (int a = 0; a < 3; ++a)
        if (t[a] == v) ring.push_back(t[(a + 1) % 3]), ring.push_back(t[(a + 2) % 3]);
    }
    std::sort(ring.begin(), ring.end());
    for (size_t i = 0; i < ring.size();) {
      size_t j = i;
      while (j < ring.size() && ring[j] == ring[i]) ++j;
      s.boundary[v] |= j - i == 1;
      s.nbr.push_back(ring[i]);
      i = j;
    }
    s.nbr_offset[v + 1] = static_cast<int32_t>(s.nbr.size());
  }
  return s;
}

// Gives empty-cone vertices a direction that sees their faces by Laplacian smoothing of a disc
// around each.
class ConeSmoother {
 public:
  ConeSmoother(TriangleMesh& mesh, double min_cone_margin)
      : mesh_(mesh),
        p_(mesh.vertices),
        s_(stars_of(mesh)),
        min_margin_(min_cone_margin),
        layer_(mesh.vertices.size(), -1) {}

  // Whether the best direction's smallest dot product with v's face normals (degenerate faces
  // left out) is at most the margin.
  bool empty(int32_t v) {
    normals_.clear();
    Vec3 mean = Vec3::Zero();
    for (int32_t k = s_.offset[v]; k < s_.offset[v + 1]; ++k) {
      const Tri& t = mesh_.faces[s_.faces[k]];
      const Vec3 n = (p_[t[1]] - p_[t[0]]).cross(p_[t[2]] - p_[t[0]]);
      if (n.norm() > 0) normals_.push_back(n.normalized()), mean += normals_.back();
    }
    if (normals_.empty()) return false;
    double best = -2;
    if (mean.norm() > 0) {
      best = 2;
      const Vec3 d = mean.normalized();
      for (const Vec3& n : normals_) best = std::min(best, d.dot(n));
      if (best > min_margin_) return false;  // seen well enough: no search needed
    }
    // Only the decision is wanted: where the normals' hull holds the origin no direction sees them
    // by more than kHullHoldsOrigin, and how far below that the best one is needs no search.
    Vec3 x = Vec3::Zero();
    const mesh::detail::HullOrigin where = mesh::detail::hull_origin(normals_, x);
    if (min_margin_ >= 0 && where == mesh::detail::HullOrigin::Holds) return true;
    mesh::detail::improve_max_min_figure(normals_, best, where, x);
    return best <= min_margin_;
  }

  // Tries discs of 1 .. max_rings rings around empty-cone vertex v; returns the vertices moved (0 when
  // no disc opened the cones, positions restored).
  int64_t open_cone(int32_t v, int max_rings) {
    for (int k = 1; k <= max_rings; ++k) {
      gather_disc(v, k);
      const int64_t moved = smooth_disc();
      for (int32_t u : disc_) layer_[u] = -1;
      if (moved) return moved;
      for (size_t i = 0; i < free_.size(); ++i) p_[free_[i]] = saved_[i];
    }
    return 0;
  }

 private:
  // The disc: vertices within k edges of v; the free ones (within k - 1, off the boundary) move,
  // the outer ring's stars share the disc's faces and are judged with them.
  void gather_disc(int32_t v, int k) {
    disc_.assign(1, v);
    layer_[v] = 0;
    for (size_t i = 0; i < disc_.size(); ++i) {
      const int32_t u = disc_[i];
      if (layer_[u] + 1 > k) continue;
      for (int32_t j = s_.nbr_offset[u]; j < s_.nbr_offset[u + 1]; ++j)
        if (layer_[s_.nbr[j]] < 0) layer_[s_.nbr[j]] = layer_[u] + 1, disc_.push_back(s_.nbr[j]);
    }
    free_.clear();
    for (int32_t u : disc_)
      if (layer_[u] < k && !s_.boundary[u]) free_.push_back(u);
    saved_.resize(free_.size());
    for (size_t i = 0; i < free_.size(); ++i) saved_[i] = p_[free_[i]];
  }

  // Smooth in growing numbers of sweeps and keep the first state that opens the cones: a crumple is
  // small next to the disc, so it goes in a few sweeps while the disc's shape stays (a disc
  // smoothed to convergence around a thin part, such as a tail's tip, flattens the part).
  // Returns the free vertices moved when the disc has fewer empty-cone vertices and none newly empty.
  int64_t smooth_disc() {
    was_empty_.resize(disc_.size());
    int64_t before = 0;
    for (size_t i = 0; i < disc_.size(); ++i) before += was_empty_[i] = empty(disc_[i]);
    for (int sweep = 1; sweep <= 1024; ++sweep) {
      for (int32_t u : free_) {
        Vec3 sum = Vec3::Zero();
        for (int32_t j = s_.nbr_offset[u]; j < s_.nbr_offset[u + 1]; ++j) sum += p_[s_.nbr[j]];
        p_[u] += 0.25 * (sum / double(s_.nbr_offset[u + 1] - s_.nbr_offset[u]) - p_[u]);
      }
      if (sweep > 16 && (sweep & (sweep - 1))) continue;  // judged after 1, 2, ... 16, 32, 64, ... sweeps
      // Judged star by star, v first: the state fails once as many are empty as before or one is
      // newly empty, and the stars after that need not be searched.
      int64_t after = 0;
      bool newly = false;
      for (size_t i = 0; i < disc_.size() && after < before && !newly; ++i) {
        const bool f = empty(disc_[i]);
        after += f;
        newly |= f && !was_empty_[i];
      }
      if (after < before && !newly) return static_cast<int64_t>(free_.size());
    }
    return 0;
  }

  TriangleMesh& mesh_;
  std::vector<Vec3>& p_;
  const Stars s_;
  const double min_margin_;
  std::vector<int32_t> layer_;  // ring index of a vertex in the current disc, -1 outside
  std::vector<int32_t> disc_, free_;
  std::vector<uint8_t> was_empty_;
  std::vector<Vec3> saved_, normals_;
};

}  // namespace

DualConeReport fix_empty_dual_cones(TriangleMesh& mesh, double min_cone_margin, int max_rings) {
  if (!(min_cone_margin >= -1 && min_cone_margin < 1))
    throw InvalidInput("fix_empty_dual_cones: min_cone_margin " + std::to_string(min_cone_margin) +
                       " must be in [-1, 1)");
  if (max_rings < 1)
    throw InvalidInput("fix_empty_dual_cones: max_rings " + std::to_string(max_rings) + " must be >= 1");
  validate_mesh_data(mesh, "fix_empty_dual_cones input");
  const auto nv = static_cast<int32_t>(mesh.vertices.size());
  ConeSmoother u(mesh, min_cone_margin);
  DualConeReport report;
  for (int32_t v = 0; v < nv; ++v) report.empty_cones_before += u.empty(v);
  for (int32_t v = 0; v < nv; ++v)
    if (u.empty(v)) report.moved += u.open_cone(v, max_rings);
  for (int32_t v = 0; v < nv; ++v) report.empty_cones_after += u.empty(v);
  return report;
}

}  // namespace hdm
