// SPDX-License-Identifier: MIT
// The scenario sites are found from the model's own geometry: each one is checked against the
// exact input (on the surface, inside/outside tests, ray hits) and against facts of the bunny
// (its ears are its thinnest parts and are at the top, +Y). A rotated bunny gets the same kind of
// sites, so the scenarios do not depend on the model's orientation.
#include "haptics/haptics_fixtures.h"
#include "support/test_models.h"

#include <hdm/harness/scenario_sites.h>
#include <hdm/harness/scenarios.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace hdm {
namespace {

// The paper's bunny bake (shared fixture) and the sites found on it.
struct SitesBunny {
  const SlabModel& model = test::paper_bunny().model;
  const SlabLocator& locator = test::paper_bunny().locator;
  const ExactMeshQuery& reference = test::paper_bunny().reference;
  ScenarioSites sites{reference};
  double diag = test::paper_bunny().diag;
};

const SitesBunny& sites_bunny() {
  static const SitesBunny b;
  return b;
}

// Brute-force references over every face of the input, sharing nothing with ExactMeshQuery (no
// Embree scene, no closest-point or ray primitive of the library).

Vec3 closest_on_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 d = b - a;
  const double len2 = d.squaredNorm();
  return a + (len2 > 0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0) * d;
}

// Distance from p to triangle abc: to its plane when p's projection on the plane lies inside the
// triangle (on the inner side of all three edges), else to the nearest edge.
double triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const double n2 = n.squaredNorm();
  if (n2 > 0) {
    const Vec3 q = p - (p - a).dot(n) / n2 * n;
    if ((b - a).cross(q - a).dot(n) >= 0 && (c - b).cross(q - b).dot(n) >= 0 && (a - c).cross(q - c).dot(n) >= 0)
      return (p - q).norm();
  }
  return std::min({(p - closest_on_segment(p, a, b)).norm(), (p - closest_on_segment(p, b, c)).norm(),
                   (p - closest_on_segment(p, c, a)).norm()});
}

double face_distance(const TriangleMesh& m, int32_t f, const Vec3& p) {
  const Tri& t = m.faces[f];
  return triangle_distance(p, m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]);
}

double mesh_distance(const TriangleMesh& m, const Vec3& p) {
  double best = std::numeric_limits<double>::infinity();
  for (int32_t f = 0; f < static_cast<int32_t>(m.faces.size()); ++f) best = std::min(best, face_distance(m, f, p));
  return best;
}

// The smallest t in [t_min, t_max] where the ray o + t·d (d unit) crosses a face of m
// (Möller-Trumbore per face); +inf when none does.
double first_crossing(const TriangleMesh& m, const Vec3& o, const Vec3& d, double t_min, double t_max) {
  double best = std::numeric_limits<double>::infinity();
  for (const Tri& f : m.faces) {
    const Vec3 &a = m.vertices[f[0]], e1 = m.vertices[f[1]] - a, e2 = m.vertices[f[2]] - a, pv = d.cross(e2);
    const double det = e1.dot(pv);
    if (det == 0) continue;  // parallel (or a degenerate face)
    const Vec3 tv = o - a, qv = tv.cross(e1);
    const double u = tv.dot(pv) / det, v = d.dot(qv) / det, t = e2.dot(qv) / det;
    if (u >= 0 && v >= 0 && u + v <= 1 && t >= t_min && t <= t_max) best = std::min(best, t);
  }
  return best;
}

// The header's promise for a surface point: it lies on its face, face_normal is that face's unit
// normal, and normal is the unit, barycentric interpolation of the area-weighted vertex normals
// (@p vertex_normals, summed here from the faces' cross products).
void expect_surface_point(const TriangleMesh& m, const std::vector<Vec3>& vertex_normals, const SurfacePoint& s,
                          double diag, const std::string& what) {
  ASSERT_TRUE(s.face >= 0 && s.face < static_cast<int32_t>(m.faces.size())) << what << ": face " << s.face;
  EXPECT_LT(face_distance(m, s.face, s.point), 1e-9 * diag) << what << ": not on its face";
  const Tri& t = m.faces[s.face];
  const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
  const Vec3 n = (b - a).cross(c - a);
  ASSERT_GT(n.norm(), 0.0) << what << ": on a face of no area";
  EXPECT_LT((s.face_normal - n.normalized()).norm(), 1e-9) << what << ": face normal";
  // Barycentric weights from the signed areas of the sub-triangles opposite each corner.
  const double wa = (b - s.point).cross(c - s.point).dot(n) / n.squaredNorm();
  const double wb = (c - s.point).cross(a - s.point).dot(n) / n.squaredNorm();
  const Vec3 interp =
      (wa * vertex_normals[t[0]] + wb * vertex_normals[t[1]] + (1 - wa - wb) * vertex_normals[t[2]]).normalized();
  EXPECT_NEAR(s.normal.norm(), 1.0, 1e-12) << what;
  EXPECT_LT((s.normal - interp).norm(), 1e-9) << what << ": interpolated normal";
}

