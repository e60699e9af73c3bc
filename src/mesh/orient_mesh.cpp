// SPDX-License-Identifier: MIT
#include <hdm/mesh/orient_mesh.h>

#include "nearly_closed.h"
#include "disjoint_sets.h"
#include "edge_buckets.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <numeric>
#include <unordered_map>
#include <vector>

namespace hdm {
namespace {

struct Part {
  std::vector<int32_t> faces;
  Aabb box;
  std::vector<std::array<Vec3, 3>> caps;  // fan triangles closing the boundary loops
  double area = 0, cap_area = 0, volume = 0;
  bool closed = true;
};

// Ray (fixed skew direction) parity of p against the triangles of a part and its caps
// (Möller & Trumbore 1997).
bool inside_part(const TriangleMesh& m, const Part& part, const Vec3& p) {
  const Vec3 d = Vec3(0.5773, 0.5774, 0.5775).normalized();
  auto crosses = [&](const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 e1 = b - a, e2 = c - a, h = d.cross(e2);
    const double det = e1.dot(h);
    if (std::abs(det) < 1e-300) return false;
    const Vec3 s = p - a;
    const double u = s.dot(h) / det;
    if (u < 0 || u > 1) return false;
    const Vec3 q = s.cross(e1);
    const double v = d.dot(q) / det;
    if (v < 0 || u + v > 1) return false;
    return e2.dot(q) / det > 0;
  };
  bool in = false;
  for (int32_t f : part.faces) {
    const Tri& t = m.faces[f];
    in ^= crosses(m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]);
  }
  for (const auto& c : part.caps) in ^= crosses(c[0], c[1], c[2]);
  return in;
}

// Per half-edge 3f + k (face f's vertex k to vertex k + 1): `twin` is the face across it (the
// first face, by number, that traverses its edge the other way; -1: none, a boundary or a
// misoriented neighbour), `first` the first face that traverses it the same way (itself, unless the
// edge is used twice in one direction). From the half-edges grouped by edge (EdgeBuckets), each
// vertex's group sorted and scanned in parallel.
struct HalfEdges {
  std::vector<int32_t> twin, first;

  explicit HalfEdges(const TriangleMesh& mesh) : twin(3 * mesh.faces.size(), -1), first(3 * mesh.faces.size()) {
    using mesh::detail::EdgeBuckets;
    EdgeBuckets edges(mesh, true);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, mesh.vertices.size(), 4096), [&](const auto& range) {
      for (size_t lo = range.begin(); lo < range.end(); ++lo) {
        edges.sort(lo);
        for (uint64_t i = edges.start[lo], end = edges.start[lo + 1]; i < end;) {
          const int32_t hi = EdgeBuckets::hi(edges.uses[i]);
          uint64_t j = i;
          int32_t by_dir[2] = {-1, -1};  // the first face of each direction
          for (; j < end && EdgeBuckets::hi(edges.uses[j]) == hi; ++j) {
            int32_t& f = by_dir[EdgeBuckets::forward(edges.uses[j])];
            if (f < 0) f = int32_t(EdgeBuckets::half(edges.uses[j]) / 3);
          }
          // (a→a) of a face with a repeated vertex is its own reverse.
          const bool loop = hi == int32_t(lo);
          for (uint64_t k = i; k < j; ++k) {
            const int d = EdgeBuckets::forward(edges.uses[k]);
            const uint32_t h = EdgeBuckets::half(edges.uses[k]);
            twin[h] = by_dir[loop ? d : 1 - d];
            first[h] = by_dir[d];
          }
          i = j;
        }
      }
    });
  }
};

// A half-edge without a twin: (a→b) of a face, and the first face with (a→b) (HalfEdges::first).
struct BoundaryEdge {
  int32_t first, second, face;
};

std::vector<Part> mesh_parts(const TriangleMesh& mesh, const HalfEdges& he, std::vector<int32_t>& part_of_face,
                             std::vector<BoundaryEdge>& boundary) {
  const size_t nf = mesh.faces.size();
  mesh::detail::DisjointSets<> sets(nf);
  for (size_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const int32_t a = mesh.faces[f][k], b = mesh.faces[f][(k + 1) % 3];
      const int32_t g = he.twin[3 * f + k];
      if (g >= 0)
        sets.unite(int32_t(f), g);
      else
        boundary.push_back({a, b, he.first[3 * f + k]});
    }
  std::vector<Part> parts;
  part_of_face.assign(nf, -1);  // first the part of each root face, then of every face
  for (size_t f = 0; f < nf; ++f) {
    int32_t& part = part_of_face[sets.find(int32_t(f))];
    if (part < 0) part = int32_t(parts.size()), parts.emplace_back();
    part_of_face[f] = part;
    Part& p = parts[part];
    p.faces.push_back(int32_t(f));
    for (int32_t v : mesh.faces[f]) p.box.extend(mesh.vertices[v]);
    const Vec3 &a = mesh.vertices[mesh.faces[f][0]], &b = mesh.vertices[mesh.faces[f][1]],
               &c = mesh.vertices[mesh.faces[f][2]];
    p.area += 0.5 * (b - a).cross(c - a).norm();
    p.volume += a.dot(b.cross(c)) / 6;
  }
  return parts;
}

