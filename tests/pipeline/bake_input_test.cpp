// SPDX-License-Identifier: MIT
// The one bake of every front end, judged against analytic shapes: two boxes pushed into each
// other bake to their union (its signed distance, volume and area), in the input's own units.
#include <hdm/core/error.h>
#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/pipeline/bake_input.h>
#include <hdm/slab/scale_model.h>
#include <hdm/slab/shell_check.h>

#include "support/test_models.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <utility>

using namespace hdm;

namespace {

// An axis-aligned box [lo, hi], each face cut into k x k quads of two triangles, counter-clockwise
// seen from outside.
void add_box(TriangleMesh& m, const Vec3& lo, const Vec3& hi, int k) {
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      const int base = static_cast<int>(m.vertices.size());
      for (int i = 0; i <= k; ++i)
        for (int j = 0; j <= k; ++j) {
          Vec3 p;
          p[axis] = side ? hi[axis] : lo[axis];
          p[u] = lo[u] + (hi[u] - lo[u]) * i / k;
          p[v] = lo[v] + (hi[v] - lo[v]) * j / k;
          m.vertices.push_back(p);
        }
      for (int i = 0; i < k; ++i)
        for (int j = 0; j < k; ++j) {
          const int a = base + i * (k + 1) + j, b = a + (k + 1), c = b + 1, d = a + 1;
          // (u, v, axis) is right-handed: a, b, c winds counter-clockwise seen from +axis.
          if (side) {
            m.faces.push_back({a, b, c});
            m.faces.push_back({a, c, d});
          } else {
            m.faces.push_back({a, c, b});
            m.faces.push_back({a, d, c});
          }
        }
    }
}

// Signed distance to the box [lo, hi] (negative inside).
double box_distance(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  const Vec3 q = (p - (lo + hi) / 2).cwiseAbs() - (hi - lo) / 2;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

struct TwoBoxes {
  double scale = 3e-3;  // not a power of two: the model must come back in these units
  Vec3 offset{0.01, -0.02, 0.005};
  Vec3 a_lo{0, 0, 0}, a_hi{1, 1, 1}, b_lo{0.5, 0.25, 0.25}, b_hi{1.5, 0.75, 0.75};  // before scale and offset
  TriangleMesh mesh(int k = 12) const {
    TriangleMesh m;
    add_box(m, a_lo, a_hi, k);
    add_box(m, b_lo, b_hi, k);
    for (Vec3& p : m.vertices) p = p * scale + offset;
    return m;
  }
  double union_distance(const Vec3& p) const {
    const Vec3 q = (p - offset) / scale;
    return scale * std::min(box_distance(q, a_lo, a_hi), box_distance(q, b_lo, b_hi));
  }
  double volume() const { return std::pow(scale, 3) * (1.0 + 0.5 * 0.5 * 0.5); }
  // A's 6 faces less the 0.5 x 0.5 where B leaves it, plus B's part outside A: 4 sides and its end.
  double area() const { return scale * scale * (6.0 - 0.25 + 4 * 0.25 + 0.25); }
};

void volume_and_area(const TriangleMesh& m, double& volume, double& area) {
  volume = area = 0;
  for (const Tri& t : m.faces) {
    const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
    volume += a.dot(b.cross(c)) / 6;
    area += (b - a).cross(c - a).norm() / 2;
  }
}

// Distance to the solid cylinder x² + y² <= 1, 0 <= z <= 0.1 (its surface, both sides).
double cylinder_distance(const Vec3& p) {
  const double radial = std::hypot(p.x(), p.y()) - 1, axial = std::max(-p.z(), p.z() - 0.1);
  if (radial <= 0 && axial <= 0) return -std::max(radial, axial);
  return std::hypot(std::max(radial, 0.0), std::max(axial, 0.0));
}

}  // namespace

