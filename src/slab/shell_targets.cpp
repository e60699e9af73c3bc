// SPDX-License-Identifier: MIT
// The shell thickness each coarse vertex should and may take (docs/design.md#shell-thickness).
#include "shell_targets.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace hdm::slab::detail {
namespace {

// Distance along ray x + t·d (t > 0) to the coarse surface, ignoring faces around vertex v.
double free_distance(const ExactMeshQuery& coarse, const VertexFrame& fr, int32_t v, const Vec3& x, const Vec3& d,
                     double far, std::vector<SegmentHit>& hits) {
  coarse.segment_hits(x, x + far * d, hits);
  for (const SegmentHit& h : hits) {
    bool incident = false;
    for (int32_t k = fr.offsets[v]; k < fr.offsets[v + 1]; ++k) incident |= fr.faces[k] == h.face;
    if (!incident) return h.t * far;
  }
  return far;
}

// Thickness each side must cover the input's deviation from the coarse surface near the vertex
// (one-sided Hausdorff, attributed to the nearest coarse face's corners).
void deviation_needs(const TriangleMesh& mesh, const CoarseMesh& coarse, const ExactMeshQuery& coarse_query,
                     const VertexFrame& fr, std::vector<double>& need_in, std::vector<double>& need_out) {
  std::vector<int32_t> face(mesh.vertices.size());
  std::vector<double> signed_dist(mesh.vertices.size());
  tbb::parallel_for(size_t(0), mesh.vertices.size(), [&](size_t v) {
    const ClosestPoint cp = coarse_query.closest_point(mesh.vertices[v]);
    face[v] = cp.face;
    signed_dist[v] = (mesh.vertices[v] - cp.point).dot(fr.face_normal[cp.face]);
  });
  for (size_t v = 0; v < mesh.vertices.size(); ++v)
    for (int32_t c : coarse.faces[face[v]]) {
      need_out[c] = std::max(need_out[c], signed_dist[v]);
      need_in[c] = std::max(need_in[c], -signed_dist[v]);
    }
}

// ... and the extent the slab's own lines need: from points of each coarse slab, along the
// interpolated ray direction both ways, the outward-facing input hit nearest the coarse surface
// (where the rays will look for it). Where the input runs oblique to the rays this is longer than
// its normal distance, and it sees input features between input vertices.
void line_needs(const ExactMeshQuery& input, const CoarseMesh& coarse, const VertexFrame& fr, double diag,
                std::vector<double>& need_in, std::vector<double>& need_out) {
  std::vector<double> slab_need_in(coarse.faces.size(), 0.0), slab_need_out(coarse.faces.size(), 0.0);
  constexpr int m = 6;  // points per slab edge
  const double reach = 0.5 * diag;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, coarse.faces.size(), 64), [&](const tbb::blocked_range<size_t>& r) {
    std::vector<SegmentHit> hits;
    for (size_t f = r.begin(); f < r.end(); ++f) {
      const Tri& t = coarse.faces[f];
      double far_in = 0, far_out = 0;
      for (int i = 0; i <= m; ++i)
        for (int j = 0; i + j <= m; ++j) {
          const double wT = double(i) / m, wS = double(j) / m, wR = 1 - wT - wS;
          const Vec3 x = wR * coarse.vertices[t[0]] + wS * coarse.vertices[t[1]] + wT * coarse.vertices[t[2]];
          const Vec3 d = (wR * fr.direction[t[0]] + wS * fr.direction[t[1]] + wT * fr.direction[t[2]]).normalized();
          const double len = std::min({fr.edge[t[0]], fr.edge[t[1]], fr.edge[t[2]], reach});
          double best = INFINITY;
          input.segment_hits(x + len * d, x - len * d, hits);  // t = 0 outer end, 1 inner end
          for (const SegmentHit& h : hits)
            if (input.face_normal(h.face).dot(d) > 0) {
              const double s = (0.5 - h.t) * 2 * len;  // signed distance from x along d
              if (std::abs(s) < std::abs(best)) best = s;
            }
          if (!std::isfinite(best)) continue;
          (best > 0 ? far_out : far_in) = std::max(best > 0 ? far_out : far_in, std::abs(best));
        }
      slab_need_in[f] = far_in;
      slab_need_out[f] = far_out;
    }
  });
  for (size_t f = 0; f < coarse.faces.size(); ++f)
    for (int32_t c : coarse.faces[f]) {
      need_in[c] = std::max(need_in[c], slab_need_in[f]);
      need_out[c] = std::max(need_out[c], slab_need_out[f]);
    }
}

