// SPDX-License-Identifier: MIT
// Global sample ids: counts by Euler's formula, shared edge and corner samples, orientation.
#include "support/test_models.h"

#include <hdm/core/error.h>
#include <hdm/slab/sample_layout.h>
#include <hdm/slab/triangle_grid.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>
#include <numbers>
#include <set>

using namespace hdm;

namespace {

SlabModel sphere_shell(int n, int texel_density) {
  const TriangleMesh m = test::icosphere(1, 1.0);
  SlabModel s;
  s.grid_n = n;
  s.texel_density = texel_density;
  for (const Vec3& v : m.vertices) s.inner.push_back(0.8 * v), s.outer.push_back(1.2 * v);
  s.slabs = m.faces;
  s.displacement.assign(build_sample_layout(s.slabs, int(s.inner.size()), n).count, 0.5f);
  rebuild_derived(s);
  return s;
}

// The id of every slot (slab-major, grid index order), read through SampleLayout::id().
std::vector<int32_t> slot_ids(const SampleLayout& L) {
  std::vector<int32_t> ids(L.slot_count());
  for (int32_t k = 0; k < L.slab_count; ++k)
    for (int32_t p = 0; p < L.per_slab; ++p) ids[size_t(k) * L.per_slab + p] = L.id(k, p);
  return ids;
}

// The documented numbering, by brute force: corners are coarse vertex ids; the undirected edges
// are numbered in order of first use (slab order, edges RS, ST, TR), each with n-1 ids from its
// smaller vertex to its larger; then each slab's interior points in grid::index order.
std::vector<int32_t> documented_ids(const std::vector<Tri>& slabs, int C, int n) {
  std::map<std::pair<int32_t, int32_t>, int32_t> edge;
  for (const Tri& t : slabs)
    for (int k = 0; k < 3; ++k) edge.emplace(std::minmax(t[k], t[(k + 1) % 3]), int32_t(edge.size()));
  auto on_edge = [&](int32_t a, int32_t b, int step) {  // step-th point from a towards b
    const int32_t e = edge.at(std::minmax(a, b));
    return C + e * (n - 1) + (a < b ? step : n - step) - 1;
  };
  const int32_t interior_base = C + int32_t(edge.size()) * (n - 1);
  std::vector<int32_t> ids(slabs.size() * grid::point_count(n));
  int32_t next = interior_base;
  for (size_t k = 0; k < slabs.size(); ++k) {
    const int32_t R = slabs[k][0], S = slabs[k][1], T = slabs[k][2];
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i + j <= n; ++i) {
        int32_t id;
        if (i == 0 && j == 0)
          id = R;
        else if (i == n)
          id = T;
        else if (j == n)
          id = S;
        else if (j == 0)
          id = on_edge(R, T, i);
        else if (i == 0)
          id = on_edge(R, S, j);
        else if (i + j == n)
          id = on_edge(S, T, i);
        else
          id = next++;
        ids[k * grid::point_count(n) + grid::index(n, i, j)] = id;
      }
  }
  return ids;
}

}  // namespace

TEST(SampleLayoutTest, IdsFollowTheDocumentedNumbering) {
  // Interior ids are computed and boundary ids stored (SlabIds): both must give the numbering the
  // header documents, built here from it by brute force, on a closed mesh and an open one, for the
  // grid sizes of samples and texels.
  const TriangleMesh closed = test::icosphere(1, 1.0);
  std::vector<Tri> open(closed.faces.begin(), closed.faces.begin() + 30);
  std::map<int32_t, int32_t> used;  // the open part's vertices, renumbered in order of first use
  for (Tri& t : open)
    for (int32_t& v : t) v = used.emplace(v, int32_t(used.size())).first->second;
  for (const std::vector<Tri>* slabs : {&closed.faces, static_cast<const std::vector<Tri>*>(&open)})
    for (int n : {1, 2, 3, 5, 16, 32}) {
      const int C = slabs == &open ? int(used.size()) : int(closed.vertices.size());
      const SampleLayout L = build_sample_layout(*slabs, C, n);
      ASSERT_EQ(slot_ids(L), documented_ids(*slabs, C, n)) << "n = " << n << ", " << slabs->size() << " slabs";
    }
}

TEST(SampleLayoutTest, CountsFollowEulerFormula) {
  const TriangleMesh m = test::icosphere(1, 1.0);
  const int C = int(m.vertices.size()), S = int(m.faces.size()), E = 3 * S / 2;  // closed mesh
  for (int n : {1, 2, 5, 16}) {
    const SampleLayout L = build_sample_layout(m.faces, C, n);
    EXPECT_EQ(L.count, C + (n - 1) * E + (n - 1) * (n - 2) / 2 * S) << "n = " << n;
    EXPECT_EQ(L.triangle_count(), S * n * n);
    const std::vector<int32_t> ids = slot_ids(L);
    std::set<int32_t> seen(ids.begin(), ids.end());
    EXPECT_EQ(int(seen.size()), L.count);  // every id used
  }
}

