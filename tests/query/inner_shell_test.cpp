// SPDX-License-Identifier: MIT
// The inner shell as an enclosure test (the rule measure_contact applies to points in no slab:
// ExactMeshQuery over the slabs' inner triangles) against independent references: an analytic
// sphere and the exact inside test on the input mesh for points in no slab.
#include "support/test_models.h"

#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/io/read_mesh.h>
#include <hdm/query/slab_query.h>
#include <hdm/slab/bake.h>

#include <gtest/gtest.h>

#include <random>

using namespace hdm;

TEST(InnerShellEnclosureTest, SphereCoreIsEnclosedAndTheOutsideIsNot) {
  BakeOptions o;
  o.slabs = 80;
  o.grid_n = 4;
  const SlabModel m = bake_slabs(test::icosphere(3, 1.0), "sphere", o);
  const ExactMeshQuery core(TriangleMesh{m.inner, m.slabs});
  ASSERT_TRUE(core.closed());
  // Radii bounding the inner shell, by brute force over its triangles: every point closer to the
  // centre than the nearest inner triangle is enclosed, every point beyond the farthest corner is not.
  double r_in = INFINITY, r_out = 0;
  for (const Tri& t : m.slabs) {
    const Vec3 c = closest_point_on_triangle(Vec3::Zero(), m.inner[t[0]], m.inner[t[1]], m.inner[t[2]]);
    r_in = std::min(r_in, c.norm());
  }
  for (const Vec3& v : m.inner) r_out = std::max(r_out, v.norm());
  ASSERT_GT(r_in, 0.5);  // a shell that collapsed onto the centre would make the test vacuous
  r_in *= 0.999;
  std::mt19937 rng(5);
  std::normal_distribution<double> g(0, 1);
  for (int k = 0; k < 2000; ++k) {
    const Vec3 dir = Vec3(g(rng), g(rng), g(rng)).normalized();
    EXPECT_TRUE(core.inside(dir * r_in * (k % 100) / 100.0)) << k;
    EXPECT_FALSE(core.inside(dir * (r_out * 1.001 + (k % 100) / 50.0))) << k;
  }
  EXPECT_FALSE(core.inside(Vec3(NAN, 0, 0)));
}

TEST(InnerShellEnclosureTest, PointsInNoSlabAreEnclosedIffInsideTheInput) {
  const SlabModel& m = test::baked_bunny(0, 16);
  const ExactMeshQuery core(TriangleMesh{m.inner, m.slabs});
  ASSERT_TRUE(core.closed());
  const ExactMeshQuery exact(test::bunny());
  const SlabLocator loc(m);
  const Aabb box = bounds(test::bunny());
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(0, 1);
  int tested = 0, enclosed = 0;
  for (int k = 0; k < 20000; ++k) {
    const Vec3 p = box.min + (box.max - box.min).cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
    QueryCache cache;
    if (query(m, loc, p, cache).in_shell()) continue;  // the displacement map answers there
    ++tested;
    const bool in = core.inside(p);
    enclosed += in;
    EXPECT_EQ(in, exact.inside(p)) << p.transpose();
  }
  EXPECT_GT(tested, 5000);
  EXPECT_GT(enclosed, 500);
}

// An open model's inner shell is open like its input, so enclosure is the same "behind the nearest
// surface" rule that ExactMeshQuery::inside applies to the open input: below the surface, where
// the shells cover the input, both say the same.
TEST(InnerShellEnclosureTest, OpenModelsAgreeWithTheParityOfTheOpenInputBelowTheShell) {
  const TriangleMesh input = read_mesh(test::data_path("lion-head.off"));
  BakeOptions o;
  o.slabs = 600;  // enough that the shells cover the input (150 leave ray misses: 1.6% error)
  o.grid_n = 8;
  const SlabModel m = bake_slabs(input, "lion-head.off", o);
  const ExactMeshQuery core(TriangleMesh{m.inner, m.slabs});
  EXPECT_FALSE(core.closed());
  const ExactMeshQuery exact(input);
  const SlabLocator loc(m);
  const double diag = bounds(input).diagonal();
  std::mt19937 rng(3);
  std::uniform_int_distribution<size_t> face(0, input.faces.size() - 1);
  std::uniform_real_distribution<double> u(0, 1);
  int tested = 0, agree = 0, enclosed = 0;
  for (int k = 0; k < 40000; ++k) {
    const int32_t f = static_cast<int32_t>(face(rng));
    const Tri& t = input.faces[f];
    double a = u(rng), b = u(rng);
    if (a + b > 1) a = 1 - a, b = 1 - b;
    const Vec3 on = input.vertices[t[0]] + a * (input.vertices[t[1]] - input.vertices[t[0]]) +
                    b * (input.vertices[t[2]] - input.vertices[t[0]]);
    const Vec3 p = on - u(rng) * 0.02 * diag * exact.face_normal(f);  // up to 2% below the surface
    QueryCache cache;
    if (query(m, loc, p, cache).in_shell()) continue;
    ++tested;
    const bool in = core.inside(p);
    enclosed += in;
    agree += in == exact.inside(p);
  }
  ASSERT_GT(tested, 500);
  EXPECT_GT(enclosed, tested / 2);
  EXPECT_GT(agree, 0.97 * tested) << agree << " of " << tested;
}
