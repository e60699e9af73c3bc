// SPDX-License-Identifier: MIT
// Global sample ids: counts by Euler's formula, shared edge and corner samples, orientation.
#include "support/test_models.h"

#include <hdm/core/error.h>
#include <hdm/slab/sample_layout.h>
#include <hdm/slab/triangle_grid.h>

#include <gtest/gtest.h>

#include <algorithm>
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

}  // namespace

TEST(SampleLayoutTest, counts_follow_euler_formula) {
  const TriangleMesh m = test::icosphere(1, 1.0);
  const int C = int(m.vertices.size()), S = int(m.faces.size()), E = 3 * S / 2;  // closed mesh
  for (int n : {1, 2, 5, 16}) {
    const SampleLayout L = build_sample_layout(m.faces, C, n);
    EXPECT_EQ(L.count, C + (n - 1) * E + (n - 1) * (n - 2) / 2 * S) << "n = " << n;
    EXPECT_EQ(int(L.triangles.size()), S * n * n);
    std::set<int32_t> seen(L.ids.begin(), L.ids.end());
    EXPECT_EQ(int(seen.size()), L.count);  // every id used
  }
}

TEST(SampleLayoutTest, shared_samples_have_identical_projection_lines) {
  const SlabModel s = sphere_shell(6, 1);
  const SampleLayout& L = s.samples;
  // Every (slab, grid point) that maps to the same id must give the same projection line.
  for (int slab = 0; slab < s.slab_count(); ++slab)
    for (int k = 0; k < L.per_slab; ++k) {
      const int id = L.ids[slab * L.per_slab + k];
      Vec3 a0, a1, b0, b1;
      projection_line(s, slab, k, a0, a1);
      projection_line(s, L.home_slab[id], L.home_index[id], b0, b1);
      EXPECT_LT((a0 - b0).norm() + (a1 - b1).norm(), 1e-12);
    }
}

TEST(SampleLayoutTest, grid_triangles_face_outward) {
  const SlabModel s = sphere_shell(4, 1);
  for (const Tri& t : s.samples.triangles) {
    const Vec3 a = sample_position(s, t[0]), b = sample_position(s, t[1]), c = sample_position(s, t[2]);
    EXPECT_GT((b - a).cross(c - a).dot(a + b + c), 0.0);
  }
  // Normals point away from the centre, within the facet angle of the 80-face polyhedron (< 12°).
  for (int id = 0; id < s.samples.count; ++id)
    EXPECT_GT(s.normals[id].cast<double>().dot(sample_position(s, id).normalized()), std::cos(12 * M_PI / 180));
}

TEST(SampleLayoutTest, rejects_non_manifold_and_bad_ids) {
  std::vector<Tri> fan = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};  // edge (0,1) in three slabs
  EXPECT_THROW(build_sample_layout(fan, 5, 4), InvalidInput);
  EXPECT_THROW(build_sample_layout({{0, 1, 7}}, 3, 4), InvalidInput);
  EXPECT_THROW(build_sample_layout({{0, 1, 2}}, 3, 0), InvalidInput);
}

TEST(SampleLayoutTest, slots_list_every_grid_point_of_a_sample) {
  // Reference: invert `ids` by brute force; for_each_slot must give exactly the same slots.
  const TriangleMesh m = test::icosphere(1, 1.0);
  for (int n : {1, 2, 3, 16}) {
    const SampleLayout L = build_sample_layout(m.faces, int(m.vertices.size()), n);
    std::vector<std::vector<int32_t>> expected(L.count);
    for (size_t slot = 0; slot < L.ids.size(); ++slot) expected[L.ids[slot]].push_back(int32_t(slot));
    for (int32_t s = 0; s < L.count; ++s) {
      std::vector<int32_t> got;
      L.for_each_slot(s, [&](int32_t slot) { got.push_back(slot); });
      std::sort(got.begin(), got.end());
      ASSERT_EQ(got, expected[s]) << "n = " << n << ", sample " << s;
      if (s >= L.first_interior) {
        ASSERT_EQ(expected[s].size(), 1u);  // interior: one slab only
      }
    }
  }
}

TEST(SampleLayoutTest, without_adjacency_the_rest_of_the_layout_is_the_same) {
  // The texel layout leaves out the grid triangles, their incidence and the neighbour rows; ids,
  // homes and slots must not depend on that, and for_each_neighbour() must list, from the slots
  // alone, exactly the samples a grid edge joins: counted here from the grid triangles of the
  // full layout (brute force over every triangle's three edges).
  const TriangleMesh m = test::icosphere(2, 1.0);
  for (int n : {1, 4, 32}) {
    const SampleLayout a = build_sample_layout(m.faces, int(m.vertices.size()), n);
    const SampleLayout b = build_sample_layout(m.faces, int(m.vertices.size()), n, false);
    EXPECT_TRUE(b.triangles.empty() && b.triangle_offsets.empty() && b.incident_triangles.empty());
    EXPECT_TRUE(b.neighbour_offsets.empty() && b.neighbours.empty());
    EXPECT_EQ(b.triangles.capacity(), 0u) << "the grid triangles are never allocated";
    EXPECT_EQ(a.count, b.count);
    EXPECT_EQ(a.first_interior, b.first_interior);
    EXPECT_EQ(a.ids, b.ids);
    EXPECT_EQ(a.home_slab, b.home_slab);
    EXPECT_EQ(a.home_index, b.home_index);
    EXPECT_EQ(a.shared_slot_offsets, b.shared_slot_offsets);
    EXPECT_EQ(a.slot_of_shared, b.slot_of_shared);
    std::vector<std::set<int32_t>> joined(a.count);
    for (const Tri& t : a.triangles)
      for (int k = 0; k < 3; ++k) joined[t[k]].insert(t[(k + 1) % 3]), joined[t[(k + 1) % 3]].insert(t[k]);
    for (int32_t s = 0; s < a.count; ++s) {
      std::set<int32_t> seen_a, seen_b;
      a.for_each_neighbour(s, [&](int32_t t) { seen_a.insert(t); });
      b.for_each_neighbour(s, [&](int32_t t) { seen_b.insert(t); });
      ASSERT_EQ(seen_b, joined[s]) << "n = " << n << ", sample " << s;
      ASSERT_EQ(seen_a, joined[s]) << "n = " << n << ", sample " << s;
    }
  }
}
