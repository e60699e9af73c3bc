// SPDX-License-Identifier: MIT
#pragma once
// Internal to decimate_mesh(): the mesh being decimated, its quadrics and the cone margin of vertex
// stars. One class, its methods in three files by purpose: simplifier.cpp (set-up, the collapse
// queue, the result), simplifier_collapse.cpp (one checked collapse), simplifier_folds.cpp (stars
// no direction sees, merged or removed after the queue).

#include <hdm/mesh/decimate_mesh.h>

#include <cmath>
#include <queue>
#include <vector>

namespace hdm::mesh::detail {

// Symmetric 4×4 quadric of weighted squared plane distances, Q(x) = xᵀAx + 2b·x + c, stored as
// the 10 distinct entries (Garland & Heckbert 1997).
struct Quadric {
  double a00 = 0, a01 = 0, a02 = 0, a11 = 0, a12 = 0, a22 = 0, b0 = 0, b1 = 0, b2 = 0, c = 0;

  // Plane n·x + d = 0 (unit n) with weight w.
  void add_plane(const Vec3& n, double d, double w) {
    a00 += w * n.x() * n.x(), a01 += w * n.x() * n.y(), a02 += w * n.x() * n.z();
    a11 += w * n.y() * n.y(), a12 += w * n.y() * n.z(), a22 += w * n.z() * n.z();
    b0 += w * d * n.x(), b1 += w * d * n.y(), b2 += w * d * n.z(), c += w * d * d;
  }
  Quadric operator+(const Quadric& o) const {
    return {a00 + o.a00, a01 + o.a01, a02 + o.a02, a11 + o.a11, a12 + o.a12,
            a22 + o.a22, b0 + o.b0,   b1 + o.b1,   b2 + o.b2,   c + o.c};
  }
  double operator()(const Vec3& x) const {
    const double ax = a00 * x.x() + a01 * x.y() + a02 * x.z(), ay = a01 * x.x() + a11 * x.y() + a12 * x.z(),
                 az = a02 * x.x() + a12 * x.y() + a22 * x.z();
    return std::max(0.0, x.x() * ax + x.y() * ay + x.z() * az + 2 * (b0 * x.x() + b1 * x.y() + b2 * x.z()) + c);
  }
  // The minimiser, pulled towards @p m in the directions the quadric hardly constrains (a flat or
  // straight region): minimises Q(x) + ε|x − m|² with ε a thousandth of A's mean eigenvalue, so
  // the point never runs off along the plane or the crease (after Lindstrom 2000).
  Vec3 minimiser(const Vec3& m) const {
    const double eps = 1e-3 * (a00 + a11 + a22) / 3 + 1e-300;
    // Cholesky of A + εI (symmetric positive definite), then solve for the step from m.
    const double l00 = std::sqrt(a00 + eps);
    const double l10 = a01 / l00, l20 = a02 / l00;
    const double d11 = a11 + eps - l10 * l10;
    if (!(d11 > 0)) return m;
    const double l11 = std::sqrt(d11), l21 = (a12 - l20 * l10) / l11;
    const double d22 = a22 + eps - l20 * l20 - l21 * l21;
    if (!(d22 > 0)) return m;
    const double l22 = std::sqrt(d22);
    // r = −b − A·m: the gradient direction at m.
    const double r0 = -b0 - (a00 * m.x() + a01 * m.y() + a02 * m.z());
    const double r1 = -b1 - (a01 * m.x() + a11 * m.y() + a12 * m.z());
    const double r2 = -b2 - (a02 * m.x() + a12 * m.y() + a22 * m.z());
    const double y0 = r0 / l00, y1 = (r1 - l10 * y0) / l11, y2 = (r2 - l20 * y0 - l21 * y1) / l22;
    const double x2 = y2 / l22, x1 = (y1 - l21 * x2) / l11, x0 = (y0 - l10 * x1 - l20 * x2) / l00;
    return m + Vec3(x0, x1, x2);
  }
};

// Sine of the smallest angle of triangle (a, b, c): the angle opposite the shortest edge, whose
// sine is twice the area over the product of the two longer edges (no trigonometry).
double smallest_angle_sine(const Vec3& a, const Vec3& b, const Vec3& c);

// The smallest dot product of @p normals with the best direction found by a few steps from their
// mean towards the worst-seen normal: a lower bound of the max-min cone axis's value, so a refusal
// on it is conservative. -1 when the normals cancel.
double cone_margin(const std::vector<Vec3>& normals);

// cone_margin(), made exact where it is below 0.5 (improve_max_min()). Whether a vertex's dual cone is empty is decided
// on this: the quick estimate took barely seen stars of a resolved union for empty-cone ones, and the reopening
// collapses then emptied the cones of good stars (bones.off: a star seen at 0.03 merged into one seen at -0.09). The
// acceptance of ordinary collapses stays on the quick, conservative estimate (more collapses near barely seen stars
// cost fidelity: ChineseDragon-10kv.off needed one more round).
double exact_cone_margin(const std::vector<Vec3>& normals);

// Whether exact_cone_margin(@p after) > @p enough or >= exact_cone_margin(@p before). A star no
// direction sees (its normals' hull holds the origin) has the smaller margin when the other is
// seen, so its candidate search, the costly one, runs only when neither is. @p enough >= 0.
bool cone_margin_kept(const std::vector<Vec3>& after, const std::vector<Vec3>& before, double enough);

// The mesh being decimated. Each vertex has a singly linked list of its face corners (corner
// 3f+k is vertex k of face f); a collapse of b into a relabels b's corners and splices b's list
// into a's; dead faces' corners stay in the lists and are skipped (and dropped) when walked.
class Simplifier {
 public:
  Simplifier(const TriangleMesh& mesh, const DecimateOptions& o);