TEST(BakeInput, NeedleFansAreBakedFromARemeshOfTheSameSurface) {
  // The fans' needles leave slabs invalid at every slab count the input's own triangles allow
  // (one slab per triangle at most); the same surface remeshed carries valid slabs, and the
  // rays, still cast on the input, put the surface on the disk within the bound.
  const int n = 256;
  BakeInputReport report;
  const SlabModel model = bake_input(test::fan_capped_disk(n), "fan disk", {}, &report);
  const auto own = std::find_if(report.rounds.begin(), report.rounds.end(),
                                [](const ToleranceRound& r) { return r.invalid_slabs > 0; });
  ASSERT_NE(own, report.rounds.end()) << "the input's own triangles carried valid slabs: nothing to test";
  EXPECT_GT(report.remeshed_faces, 0);
  EXPECT_TRUE(report.rounds.back().met);
  EXPECT_EQ(count_invalid_slabs(model), 0);
  EXPECT_EQ(count_overlapping_pairs(model), 0);
  TriangleMesh surface;
  displaced_surface(model, surface.vertices, surface.faces);
  const double diagonal = Vec3(2, 2, 0.1).norm();
  double worst = 0;
  for (const Vec3& p : surface.vertices) worst = std::max(worst, std::abs(cylinder_distance(p)));
  // The bound is on the distance to the 256-gon the input is; the polygon's sagitta, 1 - cos(π/n),
  // is what the analytic cylinder adds.
  EXPECT_LE(100 * worst / diagonal, 0.2 + 100 * (1 - std::cos(M_PI / n)) / diagonal);
}

TEST(BakeInput, AStepThatLeavesEdgesTheBakeRefusesIsUndone) {
  // A wall of two triangles and, 0.003 in front of it, an open box of six triangles whose edges
  // face the wall (a sign on a game asset's house): joining the box's border to the wall as
  // seams leaves edges whose two triangles run the same way, which the bake refuses. The seams
  // are undone and the parts baked as they are, on their own faces.
  TriangleMesh m;
  m.vertices = {{0.65, 0, 0.95},        {0.65, 0.35, 0.95}, {0.65, 0, 0.1},         {0.1, 0.318, 0.95},
                {0.65, 0.318, 0.95},    {0.65, 0.318, 0.1}, {0.803, 0, 0.501},      {0.803, 0.0424, 0.501},
                {0.803, 0.0424, 0.701}, {0.803, 0, 0.701},  {0.653, 0.0424, 0.701}, {0.653, 0, 0.701},
                {0.653, 0.0424, 0.501}, {0.653, 0, 0.501}};
  m.faces = {{1, 0, 2}, {3, 4, 5}, {6, 7, 8}, {10, 11, 9}, {7, 12, 10}, {7, 10, 8}, {7, 6, 13}, {7, 13, 12}};
  BakeInputReport report;
  SlabModel model;
  ASSERT_NO_THROW(model = bake_input(m, "wall and sign", {}, &report));
  EXPECT_EQ(report.input.seams.inserted + report.input.seams.snapped, 0);  // undone
  EXPECT_EQ(count_invalid_slabs(model), 0);
  // Every point of the model's surface on the input (Embree, the input as given).
  TriangleMesh surface;
  displaced_surface(model, surface.vertices, surface.faces);
  const ExactMeshQuery input(m);
  const double diagonal = bounds(m).diagonal();
  double worst = 0;
  for (const Vec3& p : surface.vertices) worst = std::max(worst, input.closest_point(p).distance);
  EXPECT_LE(100 * worst / diagonal, 0.2);
}

TEST(BakeInput, TwoBoxesPushedIntoEachOtherBakeToTheirUnionInTheInputsUnits) {
  const TwoBoxes boxes;
  BakeInputReport report;
  const SlabModel model = bake_input(boxes.mesh(), "two boxes", {}, &report);
  EXPECT_GT(report.input.self_intersections, 0);
  EXPECT_GT(report.input.resolved.interior_faces, 0);  // B's faces inside A and A's inside B, dropped
  TriangleMesh surface;
  displaced_surface(model, surface.vertices, surface.faces);
  const double diagonal = boxes.scale * Vec3(1.5, 1, 1).norm();
  double worst = 0;
  for (const Vec3& p : surface.vertices) worst = std::max(worst, std::abs(boxes.union_distance(p)));
  // The bound is on the distance to the input's surface the model follows (0.2 % of the diagonal).
  EXPECT_LE(100 * worst / diagonal, 0.2 + 1e-6);
  double volume = 0, area = 0;
  volume_and_area(surface, volume, area);
  EXPECT_NEAR(volume / boxes.volume(), 1.0, 0.01);
  EXPECT_NEAR(area / boxes.area(), 1.0, 0.01);
}

