// SPDX-License-Identifier: MIT
// Brushes: smooth and flatten reduce measured roughness / distance to the tool's plane and never
// leave the shell, paint blends once per stroke whatever the dwell, strength and falloff scale a
// carve, and carving past the under-layer's top exposes it at that depth.
#include "edit/stroke_fixture.h"

#include <hdm/edit/edit_tools.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace hdm;

namespace {

// Mean squared normal part of the umbrella Laplacian of the surface positions ((p − mean of the grid
// neighbours)·n, n the normal of the neighbours' fan computed here) over the samples within
// `radius` of `centre`: a roughness measure on the positions alone (its tangential part only
// reflects how the grid lies on the surface).
double roughness(const SlabModel& m, const Vec3& centre, double radius) {
  const SampleLayout& L = m.samples;
  double sum = 0;
  int n = 0;
  for (int s = 0; s < L.count; ++s) {
    const Vec3 p = sample_position(m, s);
    if ((p - centre).norm() > radius) continue;
    Vec3 mean = Vec3::Zero(), normal = Vec3::Zero();
    int valence = 0;
    L.for_each_neighbour(s, [&](int32_t t) { mean += sample_position(m, t), ++valence; });
    mean /= double(valence);
    L.for_each_incident_triangle(s, [&](int32_t, const Tri& t) {
      normal += (sample_position(m, t[1]) - sample_position(m, t[0]))
                    .cross(sample_position(m, t[2]) - sample_position(m, t[0]));
    });
    sum += std::pow((p - mean).dot(normal.normalized()), 2);
    ++n;
  }
  return n ? sum / n : 0.0;
}

// A dwell: the tool held at one place (moving 0.2 mm back and forth) for `seconds`.
void dwell(test::BunnyStrokes& f, StrokeEditor& editor, const Brush& brush, const Vec3& centre, const Vec3& normal,
           double seconds, double force_n) {
  std::vector<Vec3> points, normals;
  const Vec3 side = normal.cross(Vec3::UnitX()).normalized() * 0.2 * f.mm;
  const int n = static_cast<int>(seconds / 1e-3);
  for (int k = 0; k < n; ++k) {
    points.push_back(centre + side * std::sin(k * 0.01));
    normals.push_back(normal);
  }
  f.stroke(editor, brush, points, normals, 0.5 * f.mm, 1e-3, force_n);
}

// A relaxing brush (smooth, flatten) at full strength with the smooth falloff, held for `seconds`.
void relax(test::BunnyStrokes& f, BrushTool tool, const Vec3& c, const Vec3& n, double r, double seconds) {
  StrokeEditor editor(f.model);
  Brush b;
  b.tool = tool;
  b.radius = r;
  b.strength = 1;
  b.falloff = Falloff::Smooth;
  dwell(f, editor, b, c, n, seconds, 1.0);  // at full pressure
}

// A point on the surface near the normalised box point u, and the model's normal there.
Vec3 site(const test::BunnyStrokes& f, const Vec3& u, Vec3& normal) {
  const Vec3 c = f.surface_point(u);
  QueryCache cache;
  normal = query(f.model, f.locator, c, cache).normal;
  return c;
}

void expect_in_shell_and_untouched_outside(const SlabModel& after, const SlabModel& before, const Vec3& centre,
                                           double radius) {
  for (int s = 0; s < after.samples.count; ++s) {
    ASSERT_TRUE(after.displacement[s] >= 0.0f && after.displacement[s] <= 1.0f) << s;
    if ((sample_position(before, s) - centre).norm() > radius * 1.5) {
      ASSERT_EQ(after.displacement[s], before.displacement[s]) << "sample " << s << " outside the brush moved";
    }
  }
}

}  // namespace

TEST(Brushes, SmoothReducesRoughnessAndStaysInTheShell) {
  test::BunnyStrokes f;
  Vec3 n;
  const Vec3 c = site(f, Vec3(0.35, 0.3, 1.0), n);  // the rough fur of the hind leg
  const double r = 4 * f.mm;
  const double before = roughness(f.model, c, 0.6 * r);
  relax(f, BrushTool::Smooth, c, n, r, 1.0);
  const double after = roughness(f.model, c, 0.6 * r);
  std::printf("smooth: roughness %.3g -> %.3g\n", before, after);
  EXPECT_LT(after, 0.6 * before);
  expect_in_shell_and_untouched_outside(f.model, test::baked_bunny(0, 16), c, r);
}

