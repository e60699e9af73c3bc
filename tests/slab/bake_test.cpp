// SPDX-License-Identifier: MIT
// Bake: validity checked numerically, an analytic sphere, the real models, bad input.
#include "support/test_models.h"

#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/analysis/fidelity.h>
#include <hdm/core/error.h>
#include <hdm/io/read_mesh.h>
#include <hdm/query/alpha_plane.h>
#include <hdm/slab/bake.h>

#include <gtest/gtest.h>

#include <random>

using namespace hdm;

namespace {

// Finite-difference Jacobian determinant of X(wS, wT, α) at a point, from the stored corners only.
double numeric_jacobian(const SlabModel& m, int slab, double wS, double wT, double a) {
  auto X = [&](double s, double u, double al) { return test::point_from_corners(m, slab, Vec3(1 - s - u, s, u), al); };
  const double h = 1e-6;
  const Vec3 ds = (X(wS + h, wT, a) - X(wS - h, wT, a)) / (2 * h);
  const Vec3 dt = (X(wS, wT + h, a) - X(wS, wT - h, a)) / (2 * h);
  const Vec3 da = (X(wS, wT, a + h) - X(wS, wT, a - h)) / (2 * h);
  return ds.cross(dt).dot(da);
}

void expect_all_slabs_valid(const SlabModel& m) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  for (int s = 0; s < m.slab_count(); ++s)
    for (int k = 0; k < 20; ++k) {
      double a = u(rng), b = u(rng);
      if (a + b > 1) a = 1 - a, b = 1 - b;
      ASSERT_GT(numeric_jacobian(m, s, a, b, u(rng)), 0.0) << "slab " << s;
    }
}

}  // namespace

TEST(BakeTest, SphereReconstructionMatchesTheAnalyticSurface) {
  // A finely tessellated sphere: every reconstructed point lies on the input polyhedron, whose
  // distance to the true sphere is below the chord error 1 - cos(edge/2).
  const TriangleMesh sphere = test::icosphere(4, 1.0);
  BakeOptions o;
  o.slabs = 80;
  o.grid_n = 8;
  BakeReport r;
  const SlabModel m = bake_slabs(sphere, "sphere", o, &r);
  EXPECT_EQ(r.invalid_slabs, 0);
  EXPECT_EQ(r.ray_misses, 0);
  expect_all_slabs_valid(m);
  for (int s = 0; s < m.samples.count; ++s) EXPECT_NEAR(sample_position(m, s).norm(), 1.0, 3e-3);
}

TEST(BakeTest, ACrumpledSurfaceGivesValidSlabs) {
  // A crumple (a ring shrunk and twisted over itself) is no reason for an invalid slab: the
  // decimation merges it or the bake opens the dual cones around it, at any slab count.
  const TriangleMesh in = test::crumpled_icosphere(3, 0.1, 150);
  for (int slabs : {100, 400, 1280}) {
    BakeOptions o;
    o.slabs = slabs;
    o.grid_n = 4;
    BakeReport r;
    const SlabModel m = bake_slabs(in, "crumpled icosphere", o, &r);
    EXPECT_EQ(r.invalid_slabs, 0) << slabs << " slabs";
    expect_all_slabs_valid(m);
  }
}

TEST(BakeTest, BunnySlabsAreValidAndReportIsConsistent) {
  BakeOptions o;  // defaults: n = 16, slabs = triangles · density / n²
  BakeReport r;
  const SlabModel m = bake_slabs(test::bunny(), "bunny00.off", o, &r);
  EXPECT_EQ(r.slabs, m.slab_count());
  EXPECT_NEAR(double(r.submesh_triangles) / double(r.input_triangles), o.density, 0.1 * o.density);
  EXPECT_EQ(r.invalid_slabs, 0);
  expect_all_slabs_valid(m);
  for (float d : m.displacement) ASSERT_TRUE(d >= 0 && d <= 1);
}

