// SPDX-License-Identifier: MIT
// Bake: decimate (checked edge collapses, decimate_mesh()), choose ray directions and shell offsets, validate every
// slab, cast one ray per sample against the input (Embree, TBB). Design notes §2.2, §3.7, §9-Q1..Q3.
#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/slab/shell_check.h>
#include <hdm/core/error.h>
#include <hdm/mesh/decimate_mesh.h>
#include <hdm/mesh/flip_slivers.h>
#include <hdm/mesh/unfold_stars.h>
#include <hdm/slab/bake.h>

#include "../mesh/max_min_direction.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <chrono>
#include <cmath>
#include <numeric>
#include <string>

namespace hdm {
namespace {

struct Coarse {
  std::vector<Vec3> vertices;
  std::vector<Tri> faces;
};

void progress(const BakeOptions& o, const char* stage, double f) {
  if (o.progress) o.progress(stage, f);
}

// Decimate to about `target` triangles (decimate_mesh(): edge collapses under the link condition,
// so the coarse mesh keeps the input's topology and orientation), then flip the caps the
// decimation kept (an input vertex on another face's edge): no slab over a cap is valid. Only
// near-degenerate caps (smallest angle below half a degree): flipping the milder caps along the
// crossing curves of a resolved union made slabs overlap there (bones.off).
Coarse decimate(const TriangleMesh& mesh, int target) {
  DecimateOptions o;
  o.target_faces = target;
  TriangleMesh m = decimate_mesh(mesh, o);
  flip_slivers(m, 0.5);
  return Coarse{std::move(m.vertices), std::move(m.faces)};
}

struct VertexFrame {
  std::vector<Vec3> direction;          // unit ray direction per coarse vertex
  std::vector<double> edge;             // mean incident edge length
  std::vector<int32_t> offsets, faces;  // CSR vertex -> faces
  std::vector<Vec3> face_normal;
};

double min_dot(const Vec3& d, const std::vector<Vec3>& normals) {
  double m = 2;
  for (const Vec3& n : normals) m = std::min(m, d.dot(n));
  return m;
}

// The unit direction that maximises the smallest dot product with the incident face normals (the
// centre of the smallest spherical cap holding them). The optimum is fixed by one, two or three
// active normals: try the area-weighted normal, every normal, every pair bisector and every triple
// circumcentre (small one-rings), keep the best.
Vec3 max_min_direction(const Vec3& start, const std::vector<Vec3>& normals) {
  Vec3 best = start;
  double best_val = min_dot(start, normals);
  if (best_val > 0.5) return best;  // the area-weighted normal is good enough: keep it (smooth field)
  detail::improve_max_min(normals, best_val, &best);
  return best;
}

// Per-vertex directions with a positive dot product against every incident face normal
// (docs/design.md#ray-directions: guarantees a positive Jacobian for a thin enough shell).
VertexFrame vertex_frames(const Coarse& c, int smoothing) {
  const size_t nv = c.vertices.size();
  VertexFrame fr;
  fr.direction.assign(nv, Vec3::Zero());
  fr.edge.assign(nv, 0.0);
  std::vector<int> valence(nv, 0);
  fr.face_normal.resize(c.faces.size());
  fr.offsets.assign(nv + 1, 0);
  for (size_t f = 0; f < c.faces.size(); ++f) {
    const Tri& t = c.faces[f];
    const Vec3 n = (c.vertices[t[1]] - c.vertices[t[0]]).cross(c.vertices[t[2]] - c.vertices[t[0]]);
    fr.face_normal[f] = n.normalized();
    for (int a = 0; a < 3; ++a) {
      fr.direction[t[a]] += n;
      fr.edge[t[a]] += (c.vertices[t[(a + 1) % 3]] - c.vertices[t[a]]).norm() +
                       (c.vertices[t[(a + 2) % 3]] - c.vertices[t[a]]).norm();
      valence[t[a]] += 2;
      ++fr.offsets[t[a] + 1];
    }
  }
  for (size_t v = 0; v < nv; ++v) fr.offsets[v + 1] += fr.offsets[v];
  fr.faces.resize(fr.offsets[nv]);
  std::vector<int32_t> fill(fr.offsets.begin(), fr.offsets.end() - 1);
  for (size_t f = 0; f < c.faces.size(); ++f)
    for (int32_t v : c.faces[f]) fr.faces[fill[v]++] = static_cast<int32_t>(f);
  std::vector<Vec3> normals;
  for (size_t v = 0; v < nv; ++v) {
    fr.edge[v] /= std::max(valence[v], 1);
    normals.clear();
    for (int32_t k = fr.offsets[v]; k < fr.offsets[v + 1]; ++k) normals.push_back(fr.face_normal[fr.faces[k]]);
    fr.direction[v] = max_min_direction(fr.direction[v].normalized(), normals);
  }
  // Smooth the direction field: near-parallel rays on neighbouring vertices keep slabs prism-like,
  // so concave regions can take a thicker shell before an alpha-triangle folds. A smoothed
  // direction is kept only while it still sees every incident face (min dot >= 0.25, or no worse
  // than the max-min direction).
  for (int it = 0; it < smoothing; ++it) {
    std::vector<Vec3> next = fr.direction;
    for (size_t v = 0; v < nv; ++v) {
      Vec3 sum = fr.direction[v];
      for (int32_t k = fr.offsets[v]; k < fr.offsets[v + 1]; ++k)
        for (int32_t u : c.faces[fr.faces[k]]) sum += fr.direction[u];
      const Vec3 cand = sum.normalized();
      double mc = 2, mo = 2;
      for (int32_t k = fr.offsets[v]; k < fr.offsets[v + 1]; ++k)
        mc = std::min(mc, cand.dot(fr.face_normal[fr.faces[k]])),
        mo = std::min(mo, fr.direction[v].dot(fr.face_normal[fr.faces[k]]));
      if (mc >= std::min(0.25, mo)) next[v] = cand;
    }
    fr.direction = std::move(next);
  }
  return fr;
}

// A vertex whose incident face normals do not fit in an open hemisphere (a star folded by the
// decimation) admits no ray direction that sees every face, so no thickness makes its slabs valid.
// Move such vertices towards the centroid of their one-ring (alone first, then with the ring)
// until every star is visible from one direction; the displacement map records the input surface
// wherever the vertex goes. A move is kept only when it leaves the worst seen star around it
// (the moved vertices and their neighbours) better seen than before: an unchecked Laplacian step
// folds the neighbours' stars (bones.off: 5 folded stars became 6).
void untangle(Coarse& c) {
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

}  // namespace

namespace {

// The bake; `prebuilt` is the caller's BVH over `mesh`, or null to build one here.
SlabModel bake(const TriangleMesh& mesh, const ExactMeshQuery* prebuilt, const std::string& name, const BakeOptions& o,
               BakeReport* report) {
  const auto start = std::chrono::steady_clock::now();
  if (o.grid_n < 1 || o.grid_n > 256)
    throw InvalidInput("--grid " + std::to_string(o.grid_n) + ": must be in [1, 256]");
  if (o.texel_density < 1 || o.texel_density > 16)
    throw InvalidInput("texel density " + std::to_string(o.texel_density) + ": must be in [1, 16]");
  if (o.slabs < 0) throw InvalidInput("--slabs " + std::to_string(o.slabs) + ": must be positive");
  if (!(o.density > 0 && o.density <= 1024))
    throw InvalidInput("--density " + std::to_string(o.density) + ": must be in (0, 1024]");
  validate_for_bake(mesh, name);
  const double diag = bounds(mesh).diagonal();
  const int n = o.grid_n;
  const int target = o.slabs > 0
                         ? o.slabs
                         : std::max(8, static_cast<int>(std::lround(double(mesh.faces.size()) * o.density / (n * n))));

  progress(o, "decimate", 0);
  Coarse coarse = decimate(mesh, target);
  // A vertex whose star no direction sees whole cannot have valid slabs at any thickness.
  untangle(coarse);
  {
    // Crumples the moves above could not unfold: smoothed towards harmonic discs (unfold_stars()).
    TriangleMesh m{std::move(coarse.vertices), std::move(coarse.faces)};
    unfold_stars(m);
    coarse = Coarse{std::move(m.vertices), std::move(m.faces)};
  }
  progress(o, "decimate", 1);
  const VertexFrame fr = vertex_frames(coarse, o.direction_smoothing);
  const size_t nv = coarse.vertices.size();
  std::unique_ptr<const ExactMeshQuery> own;
  if (!prebuilt) own = std::make_unique<const ExactMeshQuery>(mesh);
  const ExactMeshQuery& input = prebuilt ? *prebuilt : *own;
  const ExactMeshQuery coarse_query(TriangleMesh{coarse.vertices, coarse.faces});

  progress(o, "measure", 0);
  // Thickness each side must cover the input's deviation from the coarse surface near the vertex
  // (one-sided Hausdorff, attributed to the nearest coarse face's corners), plus edit headroom.
  std::vector<double> need_in(nv, 0.0), need_out(nv, 0.0);
  std::vector<double> slab_need_in(coarse.faces.size(), 0.0), slab_need_out(coarse.faces.size(), 0.0);
  {
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
  {
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
  {
    const std::vector<double> in0 = need_in, out0 = need_out;
    for (const Tri& t : coarse.faces)
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
          need_in[t[a]] = std::max(need_in[t[a]], in0[t[b]]), need_out[t[a]] = std::max(need_out[t[a]], out0[t[b]]);
  }
  std::vector<double> off_in(nv), off_out(nv), cap_in(nv), cap_out(nv), min_off(nv), tgt_in(nv), tgt_out(nv);
  {
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
        const Vec3 q =
            closest_point_on_triangle(x, coarse.vertices[t[0]], coarse.vertices[t[1]], coarse.vertices[t[2]]);
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
      off_in[v] = off_out[v] = min_off[v];
    }
  }

  SlabModel model;
  model.grid_n = n;
  model.texel_density = o.texel_density;
  model.slabs = coarse.faces;
  model.source = name;
  model.source_triangles = static_cast<int64_t>(mesh.faces.size());
  model.source_diagonal = diag;
  model.samples = build_sample_layout(model.slabs, static_cast<int>(nv), n);
  const int ns = model.samples.count;
  model.displacement.assign(ns, 0.5f);
  std::vector<uint8_t> missed(ns, 0);
  std::vector<uint8_t> undercut(ns, 0);
  BakeReport rep;

  model.inner.resize(nv);
  model.outer.resize(nv);
  auto place = [&](size_t v) {
    model.inner[v] = coarse.vertices[v] - off_in[v] * fr.direction[v];
    model.outer[v] = coarse.vertices[v] + off_out[v] * fr.direction[v];
  };
  auto jacobian = [&](int32_t f) {
    const Tri& t = model.slabs[f];
    const SlabGeometry g = make_slab_geometry(model.inner[t[0]], model.inner[t[1]], model.inner[t[2]],
                                              model.outer[t[0]], model.outer[t[1]], model.outer[t[2]]);
    return slab_min_jacobian(g, model.outer[t[1]] - model.inner[t[1]], model.outer[t[2]] - model.inner[t[2]]);
  };
  // The Jacobian each slab must keep while the shell grows: 0.02, or half of what the thinnest
  // shell gives where that is less (a barely seen star), never letting a valid slab turn invalid.
  std::vector<double> required(model.slabs.size());
  auto slab_ok = [&](int32_t f) { return jacobian(f) > required[f]; };
  for (size_t v = 0; v < nv; ++v) place(v);
  // Slabs that are invalid even in the thinnest shell (a direction that cannot see all its faces)
  // are left out of the growth test and reported.
  std::vector<uint8_t> hopeless(model.slabs.size());
  for (size_t f = 0; f < model.slabs.size(); ++f) {
    const double j = jacobian(static_cast<int32_t>(f));
    hopeless[f] = !(j > 0);
    required[f] = j > 0.04 ? 0.02 : 0.5 * j;
  }
  auto ring_ok = [&](size_t v) {
    for (int32_t k = fr.offsets[v]; k < fr.offsets[v + 1]; ++k)
      if (!hopeless[fr.faces[k]] && !slab_ok(fr.faces[k])) return false;
    return true;
  };
  // Grow while valid (thin-to-thick, as in the shell literature, docs/design.md#growing-the-shell):
  // from a thin valid shell, raise each vertex's offset towards its target, keeping the largest value
  // (found by bisection) for which every slab around the vertex stays valid. Gauss-Seidel sweeps.
  auto grow = [&] {
    // Every vertex grows by a bounded step per sweep (at most doubling, or a sixth of its
    // target), so neighbours rise together and the alpha-planes stay parallel; a vertex that
    // jumped to its target alone would tilt its slabs and block its neighbours' growth.
    for (int sweep = 0; sweep < 32; ++sweep) {
      bool changed = false;
      for (size_t v = 0; v < nv; ++v)
        for (int side = 0; side < 2; ++side) {
          double& off = side ? off_out[v] : off_in[v];
          const double target = side ? tgt_out[v] : tgt_in[v];
          if (off >= target * 0.999) continue;
          const double start = off;
          double lo = off, hi = std::min(target, std::max(2 * off, off + target / 6));
          off = hi;
          place(v);
          if (!ring_ok(v)) {
            for (int it = 0; it < 6; ++it) {
              off = 0.5 * (lo + hi);
              place(v);
              (ring_ok(v) ? lo : hi) = off;
            }
            off = lo;
            place(v);
          }
          changed |= off > start * 1.001;
        }
      if (!changed) break;
    }
  };

  // Thin the shell where slabs of different parts overlap (an exact boundary intersection test),
  // then re-thin any slab the uneven shrinking made invalid; targets follow so growth stops there.
  auto shrink = [&](size_t v, double f) {
    off_in[v] = std::max(min_off[v], off_in[v] * f), off_out[v] = std::max(min_off[v], off_out[v] * f);
    tgt_in[v] = std::min(tgt_in[v], off_in[v]), tgt_out[v] = std::min(tgt_out[v], off_out[v]);
    place(v);
  };
  // Overlapping pairs are kept from one check to the next and recomputed only around slabs
  // whose corners moved since (most of the shell is settled after the first iterations).
  std::vector<std::pair<int32_t, int32_t>> known_pairs;
  std::vector<Vec3> checked_inner, checked_outer;
  std::vector<uint8_t> moved(model.slabs.size());
  auto current_pairs = [&]() -> const std::vector<std::pair<int32_t, int32_t>>& {
    if (checked_inner.empty()) {
      known_pairs = overlapping_pairs(model);
    } else {
      for (size_t f = 0; f < model.slabs.size(); ++f) {
        moved[f] = 0;
        for (int32_t v : model.slabs[f])
          moved[f] |= model.inner[v] != checked_inner[v] || model.outer[v] != checked_outer[v];
      }
      update_overlapping_pairs(model, moved, known_pairs);
    }
    checked_inner = model.inner;
    checked_outer = model.outer;
    return known_pairs;
  };
  auto separate = [&] {
    for (int it = 0; it < 12; ++it) {
      const auto pairs = current_pairs();
      if (pairs.empty()) break;
      for (const auto& [a, b] : pairs)
        for (int32_t f : {a, b})
          for (int32_t v : model.slabs[f]) shrink(v, 0.9);
      for (int fix = 0; fix < 40; ++fix) {
        bool bad = false;
        for (size_t f = 0; f < model.slabs.size(); ++f)
          if (!hopeless[f] && !slab_ok(static_cast<int32_t>(f))) {
            bad = true;
            for (int32_t v : model.slabs[f]) shrink(v, 0.8);
          }
        if (!bad) break;
      }
    }
  };

  // Two passes: with slab separation, and, if thinning the shell where slabs overlap leaves too
  // many rays without a surface, without it (overlaps are then reported by `hdm check`).
  const std::vector<double> tgt_in0 = tgt_in, tgt_out0 = tgt_out;
  for (int pass = 0; pass < 2; ++pass) {
    const bool separating = pass == 0 && o.separate_slabs;
    if (pass == 1 && !o.separate_slabs) break;
    tgt_in = tgt_in0, tgt_out = tgt_out0;
    for (size_t v = 0; v < nv; ++v) off_in[v] = off_out[v] = min_off[v], place(v);
    rep.separated = separating;
    // Corners at the last cast: later rounds recast only the columns whose slab moved.
    std::vector<Vec3> cast_inner(nv, Vec3::Constant(NAN)), cast_outer(nv, Vec3::Constant(NAN));
    std::vector<uint8_t> stale(nv);
    for (int round = 0; round < 8; ++round) {
      rep.shell_iterations = round + 1;
      progress(o, "grow shell", round / 8.0);
      grow();
      progress(o, "separate", round / 8.0);
      if (separating) separate();
      for (size_t v = 0; v < nv; ++v)
        stale[v] = !(model.inner[v] == cast_inner[v]) || !(model.outer[v] == cast_outer[v]);
      cast_inner = model.inner;
      cast_outer = model.outer;
      // One ray per distinct sample, from the outer end inward; of the hits whose triangle faces
      // outward, keep the one nearest the coarse surface, not the outermost: in a thick shell
      // between close parts, fingers or the walls of a hole, the outermost hit can be another
      // part's surface, while the coarse surface follows the local one (docs/design.md#casting-the-displacements).
      const int blocks = 20;
      for (int b = 0; b < blocks; ++b) {
        const int lo = int(int64_t(ns) * b / blocks), hi = int(int64_t(ns) * (b + 1) / blocks);
        tbb::parallel_for(tbb::blocked_range<int>(lo, hi, 512), [&](const tbb::blocked_range<int>& r) {
          std::vector<SegmentHit> hits;
          for (int s = r.begin(); s < r.end(); ++s) {
            const Tri& home = model.slabs[model.samples.home_slab[s]];
            if (!stale[home[0]] && !stale[home[1]] && !stale[home[2]]) continue;
            Vec3 p0, p1;
            projection_line(model, model.samples.home_slab[s], model.samples.home_index[s], p0, p1);
            input.segment_hits(p1, p0, hits);
            const Vec3 up = p1 - p0;
            missed[s] = 1;
            undercut[s] = hits.size() > 1;
            const int index = model.samples.home_index[s];
            const double wT = model.samples.point_i[index] / double(n), wS = model.samples.point_j[index] / double(n);
            const Vec3 coarse_point = (1 - wT - wS) * coarse.vertices[home[0]] + wS * coarse.vertices[home[1]] +
                                      wT * coarse.vertices[home[2]];
            const double t_coarse = (coarse_point - p0).dot(up) / std::max(up.squaredNorm(), 1e-300);
            double best = INFINITY;
            for (const SegmentHit& h : hits)
              if (input.face_normal(h.face).dot(up) > 0 && std::abs(1.0 - h.t - t_coarse) < best) {
                best = std::abs(1.0 - h.t - t_coarse);
                model.displacement[s] = static_cast<float>(std::clamp(1.0 - h.t, 0.0, 1.0));
                missed[s] = 0;
              }
          }
        });
        progress(o, "cast rays", double(b + 1) / blocks);
      }
      // Grow the shell where rays missed: outward if the outer end is inside the input, else inward.
      // (The inside tests, three long rays each, run in parallel; the flags are gathered after.)
      int64_t misses = 0;
      std::vector<uint8_t> grow_in(nv, 0), grow_out(nv, 0);
      std::vector<uint8_t> outer_inside(ns, 0);
      tbb::parallel_for(tbb::blocked_range<int>(0, ns, 512), [&](const tbb::blocked_range<int>& r) {
        for (int s = r.begin(); s < r.end(); ++s) {
          if (!missed[s]) continue;
          Vec3 p0, p1;
          projection_line(model, model.samples.home_slab[s], model.samples.home_index[s], p0, p1);
          outer_inside[s] = input.inside(p1);
        }
      });
      for (int s = 0; s < ns; ++s) {
        if (!missed[s]) continue;
        ++misses;
        for (int32_t v : model.slabs[model.samples.home_slab[s]]) (outer_inside[s] ? grow_out : grow_in)[v] = 1;
      }
      rep.ray_misses = misses;
      if (misses == 0 || round == 7) break;
      bool grew = false;
      for (size_t v = 0; v < nv; ++v) {
        if (grow_in[v] && tgt_in[v] < cap_in[v])
          tgt_in[v] = std::min(cap_in[v], std::max(tgt_in[v], off_in[v]) * 1.5), grew = true;
        if (grow_out[v] && tgt_out[v] < cap_out[v])
          tgt_out[v] = std::min(cap_out[v], std::max(tgt_out[v], off_out[v]) * 1.5), grew = true;
      }
      if (!grew) break;
    }
    if (rep.ray_misses <= o.miss_limit * ns) break;
  }
  // Slab pairs that still overlap: none once separation converged; without separation (the
  // second pass) the exact check runs once here.
  rep.overlapping_pairs = rep.separated ? static_cast<int64_t>(current_pairs().size())
                                        : static_cast<int64_t>(overlapping_pairs(model).size());
  // A column that misses the input still has a best point: the one on its line nearest the input
  // (sampled, then refined by golden-section search). This keeps the filled surface on the input
  // where the shell passes beside it, instead of averaging neighbours.
  progress(o, "fill misses", 0);
  tbb::parallel_for(0, ns, [&](int s) {
    if (!missed[s]) return;
    Vec3 p0, p1;
    projection_line(model, model.samples.home_slab[s], model.samples.home_index[s], p0, p1);
    auto dist = [&](double t) { return input.closest_point(p0 + t * (p1 - p0)).distance; };
    double best_t = 0, best = dist(0);
    for (int k = 1; k <= 16; ++k)
      if (const double d = dist(k / 16.0); d < best) best = d, best_t = k / 16.0;
    double lo = std::max(0.0, best_t - 1 / 16.0), hi = std::min(1.0, best_t + 1 / 16.0);
    const double g = (std::sqrt(5.0) - 1) / 2;
    for (int it = 0; it < 20; ++it) {  // each distance once (two closest-point queries per step)
      const double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
      const bool left = dist(x1) < dist(x2);
      (left ? hi : lo) = left ? x2 : x1;
    }
    model.displacement[s] = static_cast<float>(std::clamp(0.5 * (lo + hi), 0.0, 1.0));
  });
  rep.undercut_columns = std::count(undercut.begin(), undercut.end(), uint8_t(1));
  // rebuild_derived() builds the texel layout (and fills `colour` with its default); the bake's
  // colour is set afterwards, so the layout is built once.
  model.colour.clear();
  progress(o, "derived data", 0);
  rebuild_derived(model);
  model.colour.assign(model.texels.count, encode_srgb8(o.colour));
  progress(o, "derived data", 1);

  for (int s = 0; s < model.slab_count(); ++s) {
    const Tri& t = model.slabs[s];
    if (slab_min_jacobian(model.geometry[s], model.outer[t[1]] - model.inner[t[1]],
                          model.outer[t[2]] - model.inner[t[2]]) <= 0) {
      ++rep.invalid_slabs;
    }
  }
  rep.slabs = model.slab_count();
  rep.grid_n = n;
  rep.input_triangles = static_cast<int64_t>(mesh.faces.size());
  rep.submesh_triangles = int64_t(rep.slabs) * n * n;
  rep.samples = ns;
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (report) *report = rep;
  return model;
}

}  // namespace

SlabModel bake_slabs(const TriangleMesh& mesh, const std::string& name, const BakeOptions& o, BakeReport* report) {
  return bake(mesh, nullptr, name, o, report);
}

SlabModel bake_slabs(const ExactMeshQuery& input, const std::string& name, const BakeOptions& o, BakeReport* report) {
  return bake(input.mesh(), &input, name, o, report);
}

}  // namespace hdm