// Boundary loops: follow (a→b) to the boundary half-edge leaving b; cap each with a fan around
// the loop's centroid, counted in its part's cap area and volume, and mark the part open.
void cap_boundary_loops(const TriangleMesh& mesh, const std::vector<BoundaryEdge>& boundary,
                        const std::vector<int32_t>& part_of_face, std::vector<Part>& parts) {
  std::unordered_multimap<int32_t, size_t> leaving;
  for (size_t k = 0; k < boundary.size(); ++k) leaving.emplace(boundary[k].first, k);
  std::vector<uint8_t> used(boundary.size(), 0);
  std::vector<size_t> loop;
  for (size_t start = 0; start < boundary.size(); ++start) {
    if (used[start]) continue;
    loop.clear();
    for (size_t k = start; !used[k];) {
      used[k] = 1;
      loop.push_back(k);
      auto range = leaving.equal_range(boundary[k].second);
      size_t next = k;
      for (auto it = range.first; it != range.second; ++it)
        if (!used[it->second]) next = it->second;
      if (next == k) break;
      k = next;
    }
    Vec3 c = Vec3::Zero();
    for (size_t k : loop) c += mesh.vertices[boundary[k].first];
    c /= double(loop.size());
    // The part of the loop's first edge (a→b): its face is the one with (a→b).
    Part& part = parts[part_of_face[boundary[loop[0]].face]];
    part.closed = false;
    for (size_t k : loop) {
      const Vec3 &a = mesh.vertices[boundary[k].first], &b = mesh.vertices[boundary[k].second];
      part.caps.push_back({b, a, c});  // (b→a) closes the face's (a→b)
      part.cap_area += mesh::detail::cap_triangle_area(a, b, c);
      part.volume += b.dot(a.cross(c)) / 6;
    }
  }
}

// Solid parts (closed or nearly closed) face out at even nesting depth, in at odd depth. A part
// is nested in another only when that one's box holds its whole box (parts that merely
// interpenetrate, such as the bones of a foot, are not cavities of each other).
void flip_inward_solids(TriangleMesh& mesh, std::vector<Part>& parts, OrientReport& rep) {
  std::vector<int32_t> solid;
  for (size_t i = 0; i < parts.size(); ++i) {
    Part& p = parts[i];
    ++rep.components;
    if (p.closed)
      ++rep.closed, solid.push_back(int32_t(i));
    else if (mesh::detail::nearly_closed(p.cap_area, p.area))
      ++rep.nearly_closed, solid.push_back(int32_t(i));
    else
      ++rep.sheets;
  }
  for (int32_t i : solid) {
    const Part& p = parts[i];
    int depth = 0;
    const Vec3& probe = mesh.vertices[mesh.faces[p.faces[0]][0]];
    for (int32_t j : solid)
      if (j != i && parts[j].box.contains(p.box.min) && parts[j].box.contains(p.box.max))
        depth += inside_part(mesh, parts[j], probe);
    const bool outward = (p.volume > 0) == (depth % 2 == 0);
    if (outward) continue;
    ++rep.flipped;
    rep.flipped_faces += static_cast<int64_t>(p.faces.size());
    for (int32_t f : p.faces) std::swap(mesh.faces[f][1], mesh.faces[f][2]);
  }
}

}  // namespace

OrientReport orient_outward(TriangleMesh& mesh) {
  OrientReport rep;
  if (mesh.faces.empty()) return rep;
  const HalfEdges he(mesh);
  std::vector<int32_t> part_of_face;
  std::vector<BoundaryEdge> boundary;
  std::vector<Part> parts = mesh_parts(mesh, he, part_of_face, boundary);
  if (!boundary.empty()) cap_boundary_loops(mesh, boundary, part_of_face, parts);
  flip_inward_solids(mesh, parts, rep);
  return rep;
}

}  // namespace hdm