TEST(SampleLayoutTest, SharedSamplesHaveIdenticalProjectionLines) {
  const SlabModel s = sphere_shell(6, 1);
  const SampleLayout& L = s.samples;
  // Every (slab, grid point) that maps to the same id must give the same projection line.
  for (int slab = 0; slab < s.slab_count(); ++slab)
    for (int k = 0; k < L.per_slab; ++k) {
      const int id = L.id(slab, k);
      Vec3 a0, a1, b0, b1;
      projection_line(s, slab, k, a0, a1);
      projection_line(s, L.home(id).slab, L.home(id).index, b0, b1);
      EXPECT_LT((a0 - b0).norm() + (a1 - b1).norm(), 1e-12);
    }
}

TEST(SampleLayoutTest, GridTrianglesFaceOutward) {
  const SlabModel s = sphere_shell(4, 1);
  s.samples.for_each_triangle([&](const Tri& t) {
    const Vec3 a = sample_position(s, t[0]), b = sample_position(s, t[1]), c = sample_position(s, t[2]);
    EXPECT_GT((b - a).cross(c - a).dot(a + b + c), 0.0);
  });
  // Normals point away from the centre, within the facet angle of the 80-face polyhedron (< 12°).
  for (int id = 0; id < s.samples.count; ++id)
    EXPECT_GT(sample_normal(s, id).cast<double>().dot(sample_position(s, id).normalized()),
              std::cos(12 * std::numbers::pi / 180));
}

TEST(SampleLayoutTest, RejectsNonManifoldAndBadIds) {
  std::vector<Tri> fan = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};  // edge (0,1) in three slabs
  EXPECT_THROW(build_sample_layout(fan, 5, 4), InvalidInput);
  EXPECT_THROW(build_sample_layout({{0, 1, 7}}, 3, 4), InvalidInput);
  EXPECT_THROW(build_sample_layout({{0, 1, 2}}, 3, 0), InvalidInput);
}

// An icosphere with four faces removed: slab sides that one slab holds.
TriangleMesh holed_sphere(int subdivisions) {
  TriangleMesh open = test::icosphere(subdivisions, 1.0);
  for (int f : {70, 40, 33, 7}) open.faces.erase(open.faces.begin() + f);
  return open;
}

TEST(SampleLayoutTest, SlotsListEveryGridPointOfASample) {
  // Reference: invert `ids` by brute force; for_each_slot must give exactly the same slots, in
  // increasing order, on a closed mesh and on one with holes.
  for (const TriangleMesh& m : {test::icosphere(1, 1.0), holed_sphere(1)})
    for (int n : {1, 2, 3, 16}) {
      const SampleLayout L = build_sample_layout(m.faces, int(m.vertices.size()), n);
      std::vector<std::vector<int32_t>> expected(L.count);
      const std::vector<int32_t> ids = slot_ids(L);
      for (size_t slot = 0; slot < ids.size(); ++slot) expected[ids[slot]].push_back(int32_t(slot));
      for (int32_t s = 0; s < L.count; ++s) {
        std::vector<int32_t> got;
        L.for_each_slot(s, [&](int32_t slot) { got.push_back(slot); });
        ASSERT_EQ(got, expected[s]) << "n = " << n << ", sample " << s;
        if (s >= L.first_interior) {
          ASSERT_EQ(expected[s].size(), 1u);  // interior: one slab only
        }
      }
    }
}

// The grid triangles of slab k at grid n, listed from triangle_grid.h's definition of the split
// (every cell's "up" triangle, then its "down" one where there is one), independently of the
// layout's own enumeration: packed grid indices, row by row.
std::vector<std::array<int, 3>> grid_split(int n) {
  std::vector<std::array<int, 3>> out;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i + j < n; ++i) {
      out.push_back({grid::index(n, i, j), grid::index(n, i, j + 1), grid::index(n, i + 1, j)});
      if (i + j <= n - 2)
        out.push_back({grid::index(n, i + 1, j), grid::index(n, i, j + 1), grid::index(n, i + 1, j + 1)});
    }
  return out;
}

