// SPDX-License-Identifier: MIT
// The reference itself: Embree closest point and inside test against brute force and a sphere.
#include "support/brute_force.h"
#include "support/test_models.h"

#include <hdm/mesh/exact_mesh_query.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

using namespace hdm;

TEST(ExactMeshQueryTest, ClosestPointMatchesBruteForce) {
  const TriangleMesh m = test::icosphere(3, 2.0, Vec3(1, -1, 0.5));
  const ExactMeshQuery q(m);
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-4, 4);
  for (int k = 0; k < 300; ++k) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const double best = test::brute_distance(p, m);
    EXPECT_NEAR(q.closest_point(p).distance, best, 1e-9);
    // and close to the analytic sphere distance (chord error of the tessellation)
    EXPECT_NEAR(best, std::abs((p - Vec3(1, -1, 0.5)).norm() - 2.0), 0.02);
  }
}

TEST(ExactMeshQueryTest, InsideMatchesTheSphere) {
  const Vec3 c(1, -1, 0.5);
  const ExactMeshQuery q(test::icosphere(3, 2.0, c));
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(-4, 4);
  for (int k = 0; k < 500; ++k) {
    const Vec3 p = c + Vec3(u(rng), u(rng), u(rng));
    const double r = (p - c).norm();
    if (std::abs(r - 2.0) < 0.03) continue;  // tessellation band
    EXPECT_EQ(q.inside(p), r < 2.0) << p.transpose();
  }
}

TEST(ExactMeshQueryTest, ClosestPointWithinARadiusMatchesBruteForce) {
  const TriangleMesh m = test::icosphere(3, 2.0, Vec3(1, -1, 0.5));
  const ExactMeshQuery q(m);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-4, 4), r(0.01, 1.5);
  int found = 0, none = 0;
  for (int k = 0; k < 300; ++k) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const double radius = r(rng);
    const double best = test::brute_distance(p, m);
    const ClosestPoint c = q.closest_point(p, radius);
    if (best < radius) {
      ++found;
      ASSERT_GE(c.face, 0) << "point " << k;
      EXPECT_NEAR(c.distance, best, 1e-9);
      EXPECT_NEAR((c.point - p).norm(), best, 1e-9);
    } else {
      ++none;
      EXPECT_EQ(c.face, -1) << "point " << k;
    }
  }
  EXPECT_GT(found, 20);
  EXPECT_GT(none, 20);
}

namespace {

// An open height field z = h(x, y) on a grid of [-1, 1]², faces facing +z: a ridge (h = -0.5|y|)
// or a valley (h = +0.5|y|) along the x axis, with grid lines on y = 0.
TriangleMesh height_field(double slope) {
  TriangleMesh m;
  const int k = 8;
  for (int j = 0; j <= k; ++j)
    for (int i = 0; i <= k; ++i) {
      const double x = -1 + 2.0 * i / k, y = -1 + 2.0 * j / k;
      m.vertices.emplace_back(x, y, slope * std::abs(y));
    }
  for (int j = 0; j < k; ++j)
    for (int i = 0; i < k; ++i) {
      const int a = j * (k + 1) + i, b = a + 1, c = a + k + 1, d = c + 1;
      m.faces.push_back({a, b, d});
      m.faces.push_back({a, d, c});
    }
  return m;
}

}  // namespace

// The side of a point for an open mesh uses the pseudonormal of the feature nearest to it (face,
// edge or vertex; Bærentzen & Aanæs 2005). Points straight above or below the crease have their
// nearest point on an edge; the reference is the height field itself. The heap is dirtied first,
// so a pseudonormal summed into uninitialised memory shows (it did: the answers changed from run
// to run, and with them the bake).
TEST(ExactMeshQueryTest, SideOfAnOpenSheetMatchesTheHeightFieldAtEdgesAndVertices) {
  for (const double slope : {-0.5, 0.5}) {
    const TriangleMesh m = height_field(slope);
    for (int build = 0; build < 4; ++build) {
      {
        std::vector<std::vector<double>> junk;
        for (int i = 0; i < 4000; ++i) junk.emplace_back(6, (i % 2 ? 1 : -1) * 1e30);
      }
      const ExactMeshQuery q(m);
      ASSERT_FALSE(q.closed());
      for (int i = 1; i < 8; ++i)
        for (const double y : {0.0, 0.25, 0.5, -0.25}) {  // on the crease, on grid lines, between
          for (const double h : {0.05, 0.2}) {
            const double x = -1 + 2.0 * i / 8 + (build % 2 ? 0.0 : 0.125);
            const double z = slope * std::abs(y);
            EXPECT_FALSE(q.behind(Vec3(x, y, z + h))) << "slope " << slope << " at " << x << ", " << y << " +" << h;
            EXPECT_TRUE(q.behind(Vec3(x, y, z - h))) << "slope " << slope << " at " << x << ", " << y << " -" << h;
            EXPECT_EQ(q.inside(Vec3(x, y, z - h)), q.behind(Vec3(x, y, z - h)));
          }
        }
    }
  }
}

