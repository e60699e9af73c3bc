// SPDX-License-Identifier: MIT
// Exact refinement of crossing faces (see refine_crossings.h); its own translation unit, as the
// exact kernel and the constrained triangulation are heavy templates.
#include "refine_crossings.h"
#include "disjoint_sets.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/intersections.h>

#include <array>
#include <utility>
#include <algorithm>
#include <cstring>
#include <unordered_map>

namespace hdm::mesh::detail {
namespace {

using EK = CGAL::Exact_predicates_exact_constructions_kernel;
using FT = EK::FT;
using P3 = EK::Point_3;
using P2 = EK::Point_2;
using Vb = CGAL::Triangulation_vertex_base_2<EK>;
using Fb = CGAL::Constrained_triangulation_face_base_2<EK>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using CDT = CGAL::Constrained_Delaunay_triangulation_2<EK, Tds, CGAL::Exact_intersections_tag>;

// A rounded position as a hash key: equal exact points round to equal doubles (the rounding of
// the exact value, never of an interval), so a point reached from two faces is one key.
struct Key {
  double x, y, z;
  bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct KeyHash {
  size_t operator()(const Key& k) const {
    uint64_t h[3];
    std::memcpy(h, &k, sizeof h);
    return size_t(h[0] * 0x9E3779B97F4A7C15ull ^ h[1] * 0xC2B2AE3D27D4EB4Full ^ h[2] * 0x165667B19E3779F9ull);
  }
};

double rounded(const FT& x) { return CGAL::to_double(CGAL::exact(x)); }

// One face projected on the plane of its two largest normal coordinates and lifted back exactly.
struct FacePlane {
  int drop = 2;          // the coordinate left out
  bool flipped = false;  // whether the projection reverses the face's orientation
  EK::Plane_3 plane;

