// SPDX-License-Identifier: MIT
// Folded stars of a coarse mesh replaced by harmonic discs (see unfold_stars.h).
#include <hdm/core/error.h>
#include <hdm/mesh/unfold_stars.h>

#include "max_min_direction.h"

#include <algorithm>
#include <string>
#include <vector>

namespace hdm {

UnfoldReport unfold_stars(TriangleMesh& mesh, double min_visibility, int max_rings) {
  if (!(min_visibility >= -1 && min_visibility < 1))
    throw InvalidInput("unfold_stars: min_visibility " + std::to_string(min_visibility) + " must be in [-1, 1)");
  if (max_rings < 1) throw InvalidInput("unfold_stars: max_rings " + std::to_string(max_rings) + " must be >= 1");
  validate_mesh_data(mesh, "unfold_stars input");
  const auto nv = static_cast<int32_t>(mesh.vertices.size());
  std::vector<Vec3>& p = mesh.vertices;
  // Vertex -> faces (CSR), and the vertices on the mesh's boundary (an edge with one face).
  std::vector<int32_t> offset(nv + 1, 0), faces;
  for (const Tri& t : mesh.faces)
    for (int32_t v : t) ++offset[v + 1];
  for (int32_t v = 0; v < nv; ++v) offset[v + 1] += offset[v];
  faces.resize(offset[nv]);
  {
    std::vector<int32_t> fill(offset.begin(), offset.end() - 1);
    for (size_t f = 0; f < mesh.faces.size(); ++f)
      for (int32_t v : mesh.faces[f]) faces[fill[v]++] = static_cast<int32_t>(f);
  }
  // Neighbours of v (sorted, distinct); v is on the boundary when some neighbour is met once.
  std::vector<uint8_t> boundary(nv, 0);
  std::vector<int32_t> nbr_offset(nv + 1, 0), nbr;
  {
    std::vector<int32_t> ring;
    for (int32_t v = 0; v < nv; ++v) {
      ring.clear();
      for (int32_t k = offset[v]; k < offset[v + 1]; ++k) {
        const Tri& t = mesh.faces[faces[k]];
        for (int a = 0; a < 3; ++a)
          if (t[a] == v) ring.push_back(t[(a + 1) % 3]), ring.push_back(t[(a + 2) % 3]);
      }
      std::sort(ring.begin(), ring.end());
      for (size_t i = 0; i < ring.size();) {
        size_t j = i;
        while (j < ring.size() && ring[j] == ring[i]) ++j;
        boundary[v] |= j - i == 1;
        nbr.push_back(ring[i]);
        i = j;
      }
      nbr_offset[v + 1] = static_cast<int32_t>(nbr.size());
    }
  }
  // The best direction's smallest dot product with v's face normals (degenerate faces left out).
  std::vector<Vec3> normals;
  auto visibility = [&](int32_t v) {
    normals.clear();
    Vec3 mean = Vec3::Zero();
    for (int32_t k = offset[v]; k < offset[v + 1]; ++k) {
      const Tri& t = mesh.faces[faces[k]];
      const Vec3 n = (p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]);
      if (n.norm() > 0) normals.push_back(n.normalized()), mean += normals.back();
    }
    if (normals.empty()) return 1.0;
    double best = -2;
    if (mean.norm() > 0) {
      best = 2;
      const Vec3 d = mean.normalized();
      for (const Vec3& n : normals) best = std::min(best, d.dot(n));
      if (best > min_visibility) return best;  // seen well enough: no search needed
    }
    detail::improve_max_min(normals, best, nullptr);
    return best;
  };
  auto folded = [&](int32_t v) { return visibility(v) <= min_visibility; };

  UnfoldReport report;
  std::vector<int32_t> layer(nv, -1);  // ring index of a vertex in the current disc, -1 outside
  std::vector<int32_t> disc, affected, free;
  std::vector<uint8_t> was_folded;
  std::vector<Vec3> saved;
  for (int32_t v = 0; v < nv; ++v) report.folded_before += folded(v);
  for (int32_t v = 0; v < nv; ++v) {
    if (!folded(v)) continue;
    for (int k = 1; k <= max_rings; ++k) {
      // The disc: vertices within k - 1 edges of v (their faces are the disc's faces); the
      // affected vertices add the next ring, whose stars share those faces.
      disc.assign(1, v);
      layer[v] = 0;
      for (size_t i = 0; i < disc.size(); ++i) {
        const int32_t u = disc[i];
        if (layer[u] + 1 > k) continue;
        for (int32_t j = nbr_offset[u]; j < nbr_offset[u + 1]; ++j)
          if (layer[nbr[j]] < 0) layer[nbr[j]] = layer[u] + 1, disc.push_back(nbr[j]);
      }
      free.clear();
      affected = disc;
      for (int32_t u : disc)
        if (layer[u] < k && !boundary[u]) free.push_back(u);
      was_folded.resize(affected.size());
      int64_t before = 0;
      for (size_t i = 0; i < affected.size(); ++i) before += was_folded[i] = folded(affected[i]);
      saved.resize(free.size());
      for (size_t i = 0; i < free.size(); ++i) saved[i] = p[free[i]];
      // Smooth in growing numbers of sweeps and keep the first state that unfolds: a crumple is
      // small next to the disc, so it goes in a few sweeps while the disc's shape stays (a disc
      // smoothed to convergence around a thin part, such as a tail's tip, flattens the part).
      bool done = false;
      for (int sweep = 1; sweep <= 1024 && !done; ++sweep) {
        for (int32_t u : free) {
          Vec3 sum = Vec3::Zero();
          for (int32_t j = nbr_offset[u]; j < nbr_offset[u + 1]; ++j) sum += p[nbr[j]];
          p[u] += 0.25 * (sum / double(nbr_offset[u + 1] - nbr_offset[u]) - p[u]);
        }
        if (sweep > 16 && (sweep & (sweep - 1))) continue;  // judged after 1, 2, ... 16, 32, 64, ... sweeps
        int64_t after = 0;
        bool newly = false;
        for (size_t i = 0; i < affected.size(); ++i) {
          const bool f = folded(affected[i]);
          after += f;
          newly |= f && !was_folded[i];
        }
        done = after < before && !newly;
        if (done) report.moved += static_cast<int64_t>(free.size());
      }
      for (int32_t u : disc) layer[u] = -1;
      if (done) break;
      for (size_t i = 0; i < free.size(); ++i) p[free[i]] = saved[i];
    }
  }
  for (int32_t v = 0; v < nv; ++v) report.folded_after += folded(v);
  return report;
}

}  // namespace hdm