TEST(Brushes, FlattenMovesTheSurfaceTowardsTheToolsPlane) {
  test::BunnyStrokes f;
  Vec3 n;
  const Vec3 c = site(f, Vec3(0.6, 0.5, 1.0), n);
  const double r = 5 * f.mm;
  auto plane_rms = [&](const SlabModel& m) {  // about the plane through c normal to n, within 0.5 r
    double sum = 0;
    int k = 0;
    for (int s = 0; s < m.samples.count; ++s) {
      const Vec3 p = sample_position(m, s);
      if ((p - c).norm() > 0.5 * r) continue;
      sum += std::pow((p - c).dot(n), 2), ++k;
    }
    return std::sqrt(sum / k);
  };
  const double before = plane_rms(f.model);
  relax(f, BrushTool::Flatten, c, n, r, 0.5);
  const double after = plane_rms(f.model);
  std::printf("flatten: RMS distance to the plane %.3g -> %.3g mm\n", before / f.mm, after / f.mm);
  EXPECT_LT(after, 0.5 * before);
  expect_in_shell_and_untouched_outside(f.model, test::baked_bunny(0, 16), c, r);
}

// A paint brush of @p field with linear falloff, radius 3 mm.
Brush linear_paint(const test::BunnyStrokes& f, BrushField field, float value) {
  Brush paint;
  paint.tool = BrushTool::Paint;
  paint.field = field;
  paint.value = value;
  paint.radius = 3 * f.mm;
  paint.falloff = Falloff::Linear;
  return paint;
}

// The largest linear-falloff intensity 1 − d/r that the logged sweeps reached at @p p, d the
// distance from @p p to each sweep's segment.
double k_max(const std::vector<EditLogEntry>& log, const Vec3& p, double radius) {
  double k = 0;
  for (const EditLogEntry& e : log)
    if (e.kind == EditLogEntry::Sweep) {
      const Vec3 u = e.sweep.to - e.sweep.from;
      const double t = u.squaredNorm() > 0 ? std::clamp((p - e.sweep.from).dot(u) / u.squaredNorm(), 0.0, 1.0) : 0.0;
      k = std::max(k, std::max(0.0, 1 - (p - e.sweep.from - t * u).norm() / radius));
    }
  return k;
}

TEST(Brushes, PaintBlendsOncePerStrokeWhateverTheDwell) {
  // The paper's blend k·value + (1 − k)·base with k = pressure·strength·falloff(d/r), d the distance
  // from the sample to the brush's path, once per stroke (the largest k the stroke reached): a brush
  // held still for 10 ms or 300 ms gives the same field, bit for bit.
  std::vector<Half16> results[2];
  for (int run = 0; run < 2; ++run) {
    test::BunnyStrokes f;
    Vec3 n;
    const Vec3 c = site(f, Vec3(0.6, 0.5, 1.0), n);
    StrokeEditor editor(f.model);
    std::vector<EditLogEntry> log;
    log.reserve(1000);
    editor.record_log(&log);
    const Brush paint = linear_paint(f, BrushField::FrictionStatic, 0.9f);
    const int ticks = run == 0 ? 10 : 300;
    f.stroke(editor, paint, std::vector<Vec3>(ticks, c), std::vector<Vec3>(ticks, n), 0.5 * f.mm, 1e-3, 10.0);
    results[run] = f.model.friction_static.codes();
    const SlabModel& before = test::baked_bunny(0, 16);
    int painted = 0;
    for (int s = 0; s < f.model.samples.count; ++s) {
      const double k = k_max(log, sample_position(f.model, s), paint.radius);
      const double expected = before.friction_static[s] + k * (0.9 - before.friction_static[s]);
      // Stored as binary16: half a step below 1 is 2^-12 (2.4e-4), plus the blend's float rounding.
      ASSERT_NEAR(f.model.friction_static[s], expected, 2.5e-4) << "sample " << s;
      painted += k > 0.5;
    }
    EXPECT_GT(painted, 20);
  }
  EXPECT_TRUE(results[0] == results[1]) << "a longer dwell must not paint more";
}