  explicit FacePlane(const EK::Triangle_3& t) : plane(t.supporting_plane()) {
    const EK::Vector_3 n = plane.orthogonal_vector();
    const FT ax = CGAL::abs(n.x()), ay = CGAL::abs(n.y()), az = CGAL::abs(n.z());
    drop = (ax >= ay && ax >= az) ? 0 : (ay >= az ? 1 : 2);
    // Dropping x keeps (y, z), y keeps (z, x), z keeps (x, y): each a right-handed pair, so the
    // orientation is kept where the dropped normal coordinate is positive.
    flipped = CGAL::is_negative(n[drop]);
  }
  P2 project(const P3& p) const {
    if (drop == 0) return P2(p.y(), p.z());
    if (drop == 1) return P2(p.z(), p.x());
    return P2(p.x(), p.y());
  }
  P3 lift(const P2& q) const {  // the point of the plane over q: a x + b y + c z + d = 0
    const FT a = plane.a(), b = plane.b(), c = plane.c(), d = plane.d();
    if (drop == 0) return P3(-(b * q.x() + c * q.y() + d) / a, q.x(), q.y());
    if (drop == 1) return P3(q.y(), -(a * q.y() + c * q.x() + d) / b, q.x());
    return P3(q.x(), q.y(), -(a * q.x() + b * q.y() + d) / c);
  }
};

using Hit = decltype(CGAL::intersection(std::declval<EK::Triangle_3>(), std::declval<EK::Triangle_3>()));

// Adds @p hit, what a face shares with another (exact), to @p cdt as constraints in its plane.
void constrain(CDT& cdt, const FacePlane& plane, const Hit& hit) {
  if (!hit) return;
  if (const P3* p = boost::get<P3>(&*hit)) {
    cdt.insert(plane.project(*p));
  } else if (const EK::Segment_3* s = boost::get<EK::Segment_3>(&*hit)) {
    cdt.insert_constraint(plane.project(s->source()), plane.project(s->target()));
  } else if (const EK::Triangle_3* c = boost::get<EK::Triangle_3>(&*hit)) {
    for (int i = 0; i < 3; ++i) cdt.insert_constraint(plane.project(c->vertex(i)), plane.project(c->vertex(i + 1)));
  } else if (const auto* poly = boost::get<std::vector<P3>>(&*hit)) {
    for (size_t i = 0; i < poly->size(); ++i)
      cdt.insert_constraint(plane.project((*poly)[i]), plane.project((*poly)[(i + 1) % poly->size()]));
  }
}

}  // namespace

TriangleMesh refine_crossings(const TriangleMesh& mesh, const std::vector<std::pair<int, int>>& pairs,
                              RefineReport* report) {
  RefineReport rep;
  rep.pairs = static_cast<int64_t>(pairs.size());
  const size_t nf = mesh.faces.size();
  std::vector<std::vector<size_t>> partners(nf);  // ids into pairs
  for (size_t k = 0; k < pairs.size(); ++k) {
    const auto [a, b] = pairs[k];
    if (a < 0 || b < 0 || size_t(a) >= nf || size_t(b) >= nf || a == b) continue;
    partners[size_t(a)].push_back(k);
    partners[size_t(b)].push_back(k);
  }
  std::vector<Hit> hits(pairs.size());  // each pair's intersection, computed by its first face
  std::vector<uint8_t> done(pairs.size(), 0);
  TriangleMesh out;
  out.vertices = mesh.vertices;
  std::unordered_map<Key, int, KeyHash> ids;
  ids.reserve(mesh.vertices.size() * 2);
  for (size_t v = 0; v < mesh.vertices.size(); ++v) {
    const Vec3& p = mesh.vertices[v];
    ids.emplace(Key{p.x(), p.y(), p.z()}, int(v));  // the first of equal positions is the one
  }
  auto id_of = [&](double x, double y, double z) {
    const auto [it, added] = ids.emplace(Key{x, y, z}, int(out.vertices.size()));
    if (added) out.vertices.emplace_back(x, y, z);
    return it->second;
  };
  auto exact = [&](int f) {
    const Tri& t = mesh.faces[size_t(f)];
    auto p = [&](int v) { return P3(mesh.vertices[size_t(v)].x(), mesh.vertices[size_t(v)].y(), mesh.vertices[size_t(v)].z()); };
    return EK::Triangle_3(p(t[0]), p(t[1]), p(t[2]));
  };
  for (size_t f = 0; f < nf; ++f) {
    const Tri& tri = mesh.faces[f];
    const Vec3& a = mesh.vertices[size_t(tri[0])];
    if (partners[f].empty()) {
      const Vec3 n = (mesh.vertices[size_t(tri[1])] - a).cross(mesh.vertices[size_t(tri[2])] - a);
      if (n.squaredNorm() > 0) out.faces.push_back(tri);
      continue;
    }
    const EK::Triangle_3 t = exact(int(f));
    if (t.is_degenerate()) continue;
    const FacePlane plane(t);
    CDT cdt;
    for (int i = 0; i < 3; ++i) cdt.insert(plane.project(t.vertex(i)));
    for (size_t k : partners[f]) {
      if (!done[k]) {
        const int g = pairs[k].first == int(f) ? pairs[k].second : pairs[k].first;
        const EK::Triangle_3 u = exact(g);
        if (!u.is_degenerate()) hits[k] = CGAL::intersection(t, u);
        done[k] = 1;
        constrain(cdt, plane, hits[k]);
      } else {
        constrain(cdt, plane, hits[k]);
        hits[k] = Hit();  // both faces have it
      }
    }
    if (cdt.number_of_faces() > 1) ++rep.faces_split;
    std::unordered_map<CDT::Vertex_handle, int> vid;
    for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v) {
      const P3 q = plane.lift(v->point());
      vid[v] = id_of(rounded(q.x()), rounded(q.y()), rounded(q.z()));
    }
    for (auto c = cdt.finite_faces_begin(); c != cdt.finite_faces_end(); ++c) {
      Tri piece{vid[c->vertex(0)], vid[c->vertex(1)], vid[c->vertex(2)]};
      if (plane.flipped) std::swap(piece[1], piece[2]);
      if (piece[0] != piece[1] && piece[1] != piece[2] && piece[0] != piece[2]) out.faces.push_back(piece);
    }
  }
  rep.faces_after = static_cast<int64_t>(out.faces.size());
  if (report) *report = rep;
  return out;
}

std::vector<int32_t> patches_between_crossings(const TriangleMesh& mesh, int32_t& count) {
  // One record per directed edge use: (lo, hi) in the high bits, the face below, the direction in
  // the lowest bit, so one sort groups the uses of each edge.
  struct Use {
    uint64_t edge;
    int32_t face;
    bool forward;
  };
  std::vector<Use> uses;
  uses.reserve(mesh.faces.size() * 3);
  for (size_t f = 0; f < mesh.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int32_t a = mesh.faces[f][k], b = mesh.faces[f][(k + 1) % 3];
      const auto [lo, hi] = std::minmax(a, b);
      uses.push_back({(uint64_t(uint32_t(lo)) << 32) | uint32_t(hi), int32_t(f), a < b});
    }
  std::sort(uses.begin(), uses.end(), [](const Use& x, const Use& y) { return x.edge < y.edge; });
  DisjointSets<> sets(mesh.faces.size());
  for (size_t i = 0; i < uses.size();) {
    size_t j = i;
    while (j < uses.size() && uses[j].edge == uses[i].edge) ++j;
    if (j - i == 2 && uses[i].forward != uses[i + 1].forward) sets.unite(uses[i].face, uses[i + 1].face);
    i = j;
  }
  std::vector<int32_t> patch(mesh.faces.size(), -1), id_of_root(mesh.faces.size(), -1);
  count = 0;
  for (size_t f = 0; f < mesh.faces.size(); ++f) {
    const int32_t r = sets.find(int32_t(f));
    if (id_of_root[size_t(r)] < 0) id_of_root[size_t(r)] = count++;
    patch[f] = id_of_root[size_t(r)];
  }
  return patch;
}

}  // namespace hdm::mesh::detail
