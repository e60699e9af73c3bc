// SPDX-License-Identifier: MIT
// The haptic query (locator with its coherence cache, then the surface) against a brute-force
// reference that tries every slab: on a coherent walk over the surface (the servo loop's case, the
// cache kept between points) and on independent points (cache reset), the query finds a slab that
// holds the point, or none when no slab does, and its depth equals the depth evaluated in the
// reference's slab.
#include "support/surface_walk.h"
#include "support/test_models.h"

#include <hdm/query/slab_query.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

using namespace hdm;

namespace {

struct Sides {
  int inside = 0, outside = 0;
};

// Checks query(p) against every slab's locate_in_slab on point @p p; @p cache is the query's.
void check_point(const SlabModel& m, const SlabLocator& loc, const Vec3& p, QueryCache& cache, Sides& t) {
  const Contact got = query(m, loc, p, cache);
  std::vector<int> holders;
  SlabCoordinates c;
  for (int s = 0; s < m.slab_count(); ++s)
    if (locate_in_slab(m.geometry[s], p, AlphaSolver::Newton, c)) holders.push_back(s);
  if (holders.empty()) {
    ASSERT_EQ(got.slab, -1);
    ++t.outside;
    return;
  }
  ASSERT_NE(std::find(holders.begin(), holders.end(), got.slab), holders.end());
  // Where slabs meet, a point on the shared face is in both (within the barycentric tolerance);
  // the surface is continuous there, so the depth agrees with any holder's.
  double best = INFINITY;
  for (int s : holders) {
    locate_in_slab(m.geometry[s], p, AlphaSolver::Newton, c);
    Contact ref;
    evaluate_surface(m, s, c, ref);
    best = std::min(best, std::abs(ref.depth - got.depth));
  }
  ASSERT_LE(best, 1e-6 * m.source_diagonal);
  ++t.inside;
}

void check_model(const SlabModel& m, int walk_steps, int global_points) {
  const SlabLocator loc(m);
  std::mt19937 rng(7);
  // Coherent walk: straight steps of ~1e-4 of the diagonal towards a point of a neighbouring slab,
  // up to 3 % of the diagonal above or below the surface (in the shell, above it and below it).
  Sides walk;
  QueryCache cache;
  test::surface_walk(m, loc, 0, walk_steps, 0.03, rng, [&](const Vec3& p) {
    check_point(m, loc, p, cache, walk);
    return !testing::Test::HasFatalFailure();
  });
  if (testing::Test::HasFatalFailure()) return;
  EXPECT_GT(walk.inside, walk_steps / 4);
  EXPECT_GT(walk.outside, 0);
  // Independent points, cache reset before each (the global query).
  Sides global;
  std::uniform_int_distribution<int> any_slab(0, m.slab_count() - 1);
  for (int k = 0; k < global_points; ++k) {
    QueryCache fresh;
    check_point(m, loc, test::near_surface_point(m, any_slab(rng), 0.03, rng), fresh, global);
    if (testing::Test::HasFatalFailure()) return;
  }
  EXPECT_GT(global.inside, global_points / 4);
  EXPECT_GT(global.outside, 0);
}

}  // namespace

TEST(QueryReferenceTest, CoherentWalkAndGlobalPointsMatchAScanOfEverySlab) {
  check_model(test::baked_bunny(0, 16), 6000, 2000);
}

TEST(QueryReferenceTest, CoherentWalkAndGlobalPointsMatchAScanOfEverySlabAt3000Slabs) {
  check_model(test::baked_bunny(3000, 4), 3000, 1000);
}
