// SPDX-License-Identifier: MIT
// Concurrency stress test: the servo loop at 10 kHz edits on every tick (carve, add, smooth, paint
// strokes from the tool button; undo and redo posted from a control thread) while two renderer
// threads rebuild the vertices of the slabs that changed from snapshots and a saver thread saves
// (and, with hdm::io, exports) snapshots again and again. Checked: every version read passes its
// checksum (no torn slab), shared samples agree between the slabs of one snapshot, every file
// written loads, and each equals, bit for bit, the model obtained by replaying the edit log up to
// the epoch it was saved at (a state that existed). Built with -fsanitize=thread by
// scripts/test_tsan.sh, where it must run clean.
#include <hdm/io/hdm_file.h>
#include <hdm/session/sculpt_session.h>
#include <hdm/slab/triangle_grid.h>

#include "mouse_device.h"
#include "servo_thread.h"
#ifdef HDM_TEST_EXPORT
#include <hdm/io/export_mesh.h>
#endif

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>
#include <thread>

namespace hdm {
namespace {

// A sphere shell built by hand (no bake): an octahedron split 1-to-4 three times, pushed onto the
// unit sphere, inner and outer shells at 0.9 and 1.1, the surface halfway.
SlabModel sphere_shell(int n = 8) {
  std::vector<Vec3> v = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  std::vector<Tri> f = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  for (int level = 0; level < 3; ++level) {
    std::map<std::pair<int, int>, int> mid;
    auto half = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      if (const auto it = mid.find(key); it != mid.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      return mid[key] = static_cast<int>(v.size()) - 1;
    };
    std::vector<Tri> next;
    for (const Tri& t : f) {
      const int a = half(t[0], t[1]), b = half(t[1], t[2]), c = half(t[2], t[0]);
      next.insert(next.end(), {Tri{t[0], a, c}, Tri{a, t[1], b}, Tri{c, b, t[2]}, Tri{a, b, c}});
    }
    f = std::move(next);
  }
  SlabModel m;
  m.grid_n = n;
  m.texel_density = 2;
  for (const Vec3& p : v) m.inner.push_back(0.9 * p), m.outer.push_back(1.1 * p);
  m.slabs = f;
  m.samples = build_sample_layout(m.slabs, m.coarse_vertex_count(), n);
  m.displacement.assign(m.samples.count, 0.5f);
  m.source = "sphere shell (built by the test)";
  m.source_diagonal = 2 * std::sqrt(3.0);
  rebuild_derived(m);
  return m;
}

struct Plan {
  std::vector<Vec3> target;
  std::vector<uint32_t> button;
  std::vector<int16_t> stroke;
};

// Strokes over the sphere at 10 kHz: each presses in, slides 0.6 rad and lifts, with a brush of
// its own (the device frame: 1 model unit = 0.1 m).
Plan plan(int strokes, double seconds_each) {
  Plan p;
  auto on = [](double az, double pol, double r) -> Vec3 {
    return Vec3(std::sin(pol) * std::cos(az), std::sin(pol) * std::sin(az), std::cos(pol)) * (0.1 * r);
  };
  auto add = [&](const Vec3& to, int n, int s) {
    const Vec3 from = p.target.empty() ? to : p.target.back();
    for (int k = 1; k <= n; ++k) {
      p.target.push_back(from + (to - from) * (double(k) / n));
      p.button.push_back(s >= 0);
      p.stroke.push_back(static_cast<int16_t>(s));
    }
  };
  for (int s = 0; s < strokes; ++s) {
    const double az = 0.9 * s, pol = 0.6 + 0.3 * (s % 4);
    add(on(az, pol, 1.1), 1000, -1);
    add(on(az, pol, 0.96), 1000, s);
    add(on(az + 0.6, pol + 0.2, 0.96), static_cast<int>(seconds_each * 1e4), s);
    add(on(az + 0.6, pol + 0.2, 1.1), 1000, -1);
  }
  return p;
}

Brush brush(int s) {
  Brush b;
  b.radius = 0.12;
  switch (s % 4) {
    case 0:
      b.tool = BrushTool::Carve;
      break;
    case 1:
      b.tool = BrushTool::Add, b.height = 0.02;
      break;
    case 2:
      b.tool = BrushTool::Smooth, b.falloff = Falloff::Smooth;
      break;
    default:
      b.tool = BrushTool::Paint, b.field = BrushField::Colour, b.colour = Vec3f(0.9f, 0.2f, 0.1f);
      break;
  }
  b.pressure_force_n = 0.3;
  return b;
}

constexpr int kStrokes = 8;  // strokes of the plan, one brush each

struct Hooks {
  const Plan* plan;
  int16_t set = -1;
  std::array<int64_t, kStrokes> sweeps_of_stroke{};  ///< sweeps finished while (or after) each stroke ran
  std::atomic<int64_t> ticks{0};                     ///< ticks run, for the control thread
};
void before(void* user, SculptSession& session, const ServoTick& t) noexcept {
  auto& h = *static_cast<Hooks*>(user);
  const int16_t s = h.plan->stroke[std::min<size_t>(static_cast<size_t>(t.tick), h.plan->stroke.size() - 1)];
  if (s >= 0 && s != h.set) session.set_brush(brush(h.set = s));
}
void after(void* user, const ServoTick& t, const SessionTick& result) noexcept {
  auto& h = *static_cast<Hooks*>(user);
  if (h.set >= 0) h.sweeps_of_stroke[static_cast<size_t>(h.set) % kStrokes] += result.sweeps;
  h.ticks.store(t.tick + 1, std::memory_order_relaxed);
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}
template <class T>
bool same_bits(const SampleField<T>& a, const SampleField<T>& b) {
  return same_bits(a.codes(), b.codes());
}

std::string stored_difference(const SlabModel& a, const SlabModel& b) {
  if (!same_bits(a.displacement, b.displacement)) return "displacement";
  if (!same_bits(a.colour, b.colour)) return "colour";
  if (!same_bits(a.roughness, b.roughness)) return "roughness";
  if (!same_bits(a.friction_static, b.friction_static)) return "friction_static";
  if (!same_bits(a.friction_dynamic, b.friction_dynamic)) return "friction_dynamic";
  if (!same_bits(a.stiffness_scale, b.stiffness_scale)) return "stiffness_scale";
  if (!same_bits(a.layer_displacement, b.layer_displacement)) return "layer_displacement";
  return "";
}

}  // namespace

TEST(Concurrency, ServoEditsWhileRenderersAndASaverReadSnapshots) {
  const SlabModel initial = sphere_shell();
  const Plan p = plan(kStrokes, 0.25);
  SessionOptions o;
  o.proxy.force.damping = 0.5;
  o.publish_interval_s = 0.002;
  o.snapshots.checksums = true;
  o.snapshots.reader_slots = 4;
  // A version per slab: no sweep is ever committed in parts (it would need half of them), so every
  // file saved is a state the edit log's replay reaches. Slow readers still make edits wait.
  o.snapshots.spare_versions = initial.slab_count();
  o.edit_budget_s = 40e-6;
  SculptSession session(initial, Workspace{Vec3::Zero(), 10.0}, o);
  std::vector<EditLogEntry> edits;
  std::vector<size_t> epochs;
  edits.reserve(p.target.size() + 1024);
  epochs.reserve(1 << 16);
  session.record_log(&edits, &epochs);

  const SlabSnapshots& snaps = *session.snapshots();
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "hdm_concurrency_test";
  std::filesystem::create_directories(dir);
  std::atomic<bool> done{false};
  std::atomic<int64_t> torn{0}, seams{0}, reuploads{0}, bad_vertices{0};
  std::mutex saved_mutex;
  std::vector<std::pair<uint64_t, std::string>> saved;  // (epoch, file)

  auto renderer = [&] {
    const SlabModel& statics = snaps.model();
    const int S = statics.slab_count(), P = statics.samples.per_slab;
    std::vector<uint64_t> uploaded(S, ~0ull);
    std::vector<float> vertices(static_cast<size_t>(P) * 3);
    while (!done.load()) {
      SnapshotReader r(snaps);
      for (int s = 0; s < S; ++s) {
        const SlabView v = r.slab(s);
        if (v.epoch == uploaded[s]) continue;
        // The vertices a renderer uploads: positions on the projection lines, normals.
        for (int k = 0; k < P; ++k) {
          Vec3 p0, p1;
          projection_line(statics, s, k, p0, p1);
          const Vec3 x = p0 + double(v.points[k].delta) * (p1 - p0);
          for (int c = 0; c < 3; ++c) vertices[3 * k + c] = static_cast<float>(x[c]);
          if (!x.allFinite() || !(v.points[k].delta >= 0 && v.points[k].delta <= 1)) ++bad_vertices;
        }
        uploaded[s] = v.epoch;
        ++reuploads;
        if (!r.verify(s)) ++torn;  // (the view above lasts until this call)
      }
      // One snapshot: a sample shared by several slabs has one value in all of them.
      for (int32_t id = 0; id < statics.samples.first_interior; id += 3)
        statics.samples.for_each_slot(id, [&](int32_t slot) {
          const int slab = slot / P, k = slot % P;
          const float at_home = r.slab(statics.samples.home(id).slab).points[statics.samples.home(id).index].delta;
          if (r.slab(slab).points[k].delta != at_home) ++seams;
        });
      std::this_thread::yield();
    }
  };
  auto saver = [&] {
    for (int k = 0; !done.load(); ++k) {
      SlabModel copy;
      uint64_t epoch;
      {
        SnapshotReader r(snaps);
        epoch = r.epoch();
        copy = r.stored_model();
      }
      const std::string path = (dir / ("save_" + std::to_string(k) + ".hdm")).string();
      save_model(copy, path);
#ifdef HDM_TEST_EXPORT
      if (k % 4 == 0) {  // an export of the same snapshot
        rebuild_derived(copy);
        export_mesh(copy, (dir / ("export_" + std::to_string(k) + ".ply")).string());
      }
#endif
      std::lock_guard<std::mutex> lock(saved_mutex);
      saved.emplace_back(epoch, path);
    }
  };
  // Undo and redo from the user's other hand, off the servo thread, every 150 ms but only while
  // the tool button is up with at least 500 ticks of the gap left: an undo while the button is
  // held ends that stroke (tested with the editor), which would leave how much each stroke edits
  // to the threads' timing.
  Hooks hooks{&p};
  std::vector<uint8_t> gap(p.button.size(), 0);
  for (size_t k = 0; k + 500 < p.button.size(); ++k)
    gap[k] = std::all_of(p.button.begin() + k, p.button.begin() + k + 500, [](uint32_t b) { return b == 0; });
  auto control = [&] {
    for (int k = 0; !done.load(); ++k) {
      std::this_thread::sleep_for(std::chrono::milliseconds(150));
      for (;;) {
        const auto t = static_cast<size_t>(hooks.ticks.load(std::memory_order_relaxed));
        if (done.load() || (t < gap.size() && gap[t])) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
      session.post(SessionCommand{k % 3 == 2 ? SessionCommand::Redo : SessionCommand::Undo, {}, {}});
    }
  };
  std::thread r1(renderer), r2(renderer), s1(saver), c1(control);

  SimulatedDeviceOptions d;
  d.rate_hz = 10000;
  SimulatedDevice device(d, p.target, p.target.front(), p.button);
  ServoOptions so;
  so.rate_hz = 10000;
  so.ticks = static_cast<int64_t>(p.target.size());
  so.watchdog_ticks = 1 << 30;  // sanitizer builds run slowly; the envelope is tested elsewhere
  const ServoStats st = run_session(session, device, so, SessionHooks{before, after, &hooks});
  // Under a loaded sanitizer run the saver may have been starved while the servo thread edited;
  // let it save the last epochs too (each is checked below), for at most two minutes.
  const auto wait_until = std::chrono::steady_clock::now() + std::chrono::minutes(2);
  while (std::chrono::steady_clock::now() < wait_until) {
    {
      std::lock_guard<std::mutex> lock(saved_mutex);
      if (saved.size() > 2) break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  done = true;
  r1.join(), r2.join(), s1.join(), c1.join();
  session.finish();

  const SessionStats& ss = session.stats();
  std::printf(
      "%lld ticks at %.0f Hz (%lld overruns), %lld in contact; %lld sweeps changed %lld samples/texels; "
      "%lld epochs published (%lld ticks with an edit refused), %lld slab re-uploads, %zu files saved\n",
      (long long)st.ticks, st.rate_hz, (long long)st.overruns, (long long)ss.contact_ticks, (long long)ss.sweeps,
      (long long)ss.changed, (long long)ss.publications, (long long)ss.edits_refused, (long long)reuploads.load(),
      saved.size());
  EXPECT_EQ(torn.load(), 0) << "a reader saw a slab version being written";
  EXPECT_EQ(seams.load(), 0) << "a snapshot mixed two states of a shared sample";
  EXPECT_EQ(bad_vertices.load(), 0);
  EXPECT_GT(ss.contact_ticks, 10000);
  // The servo thread edits throughout: every stroke, however the machine's load slows the sweeps
  // (a backlog merges samples into fewer, longer sweeps).
  std::printf("sweeps per stroke:");
  for (int k = 0; k < kStrokes; ++k) std::printf(" %lld", (long long)hooks.sweeps_of_stroke[k]);
  std::printf("\n");
  for (int k = 0; k < kStrokes; ++k) EXPECT_GE(hooks.sweeps_of_stroke[k], 1) << "stroke " << k << " made no sweep";
  // Stored changes only: a smooth stroke over the sphere rounds mostly to the codes it finds.
  EXPECT_GT(ss.changed, 100) << "and its edits must change the model";
  // Several epochs reached the readers (3 under ThreadSanitizer at load 9, hundreds when idle).
  EXPECT_GE(ss.publications, 2);
  EXPECT_GT(reuploads.load(), 100);
  ASSERT_GT(saved.size(), 2u);

  // Every saved file loads and equals the replay of the edit log up to its epoch.
  std::sort(saved.begin(), saved.end());
  SlabModel replayed = initial;
  StrokeEditor replayer(replayed);
  size_t applied = 0;
  int checked = 0;
  for (const auto& [epoch, path] : saved) {
    const SlabModel loaded = load_model(path);
    ASSERT_LE(epoch, epochs.size());
    const size_t upto = epoch == 0 ? 0 : epochs[epoch - 1];
    for (; applied < upto; ++applied) {
      ASSERT_TRUE(replayer.replay(edits[applied]));
      replayer.work(replayed, INT64_MAX);
    }
    ASSERT_EQ(stored_difference(loaded, replayed), "") << path << " (epoch " << epoch << ")";
    ++checked;
  }
  EXPECT_GE(checked, 3);
  std::filesystem::remove_all(dir);
}

// The studio's threads without a window: the servo thread (ServoThread: run_session at 10 kHz)
// reads the mouse device the "render thread" (this one) feeds through a triple buffer, edits,
// publishes; this thread reads the tool state and the timing ring, posts brushes and undos, and
// reads snapshots. Under ThreadSanitizer (scripts/test_tsan.sh) it must run clean. The tool is felt
// as a point (the proxy) or as a ball of the brush's radius (the sphere proxy, `hdm studio --ball`).
static void studio_servo_and_render_threads(RenderMode mode) {
  SessionOptions o;
  o.mode = mode;
  o.publish_interval_s = 0.002;
  o.snapshots.checksums = true;
  SculptSession session(sphere_shell(), Workspace{Vec3::Zero(), 10.0}, o);
  studio::MouseDevice mouse(10000);
  int64_t last_tick = -1, torn = 0, backwards = 0, read_epochs = 0, ball_ticks = 0;
  {
    studio::ServoThread servo(session, mouse, 10000);
    const SlabSnapshots& snaps = *session.snapshots();
    const auto start = std::chrono::steady_clock::now();
    // At least 1.5 s, and on until the strokes have edited and an epoch was read (a loaded machine
    // under ThreadSanitizer may need longer), at most 20 s.
    auto running = [&] {
      const auto t = std::chrono::steady_clock::now() - start;
      if (t >= std::chrono::seconds(20)) return false;
      return t < std::chrono::milliseconds(1500) || servo.figures().sweeps == 0 || read_epochs == 0;
    };
    for (int frame = 0; running(); ++frame) {
      if (frame % 20 == 0) {
        SessionCommand c;
        c.brush = brush(frame / 20);
        session.post(c);
      }
      if (frame % 45 == 44) {
        SessionCommand c;
        c.kind = SessionCommand::Undo;
        session.post(c);
      }
      if (frame % 30 == 15) {  // the panel's live stiffness and friction
        SessionCommand c;
        c.kind = SessionCommand::SetProxy;
        c.proxy.force.stiffness = frame % 60 == 15 ? 2000 : 1000;
        c.proxy.friction_scale = frame % 60 == 15 ? 0.5 : 1.0;
        session.post(c);
      }
      // The cursor sweeps over the sphere 0.04 model units deep, the button held in strokes.
      const double a = 0.05 * frame;
      studio::MouseHandle h;
      h.position = Vec3(std::cos(a), std::sin(a), 0.3).normalized() * 0.096;
      h.buttons = (frame / 10) % 2;
      mouse.set(h);
      const studio::ToolState& t = servo.tool();
      if (t.tick < last_tick) ++backwards;
      last_tick = t.tick;
      ASSERT_TRUE(t.hip.allFinite());
      ASSERT_TRUE(t.ball_centre.allFinite());
      ball_ticks += t.ball;
      (void)servo.figures();
      SnapshotReader r(snaps);
      read_epochs += r.epoch() > 0;
      for (int s = 0; s < snaps.model().slab_count(); s += 7) torn += !r.verify(s);
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    const ServoStats& st = servo.stop();
    EXPECT_GT(st.ticks, 1000);
    const studio::ServoFigures f = servo.figures();
    EXPECT_EQ(f.ticks, st.ticks);
    EXPECT_GT(f.sweeps, 0) << "the strokes the mouse device made edited nothing";
  }
  EXPECT_EQ(backwards, 0) << "the tool state went back in time";
  if (mode == RenderMode::Sphere)
    EXPECT_GT(ball_ticks, 0) << "the tool was never felt as a ball";
  else
    EXPECT_EQ(ball_ticks, 0) << "a point proxy's tool was drawn as a ball";
  EXPECT_EQ(torn, 0);
  EXPECT_GT(read_epochs, 0) << "nothing was published";
  EXPECT_GT(session.stats().sweeps, 0);
}

// Copy on write under contention: two readers copy eight slabs from the live model over and over
// while the writer asks for them, writes every slot of each slab it is granted with one value
// (so a copy torn by a write shows as unequal slots) and commits. No reader sees a torn slab, and
// ThreadSanitizer sees no race between a reader's copy and a write.
TEST(Concurrency, TheWriterNeverWritesASlabAReaderIsCopying) {
  SlabModel model = sphere_shell();
  SnapshotOptions o;
  o.spare_versions = 16;
  SlabSnapshots snaps(model, o);
  const int P = model.samples.per_slab;
  std::atomic<bool> done{false};
  std::atomic<int64_t> torn{0}, copies{0};
  auto reader = [&] {
    while (!done.load()) {
      const SnapshotReader r(snaps);
      for (int s = 0; s < 8; ++s) {
        const SlabView v = r.slab(s);
        for (int k = 1; k < P; ++k) torn += v.points[k].delta != v.points[0].delta;
        torn += !r.verify(s);
        ++copies;
      }
    }
  };
  for (int s = 0; s < 8; ++s)  // one value per slab to start from (not yet shared with a reader)
    for (int k = 0; k < P; ++k) model.slab_samples[size_t(s) * P + k].delta = 0.5f;
  std::thread r1(reader), r2(reader);
  int64_t refused = 0, granted = 0;
  for (int round = 1; round <= 4000; ++round) {
    for (int s = 0; s < 8; ++s) {
      if (!snaps.before_write(s)) {
        ++refused;
        continue;
      }
      ++granted;
      for (int k = 0; k < P; ++k) model.slab_samples[size_t(s) * P + k].delta = float(round % 1000) / 1000.0f;
    }
    if (round % 3 == 0) snaps.publish_commit();
  }
  done = true;
  r1.join(), r2.join();
  std::printf("%lld writes granted, %lld refused; %lld slab copies read\n", (long long)granted, (long long)refused,
              (long long)copies.load());
  EXPECT_EQ(torn.load(), 0);
  EXPECT_GT(granted, 0);
}

TEST(Concurrency, StudioServoThreadAndRenderThread) { studio_servo_and_render_threads(RenderMode::Proxy); }
TEST(Concurrency, StudioServoThreadWithTheBallAndRenderThread) { studio_servo_and_render_threads(RenderMode::Sphere); }

namespace {

// A handle that follows a given path, one point per tick (1 kHz).
class PathDevice final : public HapticDevice {
 public:
  explicit PathDevice(std::vector<Vec3> path) : path_(std::move(path)) {}
  bool begin_frame(DeviceState& s) noexcept override {
    if (k_ >= path_.size()) return false;
    s.velocity = k_ > 0 ? Vec3((path_[k_] - path_[k_ - 1]) * 1000.0) : Vec3::Zero();
    s.position = path_[k_++];
    return true;
  }
  void end_frame(const Vec3&) noexcept override {}
  using HapticDevice::end_frame;
  DeviceSpec spec() const noexcept override { return {}; }

 private:
  std::vector<Vec3> path_;
  size_t k_ = 0;
};

}  // namespace

// The studio's live stiffness and friction (SessionCommand::SetProxy, posted as the panel does):
// applied from the next tick, the proxy's contact kept. Doubling the stiffness doubles the force at
// the same penetration; scaling the friction scales the ratio of tangential to normal force while
// the handle slides (stick-slip between the painted μd and μs).
TEST(Session, LiveStiffnessAndFriction) {
  SlabModel m = sphere_shell();
  m.friction_static.assign(m.samples.count, 0.5f);
  m.friction_dynamic.assign(m.samples.count, 0.4f);
  SessionOptions o;
  o.publish = false;
  SculptSession session(std::move(m), Workspace{Vec3::Zero(), 10.0}, o);  // 1 model unit = 0.1 m
  // Press in 1 mm below the top vertex (on the surface), hold, then slide along a great circle.
  std::vector<Vec3> path;
  for (int k = 0; k <= 100; ++k) path.push_back(Vec3(0, 0, 0.102 - 0.003 * k / 100.0));
  for (int k = 0; k < 200; ++k) path.push_back(path.back());
  const double depth = 0.099;
  for (int k = 1; k <= 3100; ++k) {
    const double a = 1e-4 * k;  // 0.01 mm per tick: 10 mm/s
    path.push_back(depth * Vec3(std::sin(a), 0, std::cos(a)));
  }
  PathDevice device(path);
  ServoTick t;
  auto tick = [&] {
    const SessionTick r = session.tick(device, t);
    t.time_s = 1e-3 * double(++t.tick);
    return r;
  };
  auto post = [&](double stiffness, double friction) {
    SessionCommand c;
    c.kind = SessionCommand::SetProxy;
    c.proxy = session.proxy_params();
    c.proxy.force.stiffness = stiffness;
    c.proxy.friction_scale = friction;
    EXPECT_TRUE(session.post(c));
  };
  SessionTick held;
  for (int k = 0; k < 300; ++k) held = tick();
  ASSERT_EQ(session.proxy_params().force.stiffness, 1000.0);
  const double f1 = held.force.norm();
  // 1000 N/m at about 1 mm (the surface is flat between the coarse vertices, at most 0.4 mm lower)
  EXPECT_GT(f1, 0.6);
  EXPECT_LT(f1, 1.05);
  post(2000, 1.0);
  const SessionTick doubled = tick();  // the same handle position (the path holds)
  EXPECT_EQ(session.proxy_params().force.stiffness, 2000.0);
  EXPECT_NEAR(doubled.force.norm() / f1, 2.0, 1e-3) << "doubling the stiffness must double the force";
  EXPECT_LT((doubled.out.contact.surface_point - held.out.contact.surface_point).norm(), 1e-9)
      << "the contact must go on where it was";

  // Tangential / normal force about the proxy's normal, averaged over 900 ticks of sliding.
  auto slide_ratio = [&](double friction) {
    post(1000, friction);
    double sum = 0;
    int n = 0;
    for (int k = 0; k < 1000; ++k) {
      const SessionTick r = tick();
      if (k < 100 || !r.out.contact.in_shell()) continue;  // the proxy settles into the new friction
      const Vec3 nrm = r.out.contact.normal.normalized();
      const double fn = r.force.dot(nrm);
      if (fn <= 1e-3) continue;
      sum += (r.force - fn * nrm).norm() / fn, ++n;
    }
    EXPECT_GT(n, 800);
    return n > 0 ? sum / n : -1.0;
  };
  const double full = slide_ratio(1.0), half = slide_ratio(0.5), none = slide_ratio(0.0);
  EXPECT_GE(full, 0.4 * 0.95) << "sliding with μd = 0.4, μs = 0.5";
  EXPECT_LE(full, 0.5 * 1.05);
  EXPECT_GE(half, 0.2 * 0.95) << "friction × 0.5: μd = 0.2, μs = 0.25";
  EXPECT_LE(half, 0.25 * 1.05);
  EXPECT_LT(none, 0.02) << "frictionless";
  std::printf("force %.3f N at 1000 N/m, x%.4f at 2000 N/m; tangential/normal while sliding: %.3f, %.3f, %.3f\n", f1,
              doubled.force.norm() / f1, full, half, none);
}

}  // namespace hdm
