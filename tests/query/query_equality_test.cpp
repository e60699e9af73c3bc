// SPDX-License-Identifier: MIT
// The haptic query against a straightforward reference kept here: the slab map from the stored
// corners (no SlabGeometry), the α-plane root by sampling and bisection (no Newton or Halley), the
// barycentrics by cross products, and the surface from the sample-indexed displacements and
// normals recomputed here in double from the sample positions (area-weighted sums over the grid
// triangles, docs/design.md#normals), not the slab-major copy the query reads, whose normals are
// snorm16 codes. On a million points of the default bunny,
// half along a coherent walk (cache kept), half independent (cache reset), the query's slab holds
// the point and its depth equals the reference's within 1e-6 of the diagonal; where the query
// answers "no slab", no slab holds the point by a clear margin.
#include "support/surface_walk.h"
#include "support/test_models.h"

#include <hdm/query/slab_query.h>
#include <hdm/slab/triangle_grid.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <random>
#include <vector>

using namespace hdm;

namespace {

// Corners of slab s on its α-plane: V(α) = V0 + α·(V1 − V0) for V = R, S, T.
std::array<Vec3, 3> corners_at(const SlabModel& m, int s, double alpha) {
  std::array<Vec3, 3> v;
  for (int k = 0; k < 3; ++k) {
    const int32_t c = m.slabs[s][k];
    v[k] = m.inner[c] + alpha * (m.outer[c] - m.inner[c]);
  }
  return v;
}

// f(α): signed distance (times the triangle's doubled area) of p from the α-plane.
double plane_function(const SlabModel& m, int s, const Vec3& p, double alpha) {
  const std::array<Vec3, 3> v = corners_at(m, s, alpha);
  return (v[1] - v[0]).cross(v[2] - v[0]).dot(p - v[0]);
}

struct Hit {
  double alpha = 0, wS = 0, wT = 0;
};

// Whether p is in slab s with every barycentric >= -tol: each sign change of f over 64 equal
// parts of [0,1] is bisected to the last bit, and the root's barycentrics are tested.
bool reference_locate(const SlabModel& m, int s, const Vec3& p, double tol, Hit& hit) {
  constexpr int kParts = 64;
  double a0 = 0, f0 = plane_function(m, s, p, 0);
  for (int k = 1; k <= kParts; ++k) {
    const double a1 = double(k) / kParts, f1 = plane_function(m, s, p, a1);
    if ((f0 <= 0 && f1 >= 0) || (f0 >= 0 && f1 <= 0)) {
      double lo = a0, hi = a1, flo = f0;
      for (int it = 0; it < 200 && hi - lo > 0; ++it) {
        const double mid = 0.5 * (lo + hi);
        if (mid <= lo || mid >= hi) break;
        const double fm = plane_function(m, s, p, mid);
        if ((fm > 0) == (flo > 0))
          lo = mid, flo = fm;
        else
          hi = mid;
      }
      const double alpha = 0.5 * (lo + hi);
      const std::array<Vec3, 3> v = corners_at(m, s, alpha);
      const Vec3 e1 = v[1] - v[0], e2 = v[2] - v[0], r = p - v[0], n = e1.cross(e2);
      const double wS = r.cross(e2).dot(n) / n.squaredNorm(), wT = e1.cross(r).dot(n) / n.squaredNorm();
      if (1 - wS - wT >= -tol && wS >= -tol && wT >= -tol) {
        hit = {alpha, wS, wT};
        return true;
      }
    }
    a0 = a1, f0 = f1;
  }
  return false;
}

// Unit normal of every sample in double: the sum of the cross products of its grid triangles'
// edges (area-weighted, every slab holding it), normalised.
std::vector<Vec3> reference_normals(const SlabModel& m) {
  std::vector<Vec3> sum(size_t(m.samples.count), Vec3::Zero());
  m.samples.for_each_triangle([&](const Tri& t) {
    const Vec3 a = sample_position(m, t[0]), b = sample_position(m, t[1]), c = sample_position(m, t[2]);
    const Vec3 n = (b - a).cross(c - a);
    for (int32_t v : t) sum[size_t(v)] += n;
  });
  for (Vec3& n : sum) n.normalize();
  return sum;
}

// Depth of the displaced surface at hit in slab s (docs/design.md#query): the grid triangle under
// (n·wT, n·wS), δ from the sample-indexed array and the normal from @p normals, depth on the
// tangent plane.
double reference_depth(const SlabModel& m, const std::vector<Vec3>& normals, int s, const Hit& hit) {
  const int n = m.grid_n;
  double hx = std::max(0.0, n * hit.wT), hy = std::max(0.0, n * hit.wS);
  if (hx + hy > n) {
    const double scale = n / (hx + hy);
    hx *= scale, hy *= scale;
  }
  const int i = std::min(int(std::floor(hx)), n - 1), j = std::min(int(std::floor(hy)), n - 1 - i);
  double fx = hx - i, fy = hy - j;
  int pts[3][2];
  double w[3];
  if (fx + fy > 1 && i + j <= n - 2) {
    pts[0][0] = i + 1, pts[0][1] = j + 1, pts[1][0] = i + 1, pts[1][1] = j, pts[2][0] = i, pts[2][1] = j + 1;
    w[0] = fx + fy - 1, w[1] = 1 - fy, w[2] = 1 - fx;
  } else {
    if (fx + fy > 1) {
      const double sum = fx + fy;
      fx /= sum, fy /= sum;
    }
    pts[0][0] = i, pts[0][1] = j, pts[1][0] = i + 1, pts[1][1] = j, pts[2][0] = i, pts[2][1] = j + 1;
    w[0] = 1 - fx - fy, w[1] = fx, w[2] = fy;
  }
  double delta = 0;
  Vec3 normal = Vec3::Zero();
  for (int k = 0; k < 3; ++k) {
    const int32_t id = m.samples.id(s, grid::index(n, pts[k][0], pts[k][1]));
    delta += w[k] * m.displacement[id];
    normal += w[k] * normals[size_t(id)];
  }
  normal.normalize();
  const Vec3 bary(1 - hit.wS - hit.wT, hit.wS, hit.wT);
  Vec3 ray = Vec3::Zero();
  for (int k = 0; k < 3; ++k) ray += bary[k] * (m.outer[m.slabs[s][k]] - m.inner[m.slabs[s][k]]);
  return (delta - hit.alpha) * std::max(ray.dot(normal), 0.1 * ray.norm());
}

struct Boxes {
  std::vector<Vec3> lo, hi;
};

Boxes slab_boxes(const SlabModel& m) {
  Boxes b;
  for (int s = 0; s < m.slab_count(); ++s) {
    Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
    for (int k = 0; k < 3; ++k)
      for (const Vec3& c : {m.inner[m.slabs[s][k]], m.outer[m.slabs[s][k]]}) lo = lo.cwiseMin(c), hi = hi.cwiseMax(c);
    b.lo.push_back(lo), b.hi.push_back(hi);
  }
  return b;
}

struct Tally {
  int64_t inside = 0, outside = 0;
};

// One query against the reference: a slab that the query reports holds p (barycentrics >= -1e-7)
// with the reference's depth there; "no slab" holds only if no slab holds p with a margin of 1e-7.
void check(const SlabModel& m, const std::vector<Vec3>& normals, const Boxes& boxes, const Contact& got, const Vec3& p,
           Tally& t) {
  Hit hit;
  if (got.slab >= 0) {
    ASSERT_TRUE(reference_locate(m, got.slab, p, 1e-7, hit)) << "slab " << got.slab;
    ASSERT_NEAR(got.depth, reference_depth(m, normals, got.slab, hit), 1e-6 * m.source_diagonal) << "slab " << got.slab;
    ++t.inside;
    return;
  }
  for (int s = 0; s < m.slab_count(); ++s) {
    if (!(p.array() >= boxes.lo[s].array()).all() || !(p.array() <= boxes.hi[s].array()).all()) continue;
    ASSERT_FALSE(reference_locate(m, s, p, -1e-7, hit) && hit.alpha > 1e-7 && hit.alpha < 1 - 1e-7) << "slab " << s;
  }
  ++t.outside;
}

}  // namespace