std::vector<Vec3> area_weighted_vertex_normals(const TriangleMesh& m) {
  std::vector<Vec3> n(m.vertices.size(), Vec3::Zero());
  for (const Tri& t : m.faces) {
    const Vec3 w = (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]);
    for (int k = 0; k < 3; ++k) n[t[k]] += w;
  }
  for (Vec3& v : n) v.normalize();
  return n;
}

TEST(ScenarioSites, ThinSiteIsASheetInTheEars) {
  const SitesBunny& b = sites_bunny();
  const ThinSite t = b.sites.thin_site(b.model, b.locator);
  const Aabb box = bounds(test::bunny());
  EXPECT_LT(b.reference.closest_point(t.entry.point).distance, 1e-6 * b.diag);
  EXPECT_LT(b.reference.closest_point(t.exit).distance, 1e-5 * b.diag);
  EXPECT_NEAR((t.exit - t.entry.point).norm(), t.thickness, 1e-9 * b.diag);
  // A sheet: material between entry and exit, air on both sides.
  const Vec3 n = t.entry.normal;
  EXPECT_TRUE(b.reference.inside(0.5 * (t.entry.point + t.exit)));
  EXPECT_FALSE(b.reference.inside(t.entry.point + n * (0.2 * t.thickness)));
  EXPECT_FALSE(b.reference.inside(t.exit - n * (0.2 * t.thickness)));
  EXPECT_GE(t.thickness, SiteOptions{}.min_thin * b.diag);
  EXPECT_LE(t.thickness, SiteOptions{}.max_thin * b.diag);
  // The bunny's thin parts are its ears, in the top quarter of its height (+Y up).
  EXPECT_GT(t.entry.point.y(), box.max.y() - 0.25 * (box.max.y() - box.min.y()));
}

TEST(ScenarioSites, SlideStrokeLiesOnAnExposedSurfaceOverMaterial) {
  const SitesBunny& b = sites_bunny();
  const SurfaceStroke s = b.sites.slide_stroke();
  ASSERT_GE(s.points.size(), 40u);
  double len = 0;
  for (size_t i = 0; i < s.points.size(); ++i) {
    const SurfacePoint& p = s.points[i];
    EXPECT_LT(b.reference.closest_point(p.point).distance, 1e-6 * b.diag) << i;
    EXPECT_TRUE(b.reference.inside(p.point - p.normal * (0.01 * b.diag))) << i;
    EXPECT_FALSE(b.reference.inside(p.point + p.normal * (0.01 * b.diag))) << i;
    if (i > 0) len += (p.point - s.points[i - 1].point).norm();
  }
  EXPECT_NEAR(len, SiteOptions{}.stroke_length * b.diag, 0.1 * SiteOptions{}.stroke_length * b.diag);
  EXPECT_LT(s.roughness_deg, 10.0) << "a smooth stretch of the bunny";
}

TEST(ScenarioSites, EdgesSpiralCrossesManySlabs) {
  const SitesBunny& b = sites_bunny();
  const SurfaceStroke s = b.sites.edges_spiral(b.model, b.locator);
  std::set<int> slabs;
  QueryCache cache;
  for (const SurfacePoint& p : s.points) {
    EXPECT_LT(b.reference.closest_point(p.point).distance, 1e-6 * b.diag);
    const Contact c = query(b.model, b.locator, p.point, cache);
    if (c.in_shell()) slabs.insert(c.slab);
  }
  EXPECT_GE(slabs.size(), 5u) << "the spiral goes round a corner: every slab of its fan";
  EXPECT_GE(s.slab_crossings, 6);
}

// A corner the bake does not represent is not used: flatten the displacement (δ = 0, the inner
// shell) round the corner the spiral chose, so the model misses the input there; the spiral moves
// to another corner, clear of the flattened patch.
TEST(ScenarioSites, EdgesSpiralAvoidsACornerTheBakeMisses) {
  const SitesBunny& b = sites_bunny();
  const SurfaceStroke first = b.sites.edges_spiral(b.model, b.locator);
  Vec3 centre = Vec3::Zero();
  for (const SurfacePoint& p : first.points) centre += p.point;
  centre /= double(first.points.size());
  double radius = 0;
  for (const SurfacePoint& p : first.points) radius = std::max(radius, (p.point - centre).norm());
  SlabModel m = b.model;
  int flattened = 0;
  for (int s = 0; s < m.samples.count; ++s)
    if ((sample_position(m, s) - centre).norm() < 1.2 * radius) m.displacement[s] = 0.0f, ++flattened;
  ASSERT_GT(flattened, 50);
  rebuild_derived(m);
  const SlabLocator locator(m);
  const SurfaceStroke moved = b.sites.edges_spiral(m, locator);
  for (const SurfacePoint& p : moved.points)
    ASSERT_GT((p.point - centre).norm(), 1.2 * radius) << "the spiral still crosses the flattened patch";
}

