// SPDX-License-Identifier: MIT
// The bake's coarse surface: checked decimation, then every vertex star made visible.
#include "coarse_surface.h"

#include <hdm/mesh/decimate_mesh.h>
#include <hdm/mesh/flip_slivers.h>
#include <hdm/mesh/fix_empty_dual_cones.h>

#include "../mesh/max_min_direction.h"

#include <algorithm>

namespace hdm::slab::detail {
namespace {

// Decimate to about `target` triangles (decimate_mesh(): edge collapses under the link condition,
// so the coarse mesh keeps the input's topology and orientation), then flip the caps the
// decimation kept (an input vertex on another face's edge): no slab over a cap is valid. Only
// near-degenerate caps (smallest angle below half a degree): flipping the milder caps along the
// crossing curves of a resolved union made slabs overlap there (bones.off).
CoarseMesh decimate(const TriangleMesh& mesh, int target, const std::vector<double>& max_edge, double max_cost,
                    double* last_cost) {
  DecimateOptions o;
  o.target_faces = target;
  o.max_edge = max_edge;
  o.max_cost = max_cost;
  DecimateReport r;
  TriangleMesh m = decimate_mesh(mesh, o, &r);
  if (last_cost) *last_cost = r.last_cost;
  flip_slivers(m, 0.5);
  return CoarseMesh{std::move(m.vertices), std::move(m.faces)};
}

// The sorted one-ring of v in @p c, by the vertex -> faces CSR of @p topo.
void ring_of(const CoarseMesh& c, const VertexFrame& topo, int32_t v, std::vector<int32_t>& out) {
  out.clear();
  for (int32_t k = topo.offsets[v]; k < topo.offsets[v + 1]; ++k)
    for (int32_t u : c.faces[topo.faces[k]])
      if (u != v) out.push_back(u);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

// The tries of untangle() that failed, and the moves since. A try at v reads the positions within
// three rings of it (the stars of the ring of its ring moved with it, their centroids): when none
// moved since v's last failed try, the try would fail the same way, so it is skipped.
class FailedTries {
 public:
  explicit FailedTries(size_t nv) : moved_at_(nv, -1), failed_at_(nv, -1), visit_(nv, -1) {}
  void forget() { std::fill(failed_at_.begin(), failed_at_.end(), -1); }  // the tries change
  void moved(const std::vector<int32_t>& movers) {
    ++epoch_;
    for (int32_t m : movers) moved_at_[m] = epoch_;
  }
  void failed(int32_t v) { failed_at_[v] = epoch_; }
  int64_t epoch() const { return epoch_; }
  // Whether a vertex of v's star (its faces' corners) moved after @p when.
  bool star_moved_since(const CoarseMesh& c, const VertexFrame& topo, int32_t v, int64_t when) const {
    for (int32_t k = topo.offsets[v]; k < topo.offsets[v + 1]; ++k)
      for (int32_t u : c.faces[topo.faces[k]])
        if (moved_at_[u] > when) return true;
    return false;
  }
  // Whether v's last try failed and nothing within three rings of it moved since.
  bool unchanged(const CoarseMesh& c, const VertexFrame& topo, int32_t v) {
    const int64_t when = failed_at_[v];
    if (when < 0) return false;
    near_.assign(1, v);
    visit_[v] = ++walk_;
    for (int r = 0, first = 0; r <= 3; ++r) {
      const int last = static_cast<int>(near_.size());
      for (int i = first; i < last; ++i) {
        if (moved_at_[near_[i]] > when) return false;
        if (r == 3) continue;
        ring_of(c, topo, near_[i], ring_);
        for (int32_t u : ring_)
          if (visit_[u] != walk_) visit_[u] = walk_, near_.push_back(u);
      }
      first = last;
    }
    return true;
  }

 private:
  int64_t epoch_ = 0, walk_ = 0;  // moves made; walks of unchanged(), which stamp visit_
  std::vector<int64_t> moved_at_, failed_at_, visit_;
  std::vector<int32_t> near_, ring_;
};

// Each star's figure as untangle() last found it with every vertex in place, and when: it holds
// while no vertex of the star moves (the figure depends on their positions alone), so the sweeps
// and the worst-star tests do not search a star again until a kept move changes it.
class KeptFigures {
 public:
  explicit KeptFigures(size_t nv) : figure_(nv, 0), at_(nv, -1) {}
  template <class Figure>
  double get(const CoarseMesh& c, const VertexFrame& topo, const FailedTries& tries, int32_t v, Figure&& figure) {
    if (at_[v] < 0 || tries.star_moved_since(c, topo, v, at_[v])) figure_[v] = figure(v), at_[v] = tries.epoch();
    return figure_[v];
  }

 private:
  std::vector<double> figure_;
  std::vector<int64_t> at_;
};

}  // namespace

// A vertex whose incident face normals do not fit in an open hemisphere (an empty dual cone, left
// by the decimation) admits no ray direction that sees every face, so no thickness makes its slabs
// valid.
// Move such vertices towards the centroid of their one-ring (alone first, then with the ring)
// until every vertex's dual cone is not empty; the displacement map records the input surface
// wherever the vertex goes. A move is kept only when it leaves the worst seen star around it
// (the moved vertices and their neighbours) better seen than before: an unchecked Laplacian step
// empties the neighbours' cones (bones.off: 5 empty-cone vertices became 6).
void untangle(CoarseMesh& c) {
  const size_t nv = c.vertices.size();
  const VertexFrame topo = vertex_frames(c, 0);  // the CSR vertex -> faces; positions change below
  std::vector<Vec3> normals;
  auto seen = [&](int32_t v) {
    normals.clear();
    for (int32_t k = topo.offsets[v]; k < topo.offsets[v + 1]; ++k) {
      const Tri& t = c.faces[topo.faces[k]];
      const Vec3 n = (c.vertices[t[1]] - c.vertices[t[0]]).cross(c.vertices[t[2]] - c.vertices[t[0]]);
      if (n.norm() > 0) normals.push_back(n.normalized());
    }
    if (normals.empty()) return 1.0;
    Vec3 mean = Vec3::Zero();
    for (const Vec3& n : normals) mean += n;
    // max_min_direction()'s figure: the mean normal's when above 0.5, else the optimum's.
    double best = min_dot(mean.norm() > 0 ? Vec3(mean.normalized()) : normals[0], normals);
    if (best <= 0.5) mesh::detail::improve_max_min_figure(normals, best);
    return best;
  };
  std::vector<int32_t> ring, around;
  auto centroid = [&](int32_t v) {
    ring_of(c, topo, v, ring);
    Vec3 m = Vec3::Zero();
    for (int32_t u : ring) m += c.vertices[u];
    return ring.empty() ? c.vertices[v] : Vec3(m / double(ring.size()));
  };
  FailedTries tries(nv);
  KeptFigures kept(nv);  // for the vertices in place; a trial move's stars are found anew
  auto seen_in_place = [&](int32_t v) { return kept.get(c, topo, tries, v, seen); };
  for (int it = 0; it < 20; ++it) {
    bool moved = false;
    if (it == 10) tries.forget();  // the ring moves too from here
    for (int32_t v = 0; v < static_cast<int32_t>(nv); ++v) {
      if (tries.unchanged(c, topo, v)) continue;
      if (seen_in_place(v) > 0.02) continue;
      // The vertices a move of v (and, from the 10th sweep, of its ring) changes the stars of.
      std::vector<int32_t> movers{v};
      if (it >= 10) {
        ring_of(c, topo, v, ring);
        movers.insert(movers.end(), ring.begin(), ring.end());
      }
      std::vector<int32_t> affected;
      for (int32_t m : movers) {
        ring_of(c, topo, m, around);
        affected.push_back(m);
        affected.insert(affected.end(), around.begin(), around.end());
      }
      std::sort(affected.begin(), affected.end());
      affected.erase(std::unique(affected.begin(), affected.end()), affected.end());
      // The worst star before the move, and whether every star is better after it: the worst one
      // before is tried first, since it is the one that most often stays the worst.
      double before = 2;
      for (size_t i = 0; i < affected.size(); ++i)
        if (const double f = seen_in_place(affected[i]); f < before) before = f, std::swap(affected[0], affected[i]);
      auto all_better = [&] {
        for (int32_t u : affected)
          if (seen(u) <= before + 1e-6) return false;
        return true;
      };
      std::vector<Vec3> old(movers.size()), target(movers.size());
      for (size_t k = 0; k < movers.size(); ++k) old[k] = c.vertices[movers[k]], target[k] = centroid(movers[k]);
      bool moved_v = false;
      for (const double step : {0.5, 0.25, 0.1}) {
        for (size_t k = 0; k < movers.size(); ++k) {
          const double s = k ? 0.5 * step : step;  // the ring follows gently
          c.vertices[movers[k]] = (1 - s) * old[k] + s * target[k];
        }
        if ((moved_v = all_better())) break;
        for (size_t k = 0; k < movers.size(); ++k) c.vertices[movers[k]] = old[k];
      }
      if (moved_v)
        tries.moved(movers);
      else
        tries.failed(v);
      moved = moved || moved_v;
    }
    if (!moved && it >= 10) return;
    if (!moved) it = 9;  // the vertex alone no longer helps: move its ring with it
  }
}

CoarseMesh coarse_surface(const TriangleMesh& mesh, int target, const std::vector<double>& max_edge, double max_cost,
                          double* last_cost) {
  CoarseMesh coarse = decimate(mesh, target, max_edge, max_cost, last_cost);
  // A vertex whose star no direction sees whole cannot have valid slabs at any thickness.
  untangle(coarse);
  // Crumples whose cones the moves above could not open: smoothed towards harmonic discs (fix_empty_dual_cones()).
  TriangleMesh m{std::move(coarse.vertices), std::move(coarse.faces)};
  fix_empty_dual_cones(m);
  return CoarseMesh{std::move(m.vertices), std::move(m.faces)};
}

}  // namespace hdm::slab::detail