// Every hit of a segment, in order, against a brute-force segment-triangle test: five nested
// spheres in one mesh, so a segment crosses up to ten faces. Segments that pass within 10⁻⁶ of an
// edge (barycentric), or meet two faces at t within 10⁻⁵, are skipped: either face may be reported.
TEST(ExactMeshQueryTest, SegmentHitsMatchBruteForceInOrder) {
  TriangleMesh m;
  for (int k = 1; k <= 5; ++k) {
    const TriangleMesh s = test::icosphere(2, k, Vec3(0.1, -0.2, 0.05));
    test::append(m, s);
  }
  const ExactMeshQuery q(m);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-6, 6);
  std::vector<SegmentHit> hits;
  int compared = 0, crossings = 0;
  for (int k = 0; k < 400; ++k) {
    const Vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng));
    std::vector<std::pair<double, int32_t>> want;
    bool ambiguous = false;
    for (size_t f = 0; f < m.faces.size(); ++f) {  // Möller-Trumbore in double
      const Vec3 &p0 = m.vertices[m.faces[f][0]], &p1 = m.vertices[m.faces[f][1]], &p2 = m.vertices[m.faces[f][2]];
      const Vec3 d = b - a, e1 = p1 - p0, e2 = p2 - p0, h = d.cross(e2);
      const double det = e1.dot(h);
      if (std::abs(det) < 1e-12) continue;
      const Vec3 s = a - p0, qv = s.cross(e1);
      const double v = s.dot(h) / det, w = d.dot(qv) / det, t = e2.dot(qv) / det;
      if (v < -1e-6 || w < -1e-6 || v + w > 1 + 1e-6 || t < 0 || t > 1) continue;
      if (v < 1e-6 || w < 1e-6 || v + w > 1 - 1e-6) ambiguous = true;
      want.emplace_back(t, static_cast<int32_t>(f));
    }
    std::sort(want.begin(), want.end());
    for (size_t i = 1; i < want.size(); ++i) ambiguous |= want[i].first - want[i - 1].first < 1e-5;
    if (ambiguous) continue;
    q.segment_hits(a, b, hits);
    ASSERT_EQ(hits.size(), want.size()) << a.transpose() << " -> " << b.transpose();
    for (size_t i = 0; i < want.size(); ++i) {
      EXPECT_EQ(hits[i].face, want[i].second);
      EXPECT_NEAR(hits[i].t, want[i].first, 1e-5);
    }
    ++compared;
    crossings += static_cast<int>(want.size());
  }
  EXPECT_GT(compared, 350);
  EXPECT_GT(crossings, 1000);  // most segments cross several spheres
}

namespace {

// A closed, outward axis-aligned box [lo, hi] as 12 triangles, appended to @p m.
void append_box(TriangleMesh& m, const Vec3& lo, const Vec3& hi) {
  const auto base = static_cast<int32_t>(m.vertices.size());
  for (int k = 0; k < 8; ++k)
    m.vertices.emplace_back(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(), k & 4 ? hi.z() : lo.z());
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.faces.push_back({base + q[0], base + q[1], base + q[2]});
    m.faces.push_back({base + q[0], base + q[2], base + q[3]});
  }
}

}  // namespace

