// SPDX-License-Identifier: MIT
#include "angle_deg.h"

#include <hdm/core/error.h>
#include <hdm/core/percentile.h>
#include <hdm/harness/scenario_sites.h>
#include <hdm/query/slab_query.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <limits>
#include <random>

namespace hdm {
namespace {

using harness::detail::angle_deg;

Vec3 tangential(const Vec3& v, const Vec3& n) { return v - v.dot(n) * n; }

// A deterministic unit vector perpendicular to n.
Vec3 any_perpendicular(const Vec3& n) {
  const Vec3 axis = std::abs(n.x()) < 0.6 ? Vec3::UnitX() : (std::abs(n.y()) < 0.6 ? Vec3::UnitY() : Vec3::UnitZ());
  return n.cross(axis).normalized();
}

// The bake represents the input's surface at @p p (normal @p n) when a point a quarter of the part's
// thickness @p t inside it is inside the slab model's surface, with its surface point within t/4
// of p's tangent plane (the projection line is oblique) and its normal within 25 degrees of n. A sheet thinner than the
// bake resolves fails this on one side (the two sides' slabs overlap or the displacement is clipped).
bool represented(const SlabModel& model, const SlabLocator& locator, const Vec3& p, const Vec3& n, double t) {
  QueryCache cache;
  const Contact c = query(model, locator, p - n * (0.25 * t), cache);
  return c.penetrating() && std::abs((c.surface_point - p).dot(n)) < 0.25 * t &&
         c.normal.dot(n) > std::cos(25 * std::numbers::pi / 180);
}

// The bake represents a stroke when at every point a point 0.002 of the diagonal under it (about
// 0.3 mm at the device) is inside the rendered surface, with its surface point within that depth of
// the input's tangent plane and its normal within 15 degrees of the input's interpolated normal.
// On the armadillo the smoothest slab corner fails this: its grid folds over itself near the
// corner (neighbouring grid normals 77 degrees apart) and the model's normal is 27 degrees off
// the input's there, which no force rendering of the slab model can follow.
bool stroke_represented(const SlabModel& model, const SlabLocator& locator, const SurfaceStroke& st, double diag) {
  const double d = 0.002 * diag, cos_max = std::cos(15 * std::numbers::pi / 180);
  QueryCache cache;
  for (const SurfacePoint& p : st.points) {
    const Contact c = query(model, locator, p.point - p.normal * d, cache);
    if (!c.penetrating() || std::abs((c.surface_point - p.point).dot(p.normal)) > d || c.normal.dot(p.normal) < cos_max)
      return false;
  }
  return true;
}

}  // namespace

ScenarioSites::ScenarioSites(const ExactMeshQuery& reference, const SiteOptions& options)
    : ref_(reference), o_(options) {
  const TriangleMesh& m = ref_.mesh();
  diag_ = bounds(m).diagonal();
  vertex_normals_.assign(m.vertices.size(), Vec3::Zero());
  std::vector<double> cumulative;
  cumulative.reserve(m.faces.size());
  double area = 0;
  for (const Tri& f : m.faces) {
    const Vec3 n = (m.vertices[f[1]] - m.vertices[f[0]]).cross(m.vertices[f[2]] - m.vertices[f[0]]);
    for (int k = 0; k < 3; ++k) vertex_normals_[f[k]] += n;  // area-weighted
    area += 0.5 * n.norm();
    cumulative.push_back(area);
  }
  if (!(area > 0) || !(diag_ > 0)) throw InvalidInput("scenario sites: the input mesh has no face of positive area");
  for (Vec3& n : vertex_normals_)
    if (n.norm() > 0) n.normalize();
  // Area-weighted samples from a fixed seed; projecting them gives the normals.
  std::mt19937_64 rng(o_.seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  samples_.reserve(o_.samples);
  for (int i = 0; i < o_.samples; ++i) {
    const size_t f =
        std::min(m.faces.size() - 1,
                 static_cast<size_t>(std::lower_bound(cumulative.begin(), cumulative.end(), u01(rng) * area) -
                                     cumulative.begin()));
    double a = u01(rng), b = u01(rng);
    if (a + b > 1) a = 1 - a, b = 1 - b;
    const Tri& t = m.faces[f];
    samples_.push_back(project(m.vertices[t[0]] + a * (m.vertices[t[1]] - m.vertices[t[0]]) +
                               b * (m.vertices[t[2]] - m.vertices[t[0]])));
  }
}

SurfacePoint ScenarioSites::project(const Vec3& p) const {
  SurfacePoint s;
  const ClosestPoint cp = ref_.closest_point(p);
  s.point = cp.point;
  s.face = cp.face;
  if (cp.face < 0) return s;
  s.face_normal = ref_.face_normal(cp.face);
  const TriangleMesh& m = ref_.mesh();
  const Tri& t = m.faces[cp.face];
  const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
  const Vec3 nn = (b - a).cross(c - a);
  const double area = nn.squaredNorm();
  s.normal = s.face_normal;
  if (area > 0) {
    const double wb = (cp.point - a).cross(c - a).dot(nn) / area, wc = (b - a).cross(cp.point - a).dot(nn) / area;
    const Vec3 n = (1 - wb - wc) * vertex_normals_[t[0]] + wb * vertex_normals_[t[1]] + wc * vertex_normals_[t[2]];
    if (n.norm() > 1e-12) s.normal = n.normalized();
  }
  return s;
}

bool ScenarioSites::exposed(const SurfacePoint& s, double distance) const {
  const Vec3 a = s.point + s.normal * (1e-4 * diag_);
  return ref_.first_hit(a, s.point + s.normal * distance).face < 0;
}

double ScenarioSites::thickness(const SurfacePoint& s) const {
  // From just outside, so the entry face itself is the first hit; the next one is the exit.
  const double eps = 1e-4 * diag_, len = 2 * diag_;
  const Vec3 a = s.point + s.normal * eps;
  std::vector<SegmentHit> hits;
  ref_.segment_hits(a, s.point - s.normal * len, hits);
  for (const SegmentHit& h : hits) {
    const double d = h.t * (len + eps) - eps;
    if (d > 2 * eps) return d;
  }
  return std::numeric_limits<double>::infinity();
}

SurfaceStroke ScenarioSites::walk(const SurfacePoint& start, const Vec3& direction, double length, int steps) const {
  SurfaceStroke s;
  s.points.push_back(start);
  const double h = length / steps;
  Vec3 d = tangential(direction, start.normal);
  if (d.norm() < 1e-12) return s;
  d.normalize();
  for (int i = 0; i < steps; ++i) {
    const SurfacePoint& cur = s.points.back();
    const SurfacePoint q = project(cur.point + d * h);
    const Vec3 moved = tangential(q.point - cur.point, q.normal);
    if (q.face < 0 || moved.norm() < 0.25 * h) break;  // stalled in a crease
    d = moved.normalized();                            // keep heading: the walk follows the surface like a geodesic
    s.points.push_back(q);
  }
  return s;
}

// roughness: p95 of the face-vs-interpolated normal angle (fine relief the force will not follow);
// bend: the largest normal turn between neighbours, per 0.005 of the diagonal (creases).
void ScenarioSites::score(SurfaceStroke& s) const {
  std::vector<double> dev;
  dev.reserve(s.points.size());
  s.bend_deg = 0;
  for (size_t i = 0; i < s.points.size(); ++i) {
    dev.push_back(angle_deg(s.points[i].face_normal, s.points[i].normal));
    if (i == 0) continue;
    const double step = (s.points[i].point - s.points[i - 1].point).norm();
    if (step > 0)
      s.bend_deg = std::max(s.bend_deg, angle_deg(s.points[i].normal, s.points[i - 1].normal) * 0.005 * diag_ / step);
  }
  s.roughness_deg = percentile(dev, 0.95);
}

bool ScenarioSites::stroke_ok(const SurfaceStroke& s) const {
  for (size_t i = 0; i < s.points.size(); ++i) {
    if (!exposed(s.points[i], o_.clearance * diag_)) return false;
    if (i % 4 == 0 && thickness(s.points[i]) < o_.min_depth * diag_) return false;
  }
  return true;
}

SurfaceStroke ScenarioSites::slide_stroke() const {
  const double length = o_.stroke_length * diag_;
  const int steps = 50;
  SurfaceStroke best;
  double best_score = std::numeric_limits<double>::infinity();
  int tried = 0;
  for (const SurfacePoint& s : samples_) {
    if (tried >= o_.candidates) break;
    if (s.face < 0 || angle_deg(s.face_normal, s.normal) > 10 || !exposed(s, o_.clearance * diag_)) continue;
    ++tried;
    const Vec3 u = any_perpendicular(s.normal), w = s.normal.cross(u);
    for (int k = 0; k < 8; ++k) {
      const double a = std::numbers::pi * k / 4;
      SurfaceStroke st = walk(s, std::cos(a) * u + std::sin(a) * w, length, steps);
      if (static_cast<int>(st.points.size()) != steps + 1) continue;
      score(st);
      const double sc = st.roughness_deg + 2 * st.bend_deg;
      if (sc < best_score && stroke_ok(st)) {
        best_score = sc;
        best = std::move(st);
      }
    }
  }
  if (best.points.empty()) throw InvalidInput("slide: no smooth, exposed stroke of the requested length on the input");
  return best;
}

SurfacePoint ScenarioSites::press_spot() const {
  struct Cand {
    SurfacePoint s;
    double score, thickness;
  };
  std::vector<Cand> cands;
  const double arm = 0.03 * diag_;
  for (const SurfacePoint& s : samples_) {
    if (static_cast<int>(cands.size()) >= o_.candidates) break;
    if (s.face < 0 || angle_deg(s.face_normal, s.normal) > 10 || !exposed(s, o_.clearance * diag_)) continue;
    // A small cross round the spot: the hand pushes several millimetres in, the surface around it
    // should be smooth.
    const Vec3 u = any_perpendicular(s.normal), w = s.normal.cross(u);
    SurfaceStroke patch;
    for (const Vec3& d : {u, w, Vec3(-u), Vec3(-w)}) {
      const SurfaceStroke arm_walk = walk(s, d, arm, 6);
      patch.points.insert(patch.points.end(), arm_walk.points.begin(), arm_walk.points.end());
    }
    score(patch);
    cands.push_back({s, patch.roughness_deg + 2 * patch.bend_deg, thickness(s)});
  }
  if (cands.empty()) throw InvalidInput("press: no exposed spot on the input");
  std::vector<double> scores;
  for (const Cand& c : cands) scores.push_back(c.score);
  const double cut = percentile(scores, 0.25);  // the smoothest quarter
  const Cand* best = nullptr;
  for (const Cand& c : cands)
    if (c.score <= cut && std::isfinite(c.thickness) && (!best || c.thickness > best->thickness)) best = &c;
  if (!best) throw InvalidInput("press: no smooth spot over a closed part of the input");
  return best->s;
}

ThinSite ScenarioSites::thin_site(const SlabModel& model, const SlabLocator& locator) const {
  const double tmin = o_.min_thin * diag_, tmax = o_.max_thin * diag_, eps = 1e-4 * diag_;
  const double cos_opposed = std::cos(145 * std::numbers::pi / 180), cos_flat = std::cos(35 * std::numbers::pi / 180);
  struct Cand {
    ThinSite site;
    int agree;
  };
  std::vector<Cand> cands;
  for (const SurfacePoint& s : samples_) {
    if (s.face < 0 || angle_deg(s.face_normal, s.normal) > 20) continue;
    const double t = thickness(s);
    if (!(t >= tmin && t <= tmax)) continue;
    // The exit: a face turned against the entry (a sheet, not a grazing ray), open beyond.
    const Vec3 exit = s.point - s.normal * t;
    const SurfacePoint e = project(exit);
    if (e.face < 0 || e.face_normal.dot(s.normal) > cos_opposed) continue;
    if (!exposed(s, o_.clearance * diag_)) continue;
    if (ref_.first_hit(exit - s.normal * eps, exit - s.normal * (o_.clearance * diag_)).face >= 0) continue;
    // Not a sliver or a rim: on the sides, 1.5 thicknesses (at least 0.02 of the diagonal) away,
    // the part is about as thin and faces about the same way; a frictionless proxy pushed near a
    // rim slides round it.
    const Vec3 u = any_perpendicular(s.normal), w = s.normal.cross(u);
    const double r = std::max(1.5 * t, 0.02 * diag_);
    int agree = 0;
    for (int k = 0; k < 8; ++k) {
      const double a = std::numbers::pi * k / 4;
      const SurfacePoint q = project(s.point + r * (std::cos(a) * u + std::sin(a) * w));
      const double tn = thickness(q);
      agree += tn >= 0.5 * t && tn <= 3 * t && q.normal.dot(s.normal) > cos_flat;
    }
    // Both faces: the scenario pushes the sheet from each side.
    if (agree < 6 || !represented(model, locator, s.point, s.normal, t) ||
        !represented(model, locator, e.point, e.normal, t))
      continue;
    cands.push_back({{s, exit, t}, agree});
  }
  // The thinnest of the flattest: all eight sides agreeing if any sample has that, else seven, else six.
  for (int need = 8; need >= 6; --need) {
    const Cand* best = nullptr;
    for (const Cand& c : cands)
      if (c.agree >= need && (!best || c.site.thickness < best->site.thickness)) best = &c;
    if (best) return best->site;
  }
  throw InvalidInput("thin: the input has no thin part reachable from outside that the slab model resolves");
}

SurfaceStroke ScenarioSites::edges_spiral(const SlabModel& model, const SlabLocator& locator) const {
  const int nc = model.coarse_vertex_count();
  // The surface point of each coarse corner: where its projection line meets the input.
  auto corner = [&](int v) {
    const SegmentHit h = ref_.first_hit(model.outer[v], model.inner[v]);
    return project(h.face >= 0 ? Vec3(model.outer[v] + h.t * (model.inner[v] - model.outer[v]))
                               : Vec3(0.5 * (model.outer[v] + model.inner[v])));
  };
  std::vector<SurfacePoint> corners(nc);
  for (int v = 0; v < nc; ++v) corners[v] = corner(v);
  SurfaceStroke best;
  double best_score = std::numeric_limits<double>::infinity();
  const int per_turn = 96;
  for (int v = 0; v < nc; ++v) {
    const SurfacePoint& c = corners[v];
    if (c.face < 0 || !exposed(c, o_.clearance * diag_)) continue;
    double spacing = 0;
    int count = 0;
    model.samples.for_each_vertex_slab(v, [&](int32_t slab) {
      for (int32_t u : model.slabs[slab])
        if (u != v) spacing += (corners[u].point - c.point).norm(), ++count;
    });
    if (count == 0) continue;
    spacing /= count;
    const Vec3 u = any_perpendicular(c.normal), w = c.normal.cross(u);
    SurfaceStroke st;
    for (int i = 0; i <= 2 * per_turn; ++i) {
      const double a = 2 * std::numbers::pi * i / per_turn, rho = spacing * (0.35 + 0.75 * i / (2.0 * per_turn));
      st.points.push_back(project(c.point + rho * (std::cos(a) * u + std::sin(a) * w)));
    }
    score(st);
    const double sc = st.roughness_deg + 2 * st.bend_deg;
    if (sc >= best_score || !stroke_ok(st)) continue;
    SlabCoordinates sc_coords;
    int last = -1;
    st.slab_crossings = 0;
    for (const SurfacePoint& p : st.points) {
      const int slab = locator.find(p.point, last, AlphaSolver::Newton, sc_coords);
      if (slab >= 0 && last >= 0 && slab != last) ++st.slab_crossings;
      if (slab >= 0) last = slab;
    }
    if (st.slab_crossings < 6) continue;                           // a corner whose fan the spiral misses
    if (!stroke_represented(model, locator, st, diag_)) continue;  // the bake misses the relief there
    best_score = sc;
    best = std::move(st);
  }
  if (best.points.empty()) throw InvalidInput("edges: no slab corner with a smooth, exposed neighbourhood");
  return best;
}

}  // namespace hdm