TEST(BakeInput, WithoutRepairADirtyMeshIsRefusedByName) {
  // Three triangles on one edge: non-manifold, which only the repair accepts.
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  m.faces = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  BakeInputOptions o;
  o.prepare.repair = false;
  try {
    bake_input(m, "fan.obj", o);
    FAIL() << "a non-manifold mesh was baked without repair";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("fan.obj"), std::string::npos) << e.what();
  }
}

TEST(BakeInput, RefusesMeshDataWithNaNByName) {
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, NAN, 0}};
  m.faces = {{0, 1, 2}};
  try {
    bake_input(m, "nan.off");
    FAIL() << "a NaN vertex was baked";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("nan.off"), std::string::npos) << e.what();
  }
}

// BakeOptions::density counts the triangles the user gave: resolving the intersections of two
// boxes of 12 triangles each splits faces along the intersection curves (24 triangles become 40),
// which adds no detail to sample. Flat faces decimate to the target, so the slab count is it.
TEST(BakeInput, DensityCountsTheTrianglesAsGiven) {
  const TwoBoxes boxes;
  const TriangleMesh given = boxes.mesh(1);  // 24 triangles; resolved, 40
  PrepareOptions prepare;
  prepare.resolve = true;
  const int64_t prepared = static_cast<int64_t>(prepare_input(given, "two boxes", prepare).mesh.faces.size());
  const int64_t counted = std::min<int64_t>(prepared, static_cast<int64_t>(given.faces.size()));
  ASSERT_GT(prepared, static_cast<int64_t>(given.faces.size()));  // the case this test is about
  BakeInputOptions o;
  o.bounded = false;
  o.bake.grid_n = 2;  // density 4 / n² = 1 slab per triangle counted
  BakeInputReport report;
  bake_input(given, "two boxes", o, &report);
  const double target = counted * o.bake.density / (o.bake.grid_n * o.bake.grid_n);
  EXPECT_NEAR(report.bake.slabs, target, 0.05 * target);
}

// The error-bounded bake's slab cap holds for the first round, whose count the density sets.
TEST(BakeInput, TheSlabCapHoldsForTheDensitysCount) {
  const TwoBoxes boxes;
  const TriangleMesh given = boxes.mesh(8);
  BakeInputOptions o;
  o.bake.grid_n = 2;  // density 4 / n² = 1 slab per triangle: far above the cap
  o.tolerance.max_slabs = 40;
  ASSERT_GT(default_slab_count(int64_t(given.faces.size()), o.bake), 2 * o.tolerance.max_slabs);
  BakeInputReport report;
  const SlabModel model = bake_input(given, "two boxes", o, &report);
  EXPECT_LE(model.slab_count(), 40);
  for (const ToleranceRound& r : report.rounds) EXPECT_LE(r.slabs, 40);
}

// The bake's own fidelity figure is the one `hdm check` gives: both measure the points of the
// material's surface on the faces as given (the check's reference), not the bake's resolution of
// them, whose added vertices along the intersection curves would weigh the RMS differently.
TEST(BakeInput, ReportsTheInputToModelFidelityTheCheckMeasures) {
  const TwoBoxes boxes;
  BakeInputReport report;
  SlabModel model = bake_input(boxes.mesh(), "two boxes", {}, &report);
  PrepareOptions check;
  check.resolve = false;
  PreparedInput given = prepare_input(boxes.mesh(), "two boxes", check);
  scale_model(model, given.report.scale_exponent);
  const ExactMeshQuery exact(std::move(given.mesh));
  const std::vector<uint8_t> interior = interior_faces(exact);
  const std::vector<Vec3> points = surface_points(exact, &interior);
  const Fidelity f = measure_fidelity(model, exact, &points);
  EXPECT_EQ(report.fidelity.back_points, f.back_points);
  EXPECT_NEAR(report.fidelity.rms_back_pct, f.rms_back_pct, 1e-9 * f.rms_back_pct);
  EXPECT_NEAR(report.fidelity.max_back_pct, f.max_back_pct, 1e-9 * f.max_back_pct);
  // Independently: no measured point lies inside the union. A face inside it has its centroid at
  // least 1/36 of a side deep (a third of a grid cell); half that separates the two (the repair
  // welds B's vertices onto A's where they meet, and the faces there lie within 10⁻³ of a side).
  const double to_input = std::ldexp(1.0, -given.report.scale_exponent);
  for (const Vec3& p : points) EXPECT_LT(std::abs(boxes.union_distance(p * to_input)), boxes.scale / 72);
}