// Two closed parts stacked on a shared face plane, as CAD exports put them: along a ray, the top
// of the lower part and the bottom of the upper one are met at the same point with opposite
// orientations, and cancel. The reference is the union of the two boxes.
TEST(ExactMeshQueryTest, InsideStackedPartsIsTheirUnion) {
  TriangleMesh m;
  const Vec3 lo1(0, 0, 0), hi1(2, 2, 1), lo2(0, 0.25, 1), hi2(2, 1.75, 2);
  append_box(m, lo1, hi1);
  append_box(m, lo2, hi2);
  ASSERT_GT(test::signed_volume(m), 0);
  const ExactMeshQuery q(m);
  auto in_box = [](const Vec3& p, const Vec3& lo, const Vec3& hi) {
    return (p.array() > lo.array()).all() && (p.array() < hi.array()).all();
  };
  auto near_plane = [](const Vec3& p) {
    for (int a = 0; a < 3; ++a)
      for (double c : {0.0, 0.25, 1.0, 1.75, 2.0})
        if (std::abs(p[a] - c) < 1e-3) return true;
    return false;
  };
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 3);
  int tested = 0, above_both = 0;
  for (int k = 0; k < 2000; ++k) {
    const Vec3 p(u(rng), u(rng), u(rng));
    if (near_plane(p)) continue;
    const bool expected = in_box(p, lo1, hi1) || in_box(p, lo2, hi2);
    EXPECT_EQ(q.inside(p), expected) << p.transpose();
    ++tested;
    above_both += !expected && p.x() > 0 && p.x() < 2 && p.y() > 0.25 && p.y() < 1.75 && p.z() > 2;
  }
  EXPECT_GT(tested, 1800);
  EXPECT_GT(above_both, 20);  // points whose rays cross the shared plane inside both parts' faces
}

TEST(ExactMeshQueryTest, ResultsAreTheSameWithEachOfEmbreesInstructionSets) {
  // Embree's instruction sets build different BVHs (4 wide with SSE, 8 wide with AVX) and meet
  // faces in different orders, and their float kernels round t differently. The queries must not
  // follow either: a point nearest a shared vertex gets the lowest id of the faces around it (the
  // reference: the mesh's own incidence), and the segments' hits are the same bit for bit.
  TriangleMesh m;
  for (int k = 1; k <= 3; ++k) test::append(m, test::icosphere(2, k, Vec3(0.1, -0.2, 0.05)));
  std::vector<int32_t> lowest_face(m.vertices.size(), INT32_MAX);
  for (size_t f = 0; f < m.faces.size(); ++f)
    for (int32_t v : m.faces[f]) lowest_face[v] = std::min(lowest_face[v], int32_t(f));
  const ExactMeshQuery automatic(m), sse2(m, BvhQuality::high, "isa=sse2"), sse42(m, BvhQuality::medium, "isa=sse4.2");
  const Vec3 centre(0.1, -0.2, 0.05);
  const TriangleMesh outer = test::icosphere(2, 3, centre);  // the outermost sphere's vertices
  for (size_t v = 0; v < outer.vertices.size(); ++v) {
    const int32_t id = int32_t(m.vertices.size() - outer.vertices.size() + v);
    const Vec3 p = m.vertices[id] + 0.3 * (m.vertices[id] - centre).normalized();  // nearest the vertex
    for (const ExactMeshQuery* q : {&automatic, &sse2, &sse42}) {
      const ClosestPoint c = q->closest_point(p);
      ASSERT_EQ(c.point, m.vertices[id]) << "vertex " << id;
      ASSERT_EQ(c.face, lowest_face[id]) << "vertex " << id << ": the lowest id of the faces around it";
    }
  }
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-4, 4);
  std::vector<SegmentHit> a, b, c;
  int hits = 0;
  for (int k = 0; k < 2000; ++k) {
    // Segments in general position: one exactly through a vertex may meet a different subset of
    // the faces around it with each instruction set (Embree's watertight test guarantees one).
    const Vec3 from(u(rng), u(rng), u(rng)), to(u(rng), u(rng), u(rng));
    automatic.segment_hits(from, to, a), sse2.segment_hits(from, to, b), sse42.segment_hits(from, to, c);
    ASSERT_EQ(a.size(), b.size()) << "segment " << k;
    ASSERT_EQ(a.size(), c.size()) << "segment " << k;
    for (size_t h = 0; h < a.size(); ++h) {
      ASSERT_EQ(a[h].t, b[h].t) << "segment " << k << ", hit " << h;
      ASSERT_EQ(a[h].face, b[h].face) << "segment " << k << ", hit " << h;
      ASSERT_EQ(a[h].t, c[h].t) << "segment " << k << ", hit " << h;
      ASSERT_EQ(a[h].face, c[h].face) << "segment " << k << ", hit " << h;
    }
    hits += int(a.size());
  }
  EXPECT_GT(hits, 1000);  // the comparison covered many hits
}
