// SPDX-License-Identifier: MIT
// Undo / redo per stroke: bit-exact round trips of every stored and derived array over random
// strokes of every brush and field, the memory cap, and replaying an edit log.
#include "edit/stroke_fixture.h"

#include <hdm/slab/slab_snapshots.h>

#include <gtest/gtest.h>

#include <memory>
#include <random>

using namespace hdm;

namespace {

// A random stroke: a short path between two random surface points of the flank, a random brush.
Brush random_brush(std::mt19937& rng, double mm) {
  Brush b;
  b.radius = (1.5 + rng() % 3) * mm;
  switch (rng() % 10) {
    case 0:
      b.tool = BrushTool::Carve, b.resilience = 0.2 * mm;
      break;
    case 1:
      b.tool = BrushTool::Carve, b.strength = 0.5, b.falloff = Falloff::Smooth;
      break;
    case 2:
      b.tool = BrushTool::Add, b.height = 0.6 * mm;
      break;
    case 3:
      b.tool = BrushTool::Smooth, b.strength = 1, b.falloff = Falloff::Smooth;
      break;
    case 4:
      b.tool = BrushTool::Flatten, b.strength = 1, b.falloff = Falloff::Linear;
      break;
    case 5:
      b.tool = BrushTool::Paint, b.field = BrushField::Colour, b.colour = Vec3f(0.1f, 0.9f, 0.2f);
      break;
    case 6:
      b.tool = BrushTool::Paint, b.field = BrushField::Roughness, b.value = 0.1f;
      break;
    case 7:
      b.tool = BrushTool::Paint, b.field = BrushField::FrictionStatic, b.value = 0.9f;
      break;
    case 8:
      b.tool = BrushTool::Paint, b.field = BrushField::Stiffness, b.value = 0.3f;
      break;
    default:
      b.tool = BrushTool::Paint, b.field = BrushField::LayerThickness, b.value = float(0.5 * mm);
      break;
  }
  return b;
}

void random_stroke(test::BunnyStrokes& f, StrokeEditor& editor, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.4, 0.8), v(0.3, 0.7), d(-0.08, 0.08);
  const Vec3 ua(u(rng), v(rng), 1.0), ub = ua + Vec3(d(rng), d(rng), 0);
  std::vector<Vec3> points, normals;
  f.surface_path(f.surface_point(ua), f.surface_point(ub), 0.05 * f.mm, points, normals);
  f.stroke(editor, random_brush(rng, f.mm), points, normals, 0.8 * f.mm, 2e-3);
}

}  // namespace

TEST(Undo, RandomStrokesUndoAndRedoBitForBit) {
  test::BunnyStrokes f;
  StrokeEditor editor(f.model);
  std::mt19937 rng(11);
  std::vector<test::ModelState> states{test::ModelState(f.model)};
  constexpr int kStrokes = 14;
  for (int k = 0; k < kStrokes; ++k) {
    random_stroke(f, editor, rng);
    states.emplace_back(f.model);
    ASSERT_NE(test::first_difference(states[k], states[k + 1]), "") << "stroke " << k << " changed nothing";
  }
  ASSERT_EQ(editor.history().undo_count(), kStrokes);
  // Undo one at a time: each step restores the state before that stroke exactly.
  for (int k = kStrokes; k > 0; --k) {
    ASSERT_TRUE(editor.undo());
    editor.work(f.model, INT64_MAX);
    ASSERT_EQ(test::first_difference(test::ModelState(f.model), states[k - 1]), "") << "after undoing stroke " << k - 1;
  }
  EXPECT_FALSE(editor.history().can_undo());
  for (int k = 1; k <= kStrokes; ++k) {
    ASSERT_TRUE(editor.redo());
    editor.work(f.model, INT64_MAX);
    ASSERT_EQ(test::first_difference(test::ModelState(f.model), states[k]), "") << "after redoing stroke " << k - 1;
  }
  // Undo three, then a new stroke: the undone strokes can no longer be redone.
  for (int k = 0; k < 3; ++k) editor.undo();
  editor.work(f.model, INT64_MAX);
  EXPECT_EQ(editor.history().redo_count(), 3);
  random_stroke(f, editor, rng);
  EXPECT_EQ(editor.history().redo_count(), 0);
  EXPECT_EQ(editor.history().undo_count(), kStrokes - 3 + 1);
}

TEST(Undo, TheMemoryCapForgetsTheOldestStrokes) {
  test::BunnyStrokes f;
  StrokeEditorOptions o;
  o.undo_cap_bytes = 48 * 1024;  // about 2,000 records
  StrokeEditor editor(f.model, o);
  std::mt19937 rng(5);
  std::vector<test::ModelState> states{test::ModelState(f.model)};
  for (int k = 0; k < 10; ++k) {
    random_stroke(f, editor, rng);
    states.emplace_back(f.model);
    EXPECT_LE(editor.history().records_held() * sizeof(UndoRecord), o.undo_cap_bytes);
  }
  const int kept = editor.history().undo_count();
  EXPECT_LT(kept, 10) << "the cap must have dropped strokes";
  EXPECT_GT(editor.history().strokes_dropped(), 0);
  // Undoing every kept stroke leaves the state after the last dropped one, bit for bit.
  while (editor.history().can_undo()) {
    editor.undo();
    editor.work(f.model, INT64_MAX);
  }
  if (kept > 0) {
    EXPECT_EQ(test::first_difference(test::ModelState(f.model), states[10 - kept]), "");
  }
}

