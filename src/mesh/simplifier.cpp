// SPDX-License-Identifier: MIT
// The decimation's mesh: set-up with quadrics and feature planes, the lazy collapse queue, the result.
#include "simplifier.h"

#include "max_min_direction.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <tuple>

namespace hdm::mesh::detail {
namespace {

// A collapse that moves a vertex by at most this fraction of the diagonal (a micrometre on a
// 10 cm part; a twentieth of the bake's RMS bound) changes no face visibly, though it may thin a
// sliver beside it in the last bits. CAD exports hold such edges, two vertices micrometres apart
// where an arc meets a line; held to the sliver test, their collapse was refused for a sine going
// from 0.0154148 to 0.0154146, and the edge and its slivers stayed as invalid slabs.
constexpr double kNegligibleMove = 1e-5;

}  // namespace

Simplifier::Simplifier(const TriangleMesh& mesh, const DecimateOptions& o) : o_(o), max_edge_(o.max_edge) {
  o_.max_edge = {};  // held once, in max_edge_
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
  cone_angle_.assign(nv, std::numbers::pi);  // unknown: recounted when first needed
  max_angle_ = std::acos(std::clamp(o.min_cone_margin, -1.0, 1.0));
  faces_left_ = static_cast<int64_t>(nf);
  cos_turn_ = std::cos(o.max_normal_turn_deg * std::numbers::pi / 180);
  sin_min_angle_ = std::sin(o.min_angle_deg * std::numbers::pi / 180);
  negligible_move_ = nv > 0 ? kNegligibleMove * bounds(mesh).diagonal() : 0;
  init_quadrics();
  empty_cone_.assign(nv, 0);
  for (int32_t v = 0; v < static_cast<int32_t>(nv); ++v) empty_cone_[v] = vertex_cone_margin(v) <= kEmptyCone;
}

void Simplifier::collapse_negligible_edges() {
  if (!(negligible_move_ > 0)) return;
  const double limit2 = negligible_move_ * negligible_move_;
  std::vector<int32_t> ring_v;
  for (int32_t v = 0; v < static_cast<int32_t>(pos_.size()); ++v) {
    if (!alive_[v]) continue;
    ring(v, ring_v);
    for (const int32_t w : ring_v)
      if (alive_[v] && alive_[w] && (pos_[v] - pos_[w]).squaredNorm() <= limit2) collapse(v, w);
  }
}

void Simplifier::run(int64_t target, double max_cost) {
  collapse_negligible_edges();
  for (int32_t v = 0; v < static_cast<int32_t>(pos_.size()); ++v) push_edges(v, -1, true);
  while (faces_left_ > target && !heap_.empty()) {
    const Candidate e = heap_.top();
    if (e.cost > max_cost) break;  // the heap's minimum: every other candidate costs as much
    heap_.pop();
    if (!alive_[e.a] || !alive_[e.b] || version_[e.a] != e.va || version_[e.b] != e.vb) continue;
    if (!collapse(e.a, e.b, e.cost < 0))
      retry_[e.a] = retry_[e.b] = 1;
    else
      last_cost_ = std::max(last_cost_, double(e.cost));
  }
}

TriangleMesh Simplifier::result(std::vector<int32_t>* kept) const {
  TriangleMesh out;
  if (kept) kept->clear();
  std::vector<int32_t> id(pos_.size(), -1);
  for (size_t f = 0; f < faces_.size(); ++f) {
    if (!alive_face_[f]) continue;
    Tri t;
    for (int k = 0; k < 3; ++k) {
      int32_t& i = id[faces_[f][k]];
      if (i < 0) {
        i = static_cast<int32_t>(out.vertices.size());
        out.vertices.push_back(pos_[faces_[f][k]]);
        if (kept) kept->push_back(faces_[f][k]);
      }
      t[k] = i;
    }
    out.faces.push_back(t);
  }
  return out;
}

Vec3 Simplifier::face_normal(int32_t f) const {
  const Tri& t = faces_[f];
  return (pos_[t[1]] - pos_[t[0]]).cross(pos_[t[2]] - pos_[t[0]]);
}

void Simplifier::init_quadrics() {
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
  const double cos_feature = std::cos(o_.feature_angle_deg * std::numbers::pi / 180);
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

void Simplifier::push_edges(int32_t v, int32_t skip, bool once) {
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
    // Empty-cone vertices first: they cannot give valid slabs, and at the end of the order (their
    // quadric error is high) they would survive every decimation.
    const float cost = empty_cone_[v] || empty_cone_[u] ? -1.0f : static_cast<float>(q(x));
    heap_.push({cost, v, u, version_[v], version_[u]});
  }
}

Vec3 Simplifier::place(const Quadric& q, int32_t a, int32_t b) const {
  if (!o_.on_input) return q.minimiser(0.5 * (pos_[a] + pos_[b]));
  return q(pos_[a]) <= q(pos_[b]) ? pos_[a] : pos_[b];
}

bool Simplifier::ring(int32_t v, std::vector<int32_t>& out) {
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

}  // namespace hdm::mesh::detail