  // Collapses the cheapest edges until at most @p target faces remain or the cheapest costs more
  // than @p max_cost, after collapse_negligible_edges().
  void run(int64_t target, double max_cost);

  // Collapses, with the usual checks, every edge no longer than negligible_move_, whatever its
  // quadric cost: such an edge is below any slab's resolution, and the cost order would leave it
  // to the last (a plate's flat collapses cost nothing), so that a coarse mesh kept it with the
  // two slivers beside it.
  void collapse_negligible_edges();

  // Removes vertices whose faces no direction sees (a fold of the input, or one the target left):
  // such a vertex has no valid slab direction at any thickness. Each is merged into a neighbour,
  // beyond the target, by the collapse that most improves its star and keeps the others seen.
  void clean_folds();

  // Merges the crumple around empty-cone vertex v into v: the vertices within distance r of v that
  // edges connect to it through such vertices (r = 1/4, 1/2, 1 of v's mean edge length), by
  // collapses that check only the link condition. Kept when the stars around end up with fewer
  // empty-cone ones and none newly empty; undone otherwise. Why: at a crumpled tip (diplodocus.off's
  // tail) every single collapse or removal leaves the merged star's cone as empty as before, while the
  // crumple as a whole is a few tiny faces whose removal leaves a cone seen from its axis.
  bool collapse_cluster(int32_t v);

  // What the merges of collapse_cluster() may change, to undo them: they walk and change only the
  // stars of the cluster's and the region's vertices (the heap is not used after run()).
  struct Journal {
    std::vector<int32_t> vertices, faces;
    std::vector<Vec3> pos;
    std::vector<Quadric> quadric;
    std::vector<int32_t> head, next;
    std::vector<uint32_t> version;
    std::vector<double> cone_angle;
    std::vector<uint8_t> alive, empty_cone, retry, alive_face;
    std::vector<Tri> face;
    int64_t faces_left = 0, collapses = 0;
  };
  Journal journal(const std::vector<int32_t>& region);
  void restore(const Journal& j);

  // Removes interior vertex v and fills its ring with the fan from one ring vertex (the one whose
  // fan leaves every ring vertex best seen), when that opens the cones of v's neighbourhood: a crumple that
  // no single edge collapse resolves (its ring twists, so every merged star's cone is empty too).
  bool remove_vertex(int32_t v);

  // The live faces, with every vertex they use; @p kept (optional) gets, per vertex of the result,
  // its index in the mesh the simplifier was made from.
  TriangleMesh result(std::vector<int32_t>* kept = nullptr) const;

  // The longest edge a collapse may make at vertex v: the least DecimateOptions::max_edge of the
  // input vertices merged into it (+inf without max_edge).
  double max_edge(int32_t v) const { return max_edge_.empty() ? INFINITY : max_edge_[v]; }

  // Vertices no collapse may remove, move or give a new edge (1 per vertex; empty: none): where a
  // part of a mesh decimated on its own meets the others (decimate_in_parts()).
  void freeze(std::vector<uint8_t> frozen) { frozen_ = std::move(frozen); }

  int64_t feature_edges() const { return features_; }
  int64_t collapses() const { return collapses_; }
  double last_cost() const { return last_cost_; }