TEST(SampleLayoutTest, DerivedTrianglesAndNeighboursMatchBruteForce) {
  // Nothing but ids, homes, corner slots and edges' second sides is stored for the triangles and the neighbours:
  // for_each_triangle(), grid_triangle(), for_each_incident_triangle() and for_each_neighbour()
  // must give what a brute-force scan of the split gives, on a closed mesh and on one with holes
  // (slab sides that one slab holds).
  TriangleMesh open = test::icosphere(2, 1.0);
  for (int f : {200, 120, 40, 7}) open.faces.erase(open.faces.begin() + f);
  for (const TriangleMesh& m : {test::icosphere(2, 1.0), open})
    for (int n : {1, 2, 4, 32}) {
      const SampleLayout a = build_sample_layout(m.faces, int(m.vertices.size()), n);
      std::vector<Tri> tris;
      const std::vector<std::array<int, 3>> split = grid_split(n);
      for (size_t k = 0; k < m.faces.size(); ++k)
        for (const auto& c : split) {
          const SlabIds g = a.slab_ids(int32_t(k));
          tris.push_back({g[c[0]], g[c[1]], g[c[2]]});
        }
      ASSERT_EQ(a.triangle_count(), int32_t(tris.size()));
      std::vector<Tri> listed;
      a.for_each_triangle([&](const Tri& t) { listed.push_back(t); });
      ASSERT_EQ(listed, tris) << "n = " << n;
      std::vector<std::vector<int32_t>> incident(a.count);
      std::vector<std::set<int32_t>> joined(a.count);
      for (int32_t t = 0; t < int32_t(tris.size()); ++t) {
        ASSERT_EQ(a.grid_triangle(t), tris[t]) << "n = " << n << ", triangle " << t;
        for (int k = 0; k < 3; ++k) {
          incident[tris[t][k]].push_back(t);
          joined[tris[t][k]].insert(tris[t][(k + 1) % 3]), joined[tris[t][(k + 1) % 3]].insert(tris[t][k]);
        }
      }
      for (int32_t s = 0; s < a.count; ++s) {
        std::vector<int32_t> seen;
        a.for_each_incident_triangle(s, [&](int32_t t, const Tri& corners) {
          seen.push_back(t);
          EXPECT_EQ(corners, tris[t]);
        });
        ASSERT_EQ(seen, incident[s]) << "n = " << n << ", sample " << s
                                     << ": every incident triangle, in increasing order";
        std::set<int32_t> neighbours;
        size_t listed = 0;
        a.for_each_neighbour(s, [&](int32_t t) { neighbours.insert(t), ++listed; });
        ASSERT_EQ(neighbours, joined[s]) << "n = " << n << ", sample " << s;
        ASSERT_EQ(listed, joined[s].size()) << "n = " << n << ", sample " << s << ": each once";
      }
    }
}

TEST(SampleLayoutTest, HomesAreEachSamplesFirstSlot) {
  // Reference: the first slot (slab-major, grid index order) whose id is the sample, by a scan of
  // `ids`; home() must give exactly that slab and grid index, on a closed mesh and on one with
  // holes, for sample and texel grids (n·m up to 64 here).
  for (const TriangleMesh& m : {test::icosphere(2, 1.0), holed_sphere(2)})
    for (int n : {1, 2, 7, 16, 32, 64}) {
      const SampleLayout L = build_sample_layout(m.faces, int(m.vertices.size()), n);
      // Only the shared samples store a home, only the corners their slots, each coarse edge two sides.
      ASSERT_EQ(L.homes.size(), size_t(L.first_interior));
      ASSERT_EQ(L.corner_slot_offsets.size(), size_t(L.first_edge) + 1);
      ASSERT_EQ(L.edge_other_side.size(), n > 1 ? size_t(L.first_interior - L.first_edge) / (n - 1) : 0u);
      std::vector<int64_t> first(L.count, -1);
      const std::vector<int32_t> ids = documented_ids(m.faces, int(m.vertices.size()), n);
      for (size_t slot = 0; slot < ids.size(); ++slot)
        if (first[ids[slot]] < 0) first[ids[slot]] = int64_t(slot);
      for (int32_t s = 0; s < L.count; ++s) {
        const GridSlot h = L.home(s);
        ASSERT_EQ(int64_t(h.slab) * L.per_slab + h.index, first[s]) << "n = " << n << ", sample " << s;
        ASSERT_TRUE(h.index >= 0 && h.index < L.per_slab);
      }
    }
}

TEST(SampleLayoutTest, VertexSlabsAreTheSlabsHoldingEachCoarseVertex) {
  // Reference: a scan of the slab list for the slabs that have v as a corner, in slab order; the
  // layout gives them from the corner sample's slots (a layout refuses a vertex no slab uses).
  // Closed and holed meshes, grid sizes including n = 1 (no edge samples).
  for (const TriangleMesh& m : {test::icosphere(2, 1.0), holed_sphere(2)})
    for (int n : {1, 2, 7, 16}) {
      const int C = int(m.vertices.size());
      const SampleLayout L = build_sample_layout(m.faces, C, n);
      for (int32_t v = 0; v < C; ++v) {
        std::vector<int32_t> expected, got;
        for (size_t s = 0; s < m.faces.size(); ++s)
          if (std::find(m.faces[s].begin(), m.faces[s].end(), v) != m.faces[s].end()) expected.push_back(int32_t(s));
        L.for_each_vertex_slab(v, [&](int32_t s) { got.push_back(s); });
        ASSERT_EQ(got, expected) << "n = " << n << ", vertex " << v;
        ASSERT_EQ(L.vertex_slab_count(v), int32_t(expected.size())) << "n = " << n << ", vertex " << v;
      }
    }
}
