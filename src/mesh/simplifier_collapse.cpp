// SPDX-License-Identifier: MIT
// One checked edge collapse: the link condition, the geometric checks, the merge.
#include "simplifier.h"

#include "max_min_direction.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <tuple>

namespace hdm::mesh::detail {

bool Simplifier::link_condition(int32_t a, int32_t b) {
  // Link condition (Dey et al. 1999): the common neighbours of a and b are exactly the apexes of
  // the faces on edge ab; an interior edge may not join two boundary vertices; and two faces
  // (a,c,d), (b,c,d) would become one pair of duplicates.
  const bool ba = ring(a, ra_), bb = ring(b, rb_);
  if (!frozen_.empty()) {  // nothing within one edge of a frozen vertex changes
    const auto frozen = [&](int32_t v) { return frozen_[v] != 0; };
    if (frozen(a) || frozen(b) || std::any_of(ra_.begin(), ra_.end(), frozen) ||
        std::any_of(rb_.begin(), rb_.end(), frozen))
      return false;
  }
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
  return true;
}

bool Simplifier::collapse(int32_t a, int32_t b, bool reopen) {
  if (!link_condition(a, b)) return false;
  const Quadric q = quadric_[a] + quadric_[b];
  if (forced_) return merge(a, b, pos_[a], q, -2, std::numbers::pi), true;
  // Geometry: no face of the star turns by more than max_normal_turn or becomes a new sliver
  // (unless the collapse moves it by a negligible distance);
  // every vertex whose star changes (the new vertex and the link) stays visible. A reopening
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
      if (!(la > 0) || (!reopen && lb > 0 && nb.dot(na) < cos_turn_ * lb * la)) return void(ok = false);
      if (lb > 0) min_cos = std::min(min_cos, nb.dot(na) / (lb * la));
      const double sine = smallest_angle_sine(x, p, r);
      if (!reopen && sine < sin_min_angle_ && sine < smallest_angle_sine(pos_[v], p, r) &&
          (x - pos_[v]).squaredNorm() > negligible_move_ * negligible_move_)
        return void(ok = false);
      after_.push_back(na / la);
    });
    return ok;
  };
  Vec3 x = place(q, a, b);
  if (!max_edge_.empty() && !reopen && !short_edges(a, b, x)) return false;
  double seen = -2;
  {
    Vec3 tries[4] = {x, pos_[a], pos_[b], 0.5 * (pos_[a] + pos_[b])};
    const int count = reopen ? 4 : 1;
    double best_cos = 1;
    for (int k = 0; k < count; ++k) {
      after_.clear();
      min_cos = 1;
      if (!check(a, tries[k]) || !check(b, tries[k])) continue;
      const double v = cone_margin(after_);
      if (v > seen) seen = v, x = tries[k], best_cos = min_cos;
    }
    if (seen == -2) return false;
    min_cos = best_cos;
  }
  if (!x.allFinite()) return false;

  // The worse seen of the two stars it replaces: the new star must not be seen worse, unless it
  // is seen well enough anyway; a reopening collapse must do strictly better.
  const bool good = reopen ? seen > kEmptyCone : seen >= o_.min_cone_margin;
  const double was = good ? -2 : std::min(vertex_cone_margin(a), vertex_cone_margin(b));
  if (!good && (reopen ? !(seen > was + 1e-3) : seen < was)) {
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

void Simplifier::merge(int32_t a, int32_t b, const Vec3& x, const Quadric& q, double seen, double max_turn) {
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
  if (!max_edge_.empty()) max_edge_[a] = std::min(max_edge_[a], max_edge_[b]);
  ++version_[a];
  ++collapses_;
  // The link's stars lost faces or turned them by at most max_turn: their cone angle bound grows
  // by max_turn; the new vertex's star was just measured.
  for (int32_t w : ra_) cone_angle_[w] += max_turn;
  for (int32_t w : rb_)
    if (!std::binary_search(ra_.begin(), ra_.end(), w)) cone_angle_[w] += max_turn;
  if (seen == -2) seen = vertex_cone_margin(a);
  cone_angle_[a] = std::acos(std::clamp(seen, -1.0, 1.0));
  empty_cone_[a] = seen <= kEmptyCone;
  // Empty-cone link vertices may have a direction again: their edges lose the priority (new version).
  for (const std::vector<int32_t>* r : {&ra_, &rb_})
    for (int32_t w : *r)
      if (w != a && w != b && empty_cone_[w] && vertex_cone_margin(w) > kEmptyCone) {
        empty_cone_[w] = 0;
        ++version_[w];
        reopened_.push_back(w);
      }
  push_edges(a, -1, false);
  for (int32_t w : reopened_) push_edges(w, a, false);
  reopened_.clear();
  // Edges refused earlier near here may pass now that the neighbourhood changed.
  ring(a, ra_);
  for (int32_t w : ra_)
    if (retry_[w]) retry_[w] = 0, push_edges(w, a, false);
}

bool Simplifier::short_edges(int32_t a, int32_t b, const Vec3& x) const {
  const double cap = std::min(max_edge_[a], max_edge_[b]);
  for (const std::vector<int32_t>* r : {&ra_, &rb_})
    for (int32_t w : *r) {
      const double limit = std::min(cap, max_edge_[w]);
      if (w != a && w != b && limit < INFINITY && (pos_[w] - x).squaredNorm() > limit * limit) return false;
    }
  return true;
}

double Simplifier::vertex_cone_margin(int32_t v) {
  before_.clear();
  for_faces(v, [&](int32_t f, int) {
    const Vec3 n = face_normal(f);
    if (n.norm() > 0) before_.push_back(n.normalized());
  });
  return exact_cone_margin(before_);
}

bool Simplifier::link_visible(int32_t w, int32_t a, int32_t b, const Vec3& x, double max_turn) {
  if (cone_angle_[w] + max_turn <= max_angle_) return true;
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
  const double was = cone_margin(before_);
  cone_angle_[w] = std::acos(std::clamp(was, -1.0, 1.0));
  const double will = cone_margin(after_);
  if (will >= o_.min_cone_margin) return true;
  // "No worse seen" on the quick estimate alone let a barely seen star fold (the estimate is a
  // bound, not a measure): the exact values must not fold it either.
  if (!(will >= was)) return false;
  return cone_margin_kept(after_, before_, kEmptyCone);
}

}  // namespace hdm::mesh::detail