// Dilate the needs over the one-ring: neighbouring offsets then vary slowly, which keeps the
// alpha-planes from tilting (large offset jumps between neighbours break the Jacobian).
void dilate_needs(const CoarseMesh& coarse, std::vector<double>& need_in, std::vector<double>& need_out) {
  const std::vector<double> in0 = need_in, out0 = need_out;
  for (const Tri& t : coarse.faces)
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        need_in[t[a]] = std::max(need_in[t[a]], in0[t[b]]), need_out[t[a]] = std::max(need_out[t[a]], out0[t[b]]);
}

}  // namespace

ShellTargets shell_targets(const TriangleMesh& mesh, const ExactMeshQuery& input, const CoarseMesh& coarse,
                           const ExactMeshQuery& coarse_query, const VertexFrame& fr, const BakeOptions& o,
                           double diag) {
  const size_t nv = coarse.vertices.size();
  std::vector<double> need_in(nv, 0.0), need_out(nv, 0.0);
  deviation_needs(mesh, coarse, coarse_query, fr, need_in, need_out);
  line_needs(input, coarse, fr, diag, need_in, need_out);
  dilate_needs(coarse, need_in, need_out);
  ShellTargets s;
  auto& [cap_in, cap_out, min_off, tgt_in, tgt_out] = s;
  for (auto* v : {&cap_in, &cap_out, &min_off, &tgt_in, &tgt_out}) v->resize(nv);
  std::vector<SegmentHit> hits;
  std::vector<int32_t> near_faces;
  std::vector<int32_t> ring2(coarse.faces.size(), 0);  // vi + 1 for faces of the 2-ring of vi
  for (size_t v = 0; v < nv; ++v) {
    const Vec3& x = coarse.vertices[v];
    const Vec3& d = fr.direction[v];
    const auto vi = static_cast<int32_t>(v);
    for (int32_t k = fr.offsets[v]; k < fr.offsets[v + 1]; ++k)
      for (int32_t u : coarse.faces[fr.faces[k]])
        for (int32_t j = fr.offsets[u]; j < fr.offsets[u + 1]; ++j) ring2[fr.faces[j]] = vi + 1;
    cap_in[v] = 0.45 * free_distance(coarse_query, fr, vi, x, -d, diag, hits);
    cap_out[v] = 0.45 * free_distance(coarse_query, fr, vi, x, d, diag, hits);
    // No thicker than the local slab size: longer rays add no fidelity, only spread the samples.
    cap_in[v] = std::min(cap_in[v], o.max_thickness * fr.edge[v]);
    cap_out[v] = std::min(cap_out[v], o.max_thickness * fr.edge[v]);
    // ... nor than 0.45 of the clearance to another part of the coarse surface on that side, in
    // any direction (faces beyond the vertex's 2-ring, in front of or behind the vertex): shells
    // of parts side by side (legs, fingers) cannot meet where the free distance along the
    // ray sees nothing.
    const double reach = std::max(cap_in[v], cap_out[v]) / 0.45;
    coarse_query.faces_within(x, reach, near_faces);
    double clear_in = reach, clear_out = reach;
    for (int32_t f : near_faces) {
      if (ring2[f] == vi + 1) continue;
      const Tri& t = coarse.faces[f];
      const Vec3 q = closest_point_on_triangle(x, coarse.vertices[t[0]], coarse.vertices[t[1]], coarse.vertices[t[2]]);
      double& clear = (q - x).dot(d) > 0 ? clear_out : clear_in;
      clear = std::min(clear, (q - x).norm());
    }
    cap_in[v] = std::min(cap_in[v], 0.45 * clear_in);
    cap_out[v] = std::min(cap_out[v], 0.45 * clear_out);
    // Headroom for edits and for the cursor's penetration (docs/design.md#shell-thickness), at least
    // options.min_thickness of the diagonal where the model is thick enough.
    const double floor = std::max(o.headroom * fr.edge[v], o.min_thickness * diag);
    min_off[v] = std::min({1e-3 * fr.edge[v], cap_in[v], cap_out[v]});
    tgt_in[v] = std::min(cap_in[v], std::max(1.5 * need_in[v] + 1e-4 * diag, floor));
    tgt_out[v] = std::min(cap_out[v], std::max(1.5 * need_out[v] + 1e-4 * diag, floor));
  }
  return s;
}

}  // namespace hdm::slab::detail