// The sites are points of the input with the normals the header documents, and project() gives
// the input's closest point: all checked by brute force over the bunny's faces, at the press and
// thin sites, at points off them along their normals and at points scattered round the bunny. The
// press spot is exposed and the thin site's exit is the first face its push line crosses.
TEST(ScenarioSites, SitesAreClosestPointsOfTheInputWithItsNormals) {
  const SitesBunny& b = sites_bunny();
  const TriangleMesh& m = b.reference.mesh();
  const std::vector<Vec3> vertex_normals = area_weighted_vertex_normals(m);
  const SurfacePoint press = b.sites.press_spot();
  const ThinSite thin = b.sites.thin_site(b.model, b.locator);
  expect_surface_point(m, vertex_normals, press, b.diag, "press spot");
  expect_surface_point(m, vertex_normals, thin.entry, b.diag, "thin entry");
  EXPECT_LT(mesh_distance(m, press.point), 1e-9 * b.diag);
  EXPECT_LT(mesh_distance(m, thin.entry.point), 1e-9 * b.diag);

  // Exposed: nothing of the input along the normal from just off the surface to the clearance.
  const double clearance = SiteOptions{}.clearance * b.diag, off = 1e-3 * b.diag;
  EXPECT_EQ(first_crossing(m, press.point, press.normal, off, clearance), std::numeric_limits<double>::infinity());
  EXPECT_EQ(first_crossing(m, thin.entry.point, thin.entry.normal, off, clearance),
            std::numeric_limits<double>::infinity());
  // The push line entry - t·normal first crosses the input at the exit (the ray hits of the
  // library are float, hence the tolerance), and the far side is open.
  EXPECT_NEAR(first_crossing(m, thin.entry.point, -thin.entry.normal, off, 2 * b.diag), thin.thickness, 1e-6 * b.diag);
  EXPECT_EQ(first_crossing(m, thin.exit, -thin.entry.normal, off, clearance), std::numeric_limits<double>::infinity());

  std::vector<Vec3> queries;
  for (const SurfacePoint* s : {&press, &thin.entry})
    for (const double h : {-0.002, 0.01, 0.05}) queries.push_back(s->point + h * b.diag * s->normal);
  const Aabb box = bounds(m);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  for (int i = 0; i < 48; ++i) {
    const Vec3 r(u01(rng), u01(rng), u01(rng));
    queries.push_back(box.min + r.cwiseProduct(box.max - box.min));
  }
  for (size_t i = 0; i < queries.size(); ++i) {
    const SurfacePoint s = b.sites.project(queries[i]);
    EXPECT_NEAR((s.point - queries[i]).norm(), mesh_distance(m, queries[i]), 1e-9 * b.diag) << "query " << i;
    expect_surface_point(m, vertex_normals, s, b.diag, "projection " + std::to_string(i));
  }
}

// The bunny turned on its side (+Y to -Z): press and edges find their own sites and still meet the
// pop-through target in proxy mode. (thin is not covered here: on this rotated 150-slab bake no
// sheet passes the flatness and bake-resolution tests; see docs/haptics.md.)
TEST(ScenarioSites, ScenariosDoNotDependOnOrientation) {
  TriangleMesh m = test::bunny();
  for (Vec3& v : m.vertices) v = Vec3(-v.x(), v.z(), -v.y());  // a proper rotation (det +1)
  const test::BakedMesh b(m, "rotated bunny", 150, 16);
  ScenarioOptions o;
  o.scenario = Scenario::Press;
  const ScenarioReport p = run_scenario(b.model, b.locator, b.reference, o);
  EXPECT_EQ(p.pop_throughs, 0) << p.note;
  EXPECT_GT(p.max_force_n, 3.0) << "the press reaches the device's max force: " << p.note;
  o.scenario = Scenario::Edges;
  const ScenarioReport e = run_scenario(b.model, b.locator, b.reference, o);
  EXPECT_EQ(e.pop_throughs, 0) << e.note;
  EXPECT_GE(e.slab_crossings, 5) << e.note;
  EXPECT_LT(e.normal_error_smooth_p95_deg, 10.0) << e.note;
}

}  // namespace
}  // namespace hdm