namespace {

// A square plate of 21 x 21 unit cells, one unit thick, with the 10 x 10 cells of odd (i, j)
// cut out: a closed, manifold surface of genus 100 with sharp edges everywhere (2,332 triangles).
TriangleMesh genus_100_plate() {
  constexpr int N = 21;
  auto solid = [](int i, int j) { return i >= 0 && j >= 0 && i < N && j < N && !(i % 2 == 1 && j % 2 == 1); };
  TriangleMesh m;
  std::map<std::array<int, 3>, int32_t> id;
  auto v = [&](int x, int y, int z) {
    const auto [it, added] = id.try_emplace({x, y, z}, static_cast<int32_t>(m.vertices.size()));
    if (added) m.vertices.emplace_back(x, y, z);
    return it->second;
  };
  auto quad = [&](int32_t a, int32_t b, int32_t c, int32_t d) {  // counter-clockwise from outside
    m.faces.push_back({a, b, c});
    m.faces.push_back({a, c, d});
  };
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) {
      if (!solid(i, j)) continue;
      quad(v(i, j, 1), v(i + 1, j, 1), v(i + 1, j + 1, 1), v(i, j + 1, 1));
      quad(v(i, j, 0), v(i, j + 1, 0), v(i + 1, j + 1, 0), v(i + 1, j, 0));
      if (!solid(i + 1, j)) quad(v(i + 1, j, 0), v(i + 1, j + 1, 0), v(i + 1, j + 1, 1), v(i + 1, j, 1));
      if (!solid(i - 1, j)) quad(v(i, j, 0), v(i, j, 1), v(i, j + 1, 1), v(i, j + 1, 0));
      if (!solid(i, j + 1)) quad(v(i, j + 1, 0), v(i, j + 1, 1), v(i + 1, j + 1, 1), v(i + 1, j + 1, 0));
      if (!solid(i, j - 1)) quad(v(i, j, 0), v(i + 1, j, 0), v(i + 1, j, 1), v(i, j, 1));
    }
  return m;
}

// Genus of a closed, connected triangle mesh from its Euler characteristic V - E + F = 2 - 2g.
int64_t genus(const std::vector<Tri>& faces) {
  std::set<int32_t> vertices;
  std::set<std::pair<int32_t, int32_t>> edges;
  for (const Tri& t : faces)
    for (int k = 0; k < 3; ++k) vertices.insert(t[k]), edges.insert(std::minmax(t[k], t[(k + 1) % 3]));
  const auto chi =
      static_cast<int64_t>(vertices.size()) - static_cast<int64_t>(edges.size()) + static_cast<int64_t>(faces.size());
  return (2 - chi) / 2;
}

}  // namespace

// A hundred handles: the slabs keep the plate's genus, and the default bake meets its bound with no
// invalid or overlapping slab; inside/outside agrees with Embree on the input near the surface.
TEST(BakeInput, AGenus100PlateKeepsItsHandles) {
  const TriangleMesh plate = genus_100_plate();
  ASSERT_EQ(genus(plate.faces), 100);
  BakeInputReport report;
  const SlabModel model = bake_input(plate, "genus-100 plate", {}, &report);
  EXPECT_TRUE(report.rounds.back().met);
  EXPECT_EQ(genus(model.slabs), 100);
  EXPECT_EQ(count_invalid_slabs(model), 0);
  EXPECT_EQ(count_overlapping_pairs(model), 0);
  const ExactMeshQuery exact(plate);
  EXPECT_GE(measure_contact(model, exact, 20000, 3, 1.0).agreement, 0.995);
}