TEST(BakeTest, RealModelsBake) {
  for (const char* name : {"armadillo.off", "refined_elephant.off", "lion-head.off"}) {
    const TriangleMesh mesh = read_mesh(test::data_path(name));
    BakeReport r;
    const SlabModel m = bake_slabs(mesh, name, BakeOptions{}, &r);
    EXPECT_GT(m.slab_count(), 0) << name;
    // Independent measurement on the input (Embree): the reconstruction stays close both ways.
    const Fidelity f = measure_fidelity(m, ExactMeshQuery(mesh));
    EXPECT_LT(f.rms_pct, 0.3) << name;
    EXPECT_LT(f.rms_back_pct, 0.3) << name;
    for (float d : m.displacement) ASSERT_TRUE(d >= 0 && d <= 1) << name;
  }
}

TEST(BakeTest, BadMeshesGiveErrorsNamingTheInput) {
  auto expect_error = [](const TriangleMesh& m, const std::string& what) {
    try {
      bake_slabs(m, "bad.obj", BakeOptions{});
      ADD_FAILURE() << "no error for " << what;
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find("bad.obj"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  expect_error(TriangleMesh{}, "empty");
  TriangleMesh nan = test::icosphere(1, 1.0);
  nan.vertices[3].y() = std::nan("");
  expect_error(nan, "non-finite");
  TriangleMesh fin = test::icosphere(1, 1.0);
  fin.vertices.push_back(Vec3(3, 3, 3));
  fin.faces.push_back({fin.faces[0][0], fin.faces[0][1], int32_t(fin.vertices.size() - 1)});
  expect_error(fin, "non-manifold");
  TriangleMesh flipped = test::icosphere(1, 1.0);
  std::swap(flipped.faces[0][1], flipped.faces[0][2]);
  expect_error(flipped, "orientation");
  BakeOptions zero_grid;
  zero_grid.grid_n = 0;
  EXPECT_THROW(bake_slabs(test::icosphere(1, 1.0), "x", zero_grid), InvalidInput);
}

TEST(BakeTest, BakeOnTheCallersBvhGivesTheSameModel) {
  BakeOptions o;
  o.slabs = 300;
  o.grid_n = 4;
  BakeReport r1, r2;
  const SlabModel a = bake_slabs(test::bunny(), "bunny00.off", o, &r1);
  const ExactMeshQuery input(test::bunny());
  const SlabModel b = bake_slabs(input, "bunny00.off", o, &r2);
  EXPECT_EQ(a.slabs, b.slabs);
  EXPECT_EQ(a.inner, b.inner);
  EXPECT_EQ(a.outer, b.outer);
  EXPECT_EQ(test::values(a.displacement), test::values(b.displacement));
  EXPECT_EQ(a.colour, b.colour);
  EXPECT_EQ(r1.ray_misses, r2.ray_misses);
}

// The density rule: density × input triangles of submesh (slabs·n²), at least 8 slabs, and no more
// than kMaxDensitySubmesh submesh triangles however large the input.
TEST(BakeTest, TheDefaultSlabCountFollowsTheDensityUpToTheSubmeshCap) {
  BakeOptions o;                                  // density 4, n = 16
  EXPECT_EQ(default_slab_count(75408, o), 1178);  // 75,408 · 4 / 256 = 1,178.25
  EXPECT_EQ(default_slab_count(10, o), 8);
  const int64_t million = kMaxDensitySubmesh / 4;  // where the cap starts at density 4
  EXPECT_EQ(default_slab_count(million, o), kMaxDensitySubmesh / 256);
  EXPECT_EQ(default_slab_count(12636000, o), kMaxDensitySubmesh / 256);
  EXPECT_EQ(default_slab_count(int64_t(1) << 40, o), kMaxDensitySubmesh / 256);
  o.grid_n = 4;
  EXPECT_EQ(default_slab_count(12636000, o), kMaxDensitySubmesh / 16);
  o.density = 1;
  EXPECT_EQ(default_slab_count(1000000, o), 62500);
}