TEST(QueryEqualityTest, AMillionQueriesAgreeWithAReferenceEvaluation) {
  const SlabModel& m = test::baked_bunny(0, 16);
  const SlabLocator loc(m);
  const Boxes boxes = slab_boxes(m);
  const std::vector<Vec3> normals = reference_normals(m);
  // A million points (a tenth under the sanitizers, whose instrumented arithmetic is ~10x slower).
  const int half = std::getenv("HDM_SANITIZED") ? 50'000 : 500'000;
  std::mt19937 rng(2024);
  std::uniform_int_distribution<int> any_slab(0, m.slab_count() - 1);
  // Coherent walk: steps of 1e-4 of the diagonal between points near the surface of nearby slabs,
  // up to 2 % of the diagonal above or below it.
  Tally walk;
  QueryCache cache;
  test::surface_walk(m, loc, any_slab(rng), half, 0.02, rng, [&](const Vec3& p) {
    check(m, normals, boxes, query(m, loc, p, cache), p, walk);
    return !testing::Test::HasFatalFailure();
  });
  if (testing::Test::HasFatalFailure()) return;
  // Independent points, the cache reset before each.
  Tally global;
  for (int k = 0; k < half; ++k) {
    QueryCache fresh;
    const Vec3 p = test::near_surface_point(m, any_slab(rng), 0.02, rng);
    check(m, normals, boxes, query(m, loc, p, fresh), p, global);
    if (testing::Test::HasFatalFailure()) return;
  }
  EXPECT_GT(walk.inside, half / 2);
  EXPECT_GT(walk.outside, 0);
  EXPECT_GT(global.inside, half / 2);
  EXPECT_GT(global.outside, 0);
}
