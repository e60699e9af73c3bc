// SPDX-License-Identifier: MIT
// The inner shell's enclosure test against independent references: an analytic sphere and the
// exact inside test on the input mesh (Embree ray parity) for points in no slab.
#include "support/test_models.h"

#include <hdm/analysis/exact_mesh_query.h>
#include <hdm/io/read_mesh.h>
#include <hdm/query/inner_shell.h>
#include <hdm/query/slab_query.h>
#include <hdm/slab/bake.h>

#include <gtest/gtest.h>

#include <random>

using namespace hdm;

TEST(InnerShellTest, sphere_core_is_enclosed_and_the_outside_is_not) {
  BakeOptions o;
  o.slabs = 80;
  o.grid_n = 4;
  const SlabModel m = bake_slabs(test::icosphere(3, 1.0), "sphere", o);
  const InnerShell core(m);
  ASSERT_TRUE(core.closed());
  double r_in = INFINITY, r_out = 0;  // radii bounding the inner shell (its corners lie inside)
  for (const Vec3& v : m.inner) r_in = std::min(r_in, v.norm()), r_out = std::max(r_out, v.norm());
  // A flat triangle between corners of radius >= r_in comes no closer than r_in·cos(edge angle).
  r_in *= 0.9;
  std::mt19937 rng(5);
  std::normal_distribution<double> g(0, 1);
  for (int k = 0; k < 2000; ++k) {
    const Vec3 dir = Vec3(g(rng), g(rng), g(rng)).normalized();
    EXPECT_TRUE(core.encloses(dir * r_in * (k % 100) / 100.0)) << k;
    EXPECT_FALSE(core.encloses(dir * (r_out * 1.001 + (k % 100) / 50.0))) << k;
  }
  EXPECT_FALSE(core.encloses(Vec3(NAN, 0, 0)));
}

TEST(InnerShellTest, points_in_no_slab_are_enclosed_iff_inside_the_input) {
  const SlabModel& m = test::baked_bunny(0, 16);
  const InnerShell core(m);
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
    const bool in = core.encloses(p);
    enclosed += in;
    EXPECT_EQ(in, exact.inside(p)) << p.transpose();
  }
  EXPECT_GT(tested, 5000);
  EXPECT_GT(enclosed, 500);
}

TEST(InnerShellTest, open_models_enclose_nothing) {
  BakeOptions o;
  o.slabs = 60;
  o.grid_n = 4;
  const SlabModel m = bake_slabs(read_mesh(test::data_path("lion-head.off")), "lion-head.off", o);
  const InnerShell core(m);
  EXPECT_FALSE(core.closed());
  for (const Vec3& v : m.inner) EXPECT_FALSE(core.encloses(v));
}
