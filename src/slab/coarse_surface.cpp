// SPDX-License-Identifier: MIT
// The bake's coarse surface: checked decimation, then every vertex star made visible.
#include "coarse_surface.h"

#include <hdm/mesh/decimate_mesh.h>
#include <hdm/mesh/flip_slivers.h>
#include <hdm/mesh/fix_empty_dual_cones.h>

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
    return min_dot(max_min_direction(mean.norm() > 0 ? Vec3(mean.normalized()) : normals[0], normals), normals);
  };
  std::vector<int32_t> ring, around;
  auto ring_of = [&](int32_t v, std::vector<int32_t>& out) {
    out.clear();
    for (int32_t k = topo.offsets[v]; k < topo.offsets[v + 1]; ++k)
      for (int32_t u : c.faces[topo.faces[k]])
        if (u != v) out.push_back(u);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
  };
  auto centroid = [&](int32_t v) {
    ring_of(v, ring);
    Vec3 m = Vec3::Zero();
    for (int32_t u : ring) m += c.vertices[u];
    return ring.empty() ? c.vertices[v] : Vec3(m / double(ring.size()));
  };
  for (int it = 0; it < 20; ++it) {
    bool moved = false;
    for (int32_t v = 0; v < static_cast<int32_t>(nv); ++v) {
      if (seen(v) > 0.02) continue;
      // The vertices a move of v (and, from the 10th sweep, of its ring) changes the stars of.
      std::vector<int32_t> movers{v};
      if (it >= 10) {
        ring_of(v, ring);
        movers.insert(movers.end(), ring.begin(), ring.end());
      }
      std::vector<int32_t> affected;
      for (int32_t m : movers) {
        ring_of(m, around);
        affected.push_back(m);
        affected.insert(affected.end(), around.begin(), around.end());
      }
      std::sort(affected.begin(), affected.end());
      affected.erase(std::unique(affected.begin(), affected.end()), affected.end());
      auto worst = [&] {
        double w = 2;
        for (int32_t u : affected) w = std::min(w, seen(u));
        return w;
      };
      const double before = worst();
      std::vector<Vec3> old(movers.size()), target(movers.size());
      for (size_t k = 0; k < movers.size(); ++k) old[k] = c.vertices[movers[k]], target[k] = centroid(movers[k]);
      for (const double step : {0.5, 0.25, 0.1}) {
        for (size_t k = 0; k < movers.size(); ++k) {
          const double s = k ? 0.5 * step : step;  // the ring follows gently
          c.vertices[movers[k]] = (1 - s) * old[k] + s * target[k];
        }
        if (worst() > before + 1e-6) {
          moved = true;
          break;
        }
        for (size_t k = 0; k < movers.size(); ++k) c.vertices[movers[k]] = old[k];
      }
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