TEST(Brushes, PaintOf8BitTexelsDoesNotDriftOverManyTicks) {
  // A stroke creeping 300 ticks towards its end raises k at the texels ahead of it on nearly every
  // tick; each texel must still end at base + k_max·(value − base) rounded once to 8 bits, within
  // one code step (blending from the already rounded value would compound the rounding).
  for (const BrushField field : {BrushField::Colour, BrushField::Roughness}) {
    test::BunnyStrokes f;
    Vec3 n;
    const Vec3 c = site(f, Vec3(0.6, 0.5, 1.0), n);
    const Vec3 along = n.cross(std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).normalized();
    StrokeEditor editor(f.model);
    std::vector<EditLogEntry> log;
    log.reserve(1000);
    editor.record_log(&log);
    Brush paint = linear_paint(f, field, 0.1f);
    paint.colour = Vec3f(0.9f, 0.05f, 0.3f);
    const int ticks = 300;
    std::vector<Vec3> path;
    for (int k = 0; k < ticks; ++k) path.push_back(c + (2 * f.mm * k / ticks) * along);
    f.stroke(editor, paint, path, std::vector<Vec3>(ticks, n), 0.5 * f.mm, 1e-3, 10.0);
    const SlabModel& before = test::baked_bunny(0, 16);
    int checked = 0;
    test::for_each_sample_texel(f.model, [&](int s, int t) {
      const double k = k_max(log, sample_position(f.model, s), paint.radius);
      if (field == BrushField::Roughness) {
        const double base = before.roughness[t] / 255.0;
        ASSERT_LE(std::abs(f.model.roughness[t] - 255 * (base + k * (paint.value - base))), 1.0) << t;
      } else {
        const int got[3] = {f.model.colour[t].r, f.model.colour[t].g, f.model.colour[t].b};
        const int was[3] = {before.colour[t].r, before.colour[t].g, before.colour[t].b};
        for (int q = 0; q < 3; ++q) {
          const double base = srgb8_to_linear(uint8_t(was[q]));
          ASSERT_LE(std::abs(got[q] - test::srgb_code(base + k * (paint.colour[q] - base))), 1.0)
              << "texel " << t << " channel " << q;
        }
      }
      checked += k > 0.2 && k < 0.9;
    });
    EXPECT_GT(checked, 10);
  }
}

TEST(Brushes, StrengthScalesTheCut) {
  double depth[2];
  for (int run = 0; run < 2; ++run) {
    test::BunnyStrokes f;
    Vec3 n;
    const Vec3 c = site(f, Vec3(0.6, 0.5, 1.0), n);
    StrokeEditor editor(f.model);
    Brush carve;
    carve.tool = BrushTool::Carve;
    carve.radius = 3 * f.mm;
    carve.strength = run == 0 ? 1.0 : 0.5;
    std::vector<Vec3> points(50, c), normals(50, n);
    f.stroke(editor, carve, points, normals, 1.0 * f.mm);
    // The deepest cut along the normal (the tool's bottom sits 1 mm under the surface).
    depth[run] = 0;
    for (int s = 0; s < f.model.samples.count; ++s)
      depth[run] =
          std::max(depth[run], (sample_position(test::baked_bunny(0, 16), s) - sample_position(f.model, s)).dot(n));
    std::printf("strength %.1f: cut %.3f mm\n", carve.strength, depth[run] / f.mm);
  }
  EXPECT_NEAR(depth[0], 1.0 * test::BunnyStrokes().mm,
              0.25 * test::BunnyStrokes().mm);  // the HIP 1 mm under the surface
  EXPECT_NEAR(depth[1] / depth[0], 0.5, 0.08);
}

TEST(Layers, CarvingExposesTheUnderLayerAtItsDepth) {
  test::BunnyStrokes f;
  const double t = 0.5 * f.mm;
  set_under_layer(f.model, t, UnderLayer{});
  const SlabModel before = f.model;
  StrokeEditor editor(f.model);
  Brush carve;
  carve.tool = BrushTool::Carve;
  carve.radius = 3 * f.mm;
  std::vector<Vec3> points, normals;
  f.surface_path(f.surface_point(Vec3(0.5, 0.45, 1.0)), f.surface_point(Vec3(0.75, 0.42, 1.0)), 0.02 * f.mm, points,
                 normals);
  f.stroke(editor, carve, points, normals, 1.0 * f.mm);  // a groove 1 mm deep: through the layer's top
  int exposed = 0, checked = 0;
  for (int s = 0; s < f.model.samples.count; ++s) {
    if (f.model.displacement[s] == before.displacement[s]) {
      ASSERT_GE(f.model.displacement[s], f.model.layer_displacement[s]) << "uncarved sample " << s << " exposed";
      continue;
    }
    // Depth of the cut along the surface normal (independent of the layer's representation).
    const double cut =
        (sample_position(before, s) - sample_position(f.model, s)).dot(sample_normal(before, s).cast<double>());
    const bool is_exposed = f.model.displacement[s] < f.model.layer_displacement[s];
    if (std::abs(cut - t) < 0.05 * t) continue;  // at the layer's top itself: either
    EXPECT_EQ(is_exposed, cut > t) << "sample " << s << " cut " << cut / f.mm << " mm";
    exposed += is_exposed, ++checked;
  }
  EXPECT_GT(checked, 200);
  EXPECT_GT(exposed, 50);
}
