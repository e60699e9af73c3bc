// SPDX-License-Identifier: MIT
// Scale normalisation by powers of two is exact: the exponent brings any diagonal of the accepted
// range into [1, 2), a mesh scaled there and back is bit-identical, and a model scaled by 2^k
// answers a query at 2^k·p with the same slab and 2^k times the depth it gives at p.
#include "support/test_models.h"

#include <hdm/core/error.h>
#include <hdm/mesh/scale_mesh.h>
#include <hdm/query/slab_locator.h>
#include <hdm/query/slab_query.h>
#include <hdm/slab/bake.h>
#include <hdm/slab/scale_model.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

using namespace hdm;
using hdm::test::icosphere;

TEST(ScaleMesh, TheExponentBringsEveryAcceptedDiagonalIntoOneToTwo) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> decade(-30.0, 30.0);
  for (int i = 0; i < 10000; ++i) {
    const double d = std::pow(10.0, decade(rng));
    if (d < kMinDiagonal || d > kMaxDiagonal) continue;
    const double scaled = std::ldexp(d, scale_exponent(d, "mesh.off"));
    EXPECT_GE(scaled, 1.0) << d;
    EXPECT_LT(scaled, 2.0) << d;
  }
  EXPECT_EQ(scale_exponent(1.0, "mesh.off"), 0);
  EXPECT_EQ(scale_exponent(1.999, "mesh.off"), 0);
  EXPECT_EQ(scale_exponent(0.5, "mesh.off"), 1);
}

TEST(ScaleMesh, DiagonalsOutsideTheFloatRangeAreRefusedNamingTheFileAndTheScale) {
  for (double d : {0.0, 1e-31, 1e31, std::numeric_limits<double>::infinity(),
                   std::numeric_limits<double>::quiet_NaN()}) {
    try {
      scale_exponent(d, "tiny.off");
      ADD_FAILURE() << d << " was accepted";
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find("tiny.off: the bounding-box diagonal is"), std::string::npos) << e.what();
    }
  }
}

TEST(ScaleMesh, ThereAndBackIsBitIdentical) {
  const TriangleMesh original = icosphere(3, 0.37, Vec3(0.1, -2.0, 5.0));
  for (int k : {-100, -40, -3, 3, 40, 100}) {
    TriangleMesh m = original;
    scale_mesh(m, k);
    EXPECT_DOUBLE_EQ(bounds(m).diagonal(), std::ldexp(bounds(original).diagonal(), k));
    scale_mesh(m, -k);
    EXPECT_EQ(m.vertices, original.vertices) << k;
  }
}

TEST(ScaleModel, AScaledModelAnswersTheScaledQuery) {
  BakeOptions o;
  o.slabs = 60;
  o.grid_n = 6;
  const SlabModel model = bake_slabs(icosphere(4, 1.0), "sphere", o);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  std::vector<Vec3> points(2000);
  for (Vec3& p : points) p = Vec3(u(rng), u(rng), u(rng));
  const SlabLocator locator(model);
  for (int k : {-40, -20, 20, 40}) {
    SlabModel scaled = model;
    scale_model(scaled, k);
    EXPECT_EQ(scaled.source_diagonal, std::ldexp(model.source_diagonal, k));
    const SlabLocator scaled_locator(scaled);
    QueryCache c0, c1;
    int in_shell = 0;
    for (const Vec3& p : points) {
      const Contact a = query(model, locator, p, c0);
      const Vec3 q(std::ldexp(p.x(), k), std::ldexp(p.y(), k), std::ldexp(p.z(), k));
      const Contact b = query(scaled, scaled_locator, q, c1);
      ASSERT_EQ(a.slab, b.slab) << k;
      if (!a.in_shell()) continue;
      ++in_shell;
      EXPECT_NEAR(std::ldexp(b.depth, -k), a.depth, 1e-12) << k;
      EXPECT_NEAR((a.normal - b.normal).norm(), 0.0, 1e-12) << k;
    }
    EXPECT_GT(in_shell, 50);  // the points reach the shell
    scale_model(scaled, -k);
    EXPECT_EQ(scaled.inner, model.inner);
    EXPECT_EQ(scaled.outer, model.outer);
  }
}
