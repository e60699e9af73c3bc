// SPDX-License-Identifier: MIT
// The drill brush against Archard's wear law (Archard 1953, "Contact and rubbing of flat surfaces",
// J. Appl. Phys. 24(8)), V = K·F_n·v_s·Δt / H, on a flat sheet whose removed volume is measured
// independently of the kernel (test::removed_volume). Model units are millimetres.
#include <hdm/core/error.h>
#include <hdm/edit/brush_registry.h>
#include <hdm/edit/stroke_editor.h>

#include "../support/flat_sheet.h"
#include "../support/test_models.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

namespace hdm {
namespace {

using test::flat_sheet;
using test::removed_volume;
constexpr double kUnits = test::kSheetUnits;
void locate(double x, double y, int32_t& slab, Vec3& bary) { test::locate_on_sheet(x, y, slab, bary); }

struct Drill {
  double radius = 1.5, wear = 0.01, rpm = 200000;
  // Archard's volume [mm³] for force F [N] over time t [s] on hardness hv [HV].
  double archard(double force, double t, double hv) const {
    const double speed = 2 * std::numbers::pi * rpm / 60 * (radius / kUnits);
    return wear * force * speed * t / vickers_to_pa(hv) * kUnits * kUnits * kUnits;
  }
  BrushSweep sweep(double x, double y, double force, double dt) const {
    BrushSweep sw;
    sw.brush.tool = BrushTool::Drill;
    sw.brush.radius = radius;
    sw.brush.falloff = Falloff::Smooth;
    sw.brush.wear_coefficient = wear;
    sw.brush.rpm = rpm;
    sw.from = sw.to = Vec3(x, y, 0);
    locate(x, y, sw.seed_slab, sw.seed_bary);
    sw.normal_force_n = force;
    sw.dt = dt;
    sw.units_per_metre = kUnits;
    return sw;
  }
  // Volume [mm³] @p ticks sweeps of 1 ms at (x, y) remove from @p m.
  double run(SlabModel& m, double x, double y, double force, int ticks) const {
    EditScratch scratch(m);
    std::vector<Vec3> before;
    std::vector<Tri> faces;
    displaced_surface(m, before, faces);
    for (int t = 0; t < ticks; ++t) apply_brush(m, scratch, sweep(x, y, force, 1e-3));
    return removed_volume(m, before);
  }
};

TEST(Drill, RemovedVolumeIsArchards) {
  const Drill d;
  SlabModel m = flat_sheet();
  const std::vector<float> start = test::values(m.displacement);
  const double v = d.run(m, 0.3, -0.2, 2.0, 200), ref = d.archard(2.0, 0.2, default_hardness_hv);
  std::printf("drill: 2 N, 200 ticks of 1 ms on 300 HV: removed %.6g mm3, Archard %.6g mm3 (%+.2f %%)\n", v, ref,
              100 * (v / ref - 1));
  EXPECT_NEAR(v / ref, 1.0, 0.05);
  for (size_t k = 0; k < start.size(); ++k) ASSERT_LE(m.displacement[k], start[k]);  // never raises
}

TEST(Drill, RemovalRateScalesWithTheInverseHardness) {
  const Drill d;
  SlabModel m = flat_sheet();
  // The right half is under-layer at the surface (its top above the surface): dentin-like 55 HV;
  // the left half is the surface material, enamel-like 300 HV (the defaults).
  for (int32_t s = 0; s < m.samples.count; ++s)
    if (sample_position(m, s).x() > 0) m.layer_displacement.set(s, 1.0f);
  ASSERT_EQ(m.under_layer.hardness_hv, 55.0f);
  const double enamel = d.run(m, -5, 0.1, 1.5, 100), dentin = d.run(m, 5, 0.1, 1.5, 100);
  const double expected = default_hardness_hv / m.under_layer.hardness_hv;
  std::printf("drill: 1.5 N, 100 ms: enamel %.6g mm3, dentin %.6g mm3, ratio %.4g (hardness ratio %.4g)\n", enamel,
              dentin, dentin / enamel, expected);
  EXPECT_NEAR(dentin / enamel / expected, 1.0, 0.10);
}

TEST(Drill, RemovalGrowsLinearlyWithForce) {
  const Drill d;
  std::vector<double> f, v;
  for (double force = 0.5; force <= 3.0 + 1e-9; force += 0.5) {
    SlabModel m = flat_sheet();
    f.push_back(force);
    v.push_back(d.run(m, 0.1, 0.1, force, 50));
    EXPECT_NEAR(v.back() / d.archard(force, 0.05, default_hardness_hv), 1.0, 0.05) << force;
  }
  // Least squares v = a + b·f and its R².
  const double n = double(f.size());
  double sf = 0, sv = 0, sff = 0, sfv = 0;
  for (size_t k = 0; k < f.size(); ++k) sf += f[k], sv += v[k], sff += f[k] * f[k], sfv += f[k] * v[k];
  const double b = (n * sfv - sf * sv) / (n * sff - sf * sf), a = (sv - b * sf) / n;
  double ss_res = 0, ss_tot = 0;
  for (size_t k = 0; k < f.size(); ++k) {
    ss_res += std::pow(v[k] - (a + b * f[k]), 2);
    ss_tot += std::pow(v[k] - sv / n, 2);
  }
  const double r2 = 1 - ss_res / ss_tot;
  std::printf("drill: volume over 50 ms against force 0.5-3 N: slope %.6g mm3/N, R^2 %.6f\n", b, r2);
  EXPECT_GE(r2, 0.95);
}

TEST(Drill, ZeroForceOrTimeRemovesNothing) {
  const Drill d;
  SlabModel m = flat_sheet();
  const std::vector<float> before = test::values(m.displacement);
  EditScratch scratch(m);
  EXPECT_EQ(apply_brush(m, scratch, d.sweep(0, 0, 0.0, 1e-3)).changed, 0);
  EXPECT_EQ(apply_brush(m, scratch, d.sweep(0, 0, 2.0, 0.0)).changed, 0);
  BrushSweep still = d.sweep(0, 0, 2.0, 1e-3);
  still.brush.strength = 0;  // the pedal released
  EXPECT_EQ(apply_brush(m, scratch, still).changed, 0);
  EXPECT_EQ(test::values(m.displacement), before);
}

TEST(Drill, BadParametersAreRefusedNamingThem) {
  auto refusal = [](auto set) {
    Brush b;
    b.tool = BrushTool::Drill;
    b.radius = 1;
    set(b);
    try {
      check_brush(b);
    } catch (const InvalidInput& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(refusal([](Brush&) {}), "");
  EXPECT_EQ(refusal([](Brush& b) { b.wear_coefficient = 0; }).rfind("wear_coefficient = 0: must be in (0, 1]", 0), 0u);
  EXPECT_EQ(refusal([](Brush& b) { b.wear_coefficient = 2; }).rfind("wear_coefficient = 2", 0), 0u);
  EXPECT_EQ(refusal([](Brush& b) { b.rpm = 0; }).rfind("rpm = 0: must be in (0, 1e+06]", 0), 0u);
  EXPECT_EQ(refusal([](Brush& b) { b.rpm = NAN; }).rfind("rpm = nan", 0), 0u);
  EXPECT_EQ(refusal([](Brush& b) { b.radius = -1; }).rfind("radius = -1", 0), 0u);
}

// Through the stroke editor as the servo tick drives it: the tool sample's rendered normal force
// and the workspace's scale reach the kernel; the first tick of a stroke has no elapsed time.
TEST(Drill, AStrokeRemovesArchardsVolumeAndUndoes) {
  const Drill d;
  SlabModel m = flat_sheet();
  const std::vector<float> start = test::values(m.displacement);
  std::vector<Vec3> before;
  std::vector<Tri> faces;
  displaced_surface(m, before, faces);
  StrokeEditor editor(m);
  const BrushSweep proto = d.sweep(0.2, 0.3, 1.0, 0);
  editor.begin_stroke(proto.brush);
  constexpr int kTicks = 101;
  for (int t = 0; t < kTicks; ++t) {
    ToolSample ts;
    ts.contact.slab = proto.seed_slab;
    ts.contact.coords.bary = proto.seed_bary;
    ts.contact.surface_point = proto.to;
    ts.contact.normal = Vec3::UnitZ();
    ts.hip = proto.to - 0.1 * Vec3::UnitZ();
    ts.normal_force_n = 1.0;
    ts.units_per_metre = kUnits;
    ts.time_s = 1e-3 * t;
    editor.add_sample(m, ts);
    editor.work(m, INT64_MAX);
  }
  editor.end_stroke();
  editor.work(m, INT64_MAX);
  const double v = removed_volume(m, before), ref = d.archard(1.0, 1e-3 * (kTicks - 1), default_hardness_hv);
  std::printf("drill stroke: 1 N, 100 ms: removed %.6g mm3, Archard %.6g mm3\n", v, ref);
  EXPECT_NEAR(v / ref, 1.0, 0.05);
  ASSERT_TRUE(editor.undo());
  editor.work(m, INT64_MAX);
  EXPECT_EQ(test::values(m.displacement), start);
}

// The paint brush writes the hardness field (and undo restores it); the drill then reads it.
TEST(Drill, PaintedHardnessIsReadByTheDrill) {
  SlabModel m = flat_sheet();
  EditScratch scratch(m);
  BrushSweep paint;
  paint.brush.tool = BrushTool::Paint;
  paint.brush.field = BrushField::Hardness;
  paint.brush.value = 100;
  paint.brush.radius = 4;
  paint.brush.falloff = Falloff::Constant;
  paint.from = paint.to = Vec3(0, 0, 0);
  locate(0, 0, paint.seed_slab, paint.seed_bary);
  EXPECT_GT(apply_brush(m, scratch, paint).changed, 0);
  const Drill d;
  const double v = d.run(m, 0, 0, 1.0, 50), ref = d.archard(1.0, 0.05, 100);
  EXPECT_NEAR(v / ref, 1.0, 0.05);
}

}  // namespace
}  // namespace hdm