 private:
  struct Candidate {
    float cost;
    int32_t a, b;
    uint32_t va, vb;
    bool operator<(const Candidate& o) const { return cost > o.cost; }  // min-heap
  };

  // Live faces around v (drops dead corners from v's list on the way).
  template <class F>
  void for_faces(int32_t v, F&& f) {
    int32_t* link = &head_[v];
    while (*link >= 0) {
      const int32_t c = *link;
      if (!alive_face_[c / 3]) {
        *link = next_[c];
        continue;
      }
      f(c / 3, c % 3);
      link = &next_[c];
    }
  }

  Vec3 face_normal(int32_t f) const;

  void init_quadrics();

  // Pushes the edges of v (to every neighbour except @p skip; with @p once only to neighbours of
  // a larger id, so that a sweep over all vertices pushes each edge once), with their cost.
  void push_edges(int32_t v, int32_t skip, bool once);

  // Where the merged vertex of edge (a, b) goes: the end of least quadric error (a half-edge
  // collapse: coarse vertices stay input vertices, on the surface, so a slab's corner rays pass
  // through the input), or the quadric's minimiser (DecimateOptions::on_input false).
  Vec3 place(const Quadric& q, int32_t a, int32_t b) const;

  // Sorted distinct neighbours of v, and whether v lies on a boundary (a neighbour met once).
  bool ring(int32_t v, std::vector<int32_t>& out);

  // Collapses edge (a, b) into a at the quadric's minimiser if the link condition and the
  // geometric checks allow it. Returns whether it did.
  bool collapse(int32_t a, int32_t b, bool reopen = false);

  // Whether collapsing edge (a, b) keeps the topology (the link condition) and leaves frozen
  // vertices and their edges as they are; fills ra_, rb_ and shared_ for the geometric checks.
  bool link_condition(int32_t a, int32_t b);

  // Whether collapsing b into a at x leaves no edge (x, w) longer than the max_edge_ of a, b and w.
  bool short_edges(int32_t a, int32_t b, const Vec3& x) const;

  // Collapses b into a at x (the checks passed): kills the faces on edge ab, relabels b's corners,
  // splices b's list into a's. @p seen is the new star's cone margin (-2: unknown), @p max_turn the
  // largest turn of a link face [rad].
  void merge(int32_t a, int32_t b, const Vec3& x, const Quadric& q, double seen, double max_turn);

  // Cone margin of v's star as it is (exact_cone_margin()).
  double vertex_cone_margin(int32_t v);

  // Whether link vertex w's faces stay visible (DecimateOptions::min_cone_margin) with a and b
  // moved to x, or at least no worse seen than before. cone_angle_[w] bounds the angle at which some
  // direction sees all of w's faces; no face turns by more than @p max_turn, so that direction
  // sees the new star within cone_angle_[w] + max_turn: most stars pass on that bound without a recount.
  bool link_visible(int32_t w, int32_t a, int32_t b, const Vec3& x, double max_turn);

  DecimateOptions o_;
  bool forced_ = false;  // collapse() checks only the link condition (collapse_cluster())
  std::vector<Vec3> pos_;
  std::vector<Tri> faces_;
  std::vector<int32_t> head_, next_;
  std::vector<uint8_t> alive_face_, alive_, retry_, frozen_;
  std::vector<uint32_t> version_;
  std::vector<Quadric> quadric_;
  std::vector<double>
      cone_angle_;        // per vertex, an upper bound of the angle at which one direction sees its faces [rad]
  double max_angle_ = 0;  // acos(min_cone_margin)
  std::priority_queue<Candidate> heap_;
  std::vector<int32_t> nbr_, ra_, rb_, shared_, fold_ring_, reopened_;
  std::vector<uint8_t> empty_cone_;           // stars no direction sees (cone margin <= kEmptyCone)
  static constexpr double kEmptyCone = 0.02;  // a star seen at no better dot than this has an empty dual cone
  std::vector<Vec3> before_, after_;
  int64_t faces_left_ = 0, features_ = 0, collapses_ = 0;
  double last_cost_ = 0;
  std::vector<double> max_edge_;  // per vertex, DecimateOptions::max_edge (empty: no limit)
  double cos_turn_ = 0, sin_min_angle_ = 0;
  // A vertex moved by at most this is not held to the sliver test (kNegligibleMove of the mesh's
  // bounding-box diagonal) [model units].
  double negligible_move_ = 0;
};

}  // namespace hdm::mesh::detail