TEST(Undo, AStrokeLargerThanTheCapCannotBeUndone) {
  test::BunnyStrokes f;
  StrokeEditorOptions o;
  o.undo_cap_bytes = 2400;  // 100 records
  StrokeEditor editor(f.model, o);
  std::vector<Vec3> points, normals;
  f.surface_path(f.surface_point(Vec3(0.45, 0.45, 1.0)), f.surface_point(Vec3(0.75, 0.42, 1.0)), 0.1 * f.mm, points,
                 normals);
  Brush carve;
  carve.tool = BrushTool::Carve;
  carve.radius = 3 * f.mm;
  f.stroke(editor, carve, points, normals, 1.0 * f.mm);
  EXPECT_FALSE(editor.history().can_undo());
  const test::ModelState after(f.model);
  editor.undo();  // nothing to undo: the model stays as it is
  editor.work(f.model, INT64_MAX);
  EXPECT_EQ(test::first_difference(test::ModelState(f.model), after), "");
}

namespace {
// The edit log of @p strokes random strokes (seed @p seed) on f's model, then an undo.
std::vector<EditLogEntry> logged_strokes(test::BunnyStrokes& f, int strokes, unsigned seed) {
  StrokeEditor editor(f.model);
  std::vector<EditLogEntry> log;
  log.reserve(100000);
  editor.record_log(&log);
  std::mt19937 rng(seed);
  for (int k = 0; k < strokes; ++k) random_stroke(f, editor, rng);
  editor.undo();
  editor.work(f.model, INT64_MAX);
  return log;
}
}  // namespace

TEST(Undo, ReplayingTheEditLogReproducesTheModel) {
  test::BunnyStrokes f, copy;
  const std::vector<EditLogEntry> log = logged_strokes(f, 6, 3);
  StrokeEditor replayer(copy.model);
  for (const EditLogEntry& e : log) {
    ASSERT_TRUE(replayer.replay(e));
    replayer.work(copy.model, INT64_MAX);
  }
  EXPECT_EQ(test::first_difference(test::ModelState(copy.model), test::ModelState(f.model)), "");
}

// An edit log replayed through a write gate that refuses (SlabSnapshots with its smallest pool and
// a reader holding the first epoch for a while): each refused edit stops before the
// write and resumes where it stopped after a commit, so the model ends bit for bit the same, and
// a reader pinned before the edits still reads the unedited slabs.
TEST(WriteGate, ReplayingThroughRefusalsReproducesTheModel) {
  test::BunnyStrokes f, copy;
  const std::vector<EditLogEntry> log = logged_strokes(f, 4, 5);

  const test::ModelState unedited(copy.model);
  SnapshotOptions o;
  o.spare_versions = 1;  // raised to one more than the most slabs around a coarse vertex
  SlabSnapshots snapshots(copy.model, o);
  auto pinned = std::make_unique<SnapshotReader>(snapshots);
  StrokeEditor replayer(copy.model);
  EditScratch& s = replayer.scratch();
  s.gate = WriteGate{[](void* u, int32_t slab) noexcept { return static_cast<SlabSnapshots*>(u)->before_write(slab); },
                     &snapshots};
  int64_t refusals = 0, commits = 0;
  auto work = [&] {
    for (;;) {
      const EditWork w = replayer.work(copy.model, INT64_MAX);
      if (!w.refused) return;
      ++refusals;
      ASSERT_TRUE(snapshots.starved()) << "no reader copies a slab here: only the pool refuses";
      if (refusals == 40) {  // the first epoch's reader checks what it sees, then lets go
        for (int slab = 0; slab < copy.model.slab_count(); slab += 37) {
          const SlabView v = pinned->slab(slab);
          for (int k = 0; k < copy.model.samples.per_slab; ++k)
            ASSERT_EQ(v.points[k].delta, unedited.displacement[size_t(copy.model.samples.id(slab, k))]);
        }
        pinned.reset();
      }
      snapshots.publish_commit();  // a sweep committed in parts: the versions return to the pool
      clear_dirty(s);
      ++commits;
    }
  };
  for (const EditLogEntry& e : log) {
    ASSERT_TRUE(replayer.replay(e));
    work();
  }
  std::printf("%lld refusals, %lld commits\n", (long long)refusals, (long long)commits);
  EXPECT_GT(refusals, 40);
  EXPECT_EQ(test::first_difference(test::ModelState(copy.model), test::ModelState(f.model)), "");
}
