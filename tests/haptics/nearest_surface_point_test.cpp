// SPDX-License-Identifier: MIT
// The sphere proxy's nearest-point search over the displaced surface's grid triangles
// (src/haptics/nearest_surface_point.h, internal): a search restarted from its own result, with
// the ball's centre unchanged, stays there, and never ends farther from the centre than the
// triangle it starts on. The ball follows each touch this way from round to round, so a search
// that ended elsewhere made it lose or swap a contact for a tick.
#include "haptics/haptics_fixtures.h"
#include "nearest_surface_point.h"

#include <hdm/query/slab_query.h>

#include <gtest/gtest.h>

#include <random>

namespace hdm {
namespace {

using haptics_detail::nearest_surface_point;
using haptics_detail::SurfacePoint;

TEST(NearestSurfacePoint, ARestartFromItsResultStaysThere) {
  const SlabModel& m = test::paper_bunny().model;
  const double diag = test::paper_bunny().diag;
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> slab(0, m.slab_count() - 1);
  std::uniform_real_distribution<double> u(0, 1), lift(-0.002, 0.01);
  int down = 0, up = 0;
  for (int k = 0; k < 4000; ++k) {
    // A centre near the surface: a point of it, lifted along its normal by -0.2 to 1 % of the diagonal.
    const int s = slab(rng);
    double a = u(rng), b = u(rng);
    if (a + b > 1) a = 1 - a, b = 1 - b;
    SlabCoordinates at;
    at.bary = Vec3(1 - a - b, a, b);
    Contact e;
    evaluate_surface(m, s, at, e);
    const Vec3 c = e.surface_point + lift(rng) * diag * e.normal;
    const SurfacePoint first = nearest_surface_point(m, s, a, b, c);
    const SurfacePoint again = nearest_surface_point(m, first.slab, first.wS, first.wT, c);
    ASSERT_LE((again.point - c).norm(), (first.point - c).norm() + 1e-12 * diag) << "sample " << k;
    ASSERT_LT((again.point - first.point).norm(), 1e-9 * diag) << "sample " << k << (first.down ? ", down" : ", up");
    (first.down ? down : up) += 1;
  }
  EXPECT_GT(down, 500) << "the grid's down triangles are tested";
  EXPECT_GT(up, 500);
}

}  // namespace
}  // namespace hdm
