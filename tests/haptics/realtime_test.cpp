// SPDX-License-Identifier: MIT
// Real-time rules and the servo/device layer: no allocation in the tick (global operator new is
// replaced in this test program and counted), the force envelope, the simulated and replay devices.
#include "haptics/haptics_fixtures.h"

#include <hdm/haptics/rigid_tool.h>
#include <hdm/haptics/sphere_proxy.h>

#include <hdm/core/error.h>
#include <hdm/haptics/device.h>
#include <hdm/haptics/servo_loop.h>
#include <hdm/session/sculpt_session.h>

#include <gtest/gtest.h>

#include <chrono>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <new>
#include <thread>

namespace {
std::atomic<long> g_news{0};
thread_local long t_news = 0;  // this thread's allocations (other threads may allocate meanwhile)
}  // namespace

// Counting replacements of the global allocation functions (program-wide). GCC cannot see that
// these replacements pair malloc/aligned_alloc with free.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif
void* operator new(std::size_t n) {
  g_news.fetch_add(1, std::memory_order_relaxed);
  ++t_news;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) {
  g_news.fetch_add(1, std::memory_order_relaxed);
  ++t_news;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t n, std::align_val_t a) {
  g_news.fetch_add(1, std::memory_order_relaxed);
  ++t_news;
  const std::size_t al = static_cast<std::size_t>(a);
  if (void* p = std::aligned_alloc(al, (n + al - 1) / al * al)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }

namespace hdm {
namespace {

using test::sphere;
using test::sphere_params;

// N ticks of device → proxy (and penalty) → device on the sphere, sliding across slab edges:
// zero global allocations.
TEST(Realtime, ProxyTickDoesNotAllocate) {
  const auto& S = sphere();
  SlabModel model = test::sphere_with_friction();
  const SlabLocator locator(model);
  const int n = 20000;
  std::vector<Vec3> targets(n);
  for (int k = 0; k < n; ++k) {
    const double a = 3.0 * k / n;
    targets[k] = S.ws.to_device(Vec3(std::sin(a), 0.2 * std::sin(3 * a), std::cos(a)) * 0.96);
  }
  for (RenderMode mode : {RenderMode::Proxy, RenderMode::Penalty}) {
    SimulatedDeviceOptions o;
    o.rate_hz = 10000;
    SimulatedDevice device(o, targets, S.ws.to_device(Vec3(0, 0, 1.1)));
    ProxyParams p = sphere_params(true);
    ProxyState st;
    ForceEnvelope env;
    int contact = 0;
    const long before = g_news.load();
    for (int k = 0; k < n; ++k) {
      DeviceState ds;
      device.begin_frame(ds);
      const ProxyOutput out = render_step(mode, model, locator, S.ws, ds.position, ds.velocity, p, st);
      device.end_frame(out.force * env.update(1e-4, 0, false));
      contact += st.contact;
    }
    const long allocations = g_news.load() - before;
    EXPECT_EQ(allocations, 0) << (mode == RenderMode::Proxy ? "proxy" : "penalty");
    EXPECT_GT(contact, n / 2) << "the run must exercise contact";
  }
}

// The sphere proxy's tick on the same path, with friction: zero global allocations.
TEST(Realtime, SphereProxyTickDoesNotAllocate) {
  const auto& S = sphere();
  SlabModel model = test::sphere_with_friction();
  const SlabLocator locator(model);
  SphereProxyParams p;
  p.proxy = sphere_params(true);
  p.radius = 0.1;
  SphereProxyState st;
  const int n = 5000;
  int contact = 0;
  const long before = g_news.load();
  for (int k = 0; k < n; ++k) {
    const double a = 3.0 * k / n;
    const Vec3 hip = S.ws.to_device(Vec3(std::sin(a), 0.2 * std::sin(3 * a), std::cos(a)).normalized() * 1.06);
    sphere_proxy_step(model, locator, S.ws, hip, Vec3::Zero(), p, st);
    contact += st.contact;
  }
  EXPECT_EQ(g_news.load() - before, 0);
  EXPECT_GT(contact, n / 2) << "the run must exercise contact";
}

// The rigid tool's tick: a 1,000-point burr (r = 0.05) on the sphere, its shaft along the radius, the
// tip 0.01 inside its rest height and the tool turning about the radius and tilting: zero global
// allocations.
TEST(Realtime, RigidToolTickDoesNotAllocate) {
  const auto& S = sphere();
  const ToolShell shell = burr_shell(0.05);
  auto st = std::make_unique<RigidToolState>();
  const RigidToolParams p;
  const int n = 2000;
  int contact = 0;
  const long before = g_news.load();
  for (int k = 0; k < n; ++k) {
    const double a = 1.5 * k / n;
    const Vec3 radial = Vec3(std::sin(a), 0.2 * std::sin(3 * a), std::cos(a)).normalized();
    ToolPose d;
    d.position = S.ws.to_device(radial * (1 + 0.05 - 0.01));
    d.orientation = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), radial) *
                    Eigen::Quaterniond(Eigen::AngleAxisd(0.3 * std::sin(5 * a), Vec3::UnitX()));
    const ToolWrench out = rigid_tool_step(S.model, *S.locator, S.ws, shell, d, ToolTwist{}, p, *st);
    contact += out.status == ForceStatus::Contact || out.status == ForceStatus::Clamped;
  }
  EXPECT_EQ(g_news.load() - before, 0);
  EXPECT_GT(contact, n / 2) << "the run must exercise contact";
}

// The whole servo loop with edits: device → proxy → envelope → device, strokes of every kind from
// the tool button (carve, add, smooth, paint of colour and of static friction, a per-sample field
// baked as one value), undo and redo from another thread, publication of
// changed slabs for a reader thread that takes snapshots meanwhile. The servo thread allocates
// nothing (counted per thread: the reader allocates).
namespace {
struct SessionRig {
  std::vector<Vec3> targets;
  std::vector<uint32_t> buttons;
  std::vector<Brush> brushes;  // the brush of each stroke, switched by the tick's hook
  std::vector<int> stroke;     // stroke index per tick (-1: none)
  SessionRig() {
    const Vec3 up = sphere().ws.to_device(Vec3(0, 0, 1.1));
    auto add = [&](const Vec3& to, int n, int s) {
      const Vec3 from = targets.empty() ? up : targets.back();
      for (int k = 1; k <= n; ++k) {
        targets.push_back(from + (to - from) * (double(k) / n));
        buttons.push_back(s >= 0);
        stroke.push_back(s);
      }
    };
    const double mm = sphere().ws.scale / 1000;
    for (int s = 0; s < 5; ++s) {
      Brush b;
      b.radius = 8 * mm;
      b.tool = s == 0 ? BrushTool::Carve : s == 1 ? BrushTool::Add : s == 2 ? BrushTool::Smooth : BrushTool::Paint;
      b.height = 1 * mm, b.strength = 1, b.falloff = s < 2 ? Falloff::Constant : Falloff::Smooth;
      if (s == 4) b.field = BrushField::FrictionStatic, b.value = 0.9f;  // a per-sample field, one value until now
      brushes.push_back(b);
      const double a = 0.3 + 0.5 * s;
      const Vec3 start =
          sphere().ws.to_device(Vec3(std::sin(0.4) * std::cos(a), std::sin(0.4) * std::sin(a), std::cos(0.4)) * 0.97);
      const Vec3 end =
          sphere().ws.to_device(Vec3(std::sin(0.7) * std::cos(a), std::sin(0.7) * std::sin(a), std::cos(0.7)) * 0.97);
      add(start * 1.2, 800, -1);
      add(start, 800, s);
      add(end, 3000, s);
      add(end * 1.2, 800, -1);
    }
  }
};
}  // namespace

TEST(Realtime, WholeSessionLoopWithEditsDoesNotAllocate) {
  const SessionRig rig;
  for (RenderMode mode : {RenderMode::Proxy, RenderMode::Sphere}) {  // a point, and the brush felt as a ball
    SCOPED_TRACE(mode == RenderMode::Sphere ? "sphere" : "proxy");
    SessionOptions o;
    o.mode = mode;
    o.proxy = sphere_params(true);
    o.publish_interval_s = 0.002;
    o.edit_budget_s = 1.0;  // every edit completes in its tick: the counts below do not depend on the machine's load
    SculptSession session(sphere().model, sphere().ws, o);
    SimulatedDeviceOptions d;
    d.rate_hz = 10000;
    SimulatedDevice device(d, rig.targets, rig.targets.front(), rig.buttons);
    std::atomic<bool> done{false};
    std::atomic<int> snapshots{0};
    std::thread reader([&] {  // a renderer's reads: allocations here do not count
      while (!done.load()) {
        SnapshotReader r(*session.snapshots());
        for (int s = 0; s < session.snapshots()->model().slab_count(); s += 7) (void)r.slab(s).points[0].delta;
        snapshots.fetch_add(1);
        std::this_thread::yield();
      }
    });
    // The reader is under way before the servo loop starts (how often it reads during the loop's
    // 90 ms is up to the scheduler; the stress test in tests/session checks the reads themselves).
    while (snapshots.load() == 0) std::this_thread::yield();
    int64_t sweeps = 0, published = 0, contact = 0;
    int current = -1;
    const long before = t_news;
    for (size_t k = 0; k < rig.targets.size(); ++k) {
      ServoTick t;
      t.tick = static_cast<int64_t>(k);
      t.time_s = 1e-4 * double(k);
      if (rig.stroke[k] >= 0 && rig.stroke[k] != current) session.set_brush(rig.brushes[current = rig.stroke[k]]);
      if (k == rig.targets.size() / 2) session.post(SessionCommand{SessionCommand::Undo, {}, {}});
      if (k == rig.targets.size() / 2 + 100) session.post(SessionCommand{SessionCommand::Redo, {}, {}});
      const SessionTick out = session.tick(device, t);
      sweeps += out.sweeps, published += out.published, contact += out.out.status != ProxyStatus::Free;
    }
    const long allocations = t_news - before;
    done = true;
    reader.join();
    std::printf(
        "%lld sweeps, %lld ticks with an edit refused, %lld publications deferred, %lld slabs published, %d snapshots "
        "read\n",
        (long long)sweeps, (long long)session.stats().edits_refused, (long long)session.stats().publish_deferred,
        (long long)published, snapshots.load());
    EXPECT_EQ(allocations, 0);
    EXPECT_GT(contact, 8000) << "the run must exercise contact";
    EXPECT_GT(sweeps, 5000) << "and edit on most ticks";
    // Publication must run inside the counted ticks. How often depends on the scheduler: it waits
    // while the reader holds a snapshot, and on a loaded machine 12 of ~150 chances went through.
    EXPECT_GT(published, 0);
    EXPECT_GE(snapshots.load(), 1);
    EXPECT_GT(session.editor().history().undo_count(), 2);
    EXPECT_TRUE(sphere().model.friction_static.uniform());
    EXPECT_FALSE(session.model().friction_static == sphere().model.friction_static) << "the friction stroke painted";
  }
}

// The same through run_session (the servo thread of run_servo_loop): no allocation inside a tick.
namespace {
struct Count {
  long before = 0, inside = 0;
};
void count_before(void* user, SculptSession&, const ServoTick&) noexcept { static_cast<Count*>(user)->before = t_news; }
void count_after(void* user, const ServoTick&, const SessionTick&) noexcept {
  auto& c = *static_cast<Count*>(user);
  c.inside += t_news - c.before;
}

// Runs the rig's path through run_session at 10 kHz back to back with a simulated hand of
// options @p d; the allocations inside ticks are counted into @p c.
ServoStats run_rig(SculptSession& session, const SessionRig& rig, SimulatedDeviceOptions d, Count& c) {
  d.rate_hz = 10000;
  SimulatedDevice device(d, rig.targets, rig.targets.front(), rig.buttons);
  ServoOptions so;
  so.rate_hz = 10000;
  so.realtime = false;
  so.ticks = static_cast<int64_t>(rig.targets.size());
  const ServoStats st = run_session(session, device, so, SessionHooks{count_before, count_after, &c});
  EXPECT_EQ(st.ticks, so.ticks);
  return st;
}
}  // namespace

TEST(Realtime, RunSessionTicksDoNotAllocate) {
  const SessionRig rig;
  SessionOptions o;
  o.proxy = sphere_params(true);
  SculptSession session(sphere().model, sphere().ws, o);
  Brush carve;
  carve.radius = 8 * sphere().ws.scale / 1000;
  session.set_brush(carve);
  Count c;
  run_rig(session, rig, {}, c);
  EXPECT_EQ(c.inside, 0);
  EXPECT_GT(session.stats().sweeps, 1000);
}

// RenderMode::RigidTool through run_session: the default burr on the same path, force and torque
// sent to the device, the drill brush removing under its head on the strokes, no allocation inside
// a tick.
TEST(Realtime, RigidToolSessionTicksDoNotAllocate) {
  const SessionRig rig;
  SessionOptions o;
  o.mode = RenderMode::RigidTool;
  SculptSession session(sphere().model, sphere().ws, o);
  Brush drill;
  drill.tool = BrushTool::Drill;
  drill.radius = 0.01 * sphere().model.source_diagonal;  // the default burr's head
  drill.falloff = Falloff::Smooth;
  session.set_brush(drill);
  SimulatedDeviceOptions d;
  d.spec.max_torque_nm = 0.2;
  d.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Vec3::UnitY()));
  Count c;
  const ServoStats st = run_rig(session, rig, d, c);
  EXPECT_EQ(c.inside, 0);
  EXPECT_GT(session.stats().contact_ticks, 5000) << "the run must exercise contact";
  EXPECT_GT(session.stats().sweeps, 1000) << "and drill on the strokes";
  EXPECT_GT(session.stats().changed, 0);
  std::printf("rigid tool session tick (burr, %d points): median %.1f us, p99 %.1f us, %lld of %lld ticks in contact\n",
              o.tool_points, st.compute_ns.median * 1e-3, st.compute_ns.p99 * 1e-3,
              static_cast<long long>(session.stats().contact_ticks), static_cast<long long>(st.ticks));
}

TEST(Servo, EnvelopeRampsInAndOutAndTheWatchdogCutsForce) {
  ForceEnvelope e{0.01, 0.02, 3, 0.0};
  const double T = 1e-4;  // 10 kHz
  for (int k = 1; k <= 50; ++k) EXPECT_NEAR(e.update(T, 0, false), k * T / 0.01, 1e-12);
  for (int k = 0; k < 100; ++k) e.update(T, 0, false);
  EXPECT_EQ(e.gain, 1.0);
  EXPECT_EQ(e.update(T, 3, false), 1.0) << "3 late periods: within the watchdog's tolerance";
  EXPECT_NEAR(e.update(T, 4, false), 1 - T / 0.02, 1e-12) << "missed ticks: ramp towards zero";
  for (int k = 0; k < 300; ++k) e.update(T, 10, false);
  EXPECT_EQ(e.gain, 0.0);
  for (int k = 0; k < 200; ++k) e.update(T, 0, false);
  EXPECT_EQ(e.gain, 1.0) << "back on time: ramped in again";
  for (int k = 0; k < 199; ++k) e.update(T, 0, true);
  EXPECT_GT(e.gain, 0.0);
  EXPECT_EQ(e.update(T, 0, true), 0.0) << "ramp-out over 0.02 s = 200 ticks";
}

struct GainLog {
  std::vector<double> gain;
  std::vector<uint8_t> stopping;
};
void log_tick(void* user, const ServoTick& t) noexcept {
  auto& g = *static_cast<GainLog*>(user);
  g.gain[t.tick] = t.force_gain;
  g.stopping[t.tick] = t.stopping;
}

TEST(Servo, LoopAt10kHzAppliesTheEnvelopeAndStops) {
  GainLog log;
  ServoOptions o;
  o.rate_hz = 10000;
  o.ticks = 3000;
  o.ramp_in_s = 0.01;
  o.ramp_out_s = 0.01;
  o.watchdog_ticks = 1 << 30;  // a loaded CI machine misses ticks; the watchdog is tested above
  log.gain.assign(o.ticks, -1);
  log.stopping.assign(o.ticks, 0);
  const ServoStats st = run_servo_loop(o, log_tick, &log);
  EXPECT_EQ(st.ticks, o.ticks);
  EXPECT_NEAR(log.gain[0], 0.01, 1e-12);
  EXPECT_EQ(log.gain[1500], 1.0);
  EXPECT_EQ(log.gain[o.ticks - 1], 0.0) << "ramped out at the end";
  EXPECT_TRUE(log.stopping[o.ticks - 50]);
  // The achieved rate is a benchmark's figure (build/bin/bench_servo): tests do not time.

  // An early stop request ramps out and ends the run.
  std::atomic<bool> stop{true};
  o.stop = &stop;
  o.realtime = false;
  log.gain.assign(o.ticks, -1);
  const ServoStats s2 = run_servo_loop(o, log_tick, &log);
  EXPECT_EQ(s2.ticks, 101) << "ramp_out 0.01 s at 10 kHz: 100 ticks + the current one";
  EXPECT_EQ(log.gain[s2.ticks - 1], 0.0);
}

// keep_ticks bounds the per-tick records of a long run: the medians and maxima cover the last
// keep_ticks ticks, the counts every tick. One slow tick (20 ms) early in the run is out of the window's
// maximum but still counted as a long tick.
TEST(Servo, KeptWindowBoundsTheStatisticsButNotTheCounts) {
  struct Slow {
    static void tick(void*, const ServoTick& t) noexcept {
      if (t.tick != 10) return;
      const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(20);
      while (std::chrono::steady_clock::now() < until) {}
    }
  };
  ServoOptions o;
  o.rate_hz = 1000;
  o.realtime = false;
  o.ticks = 500;
  o.keep_ticks = 100;
  const ServoStats st = run_servo_loop(o, Slow::tick, nullptr);
  EXPECT_EQ(st.ticks, 500);
  EXPECT_GE(st.long_ticks, 1) << "the 20 ms tick is counted although it left the window";
  EXPECT_LT(st.compute_ns.max, 20e6) << "the window's maximum leaves out tick 10";
  o.keep_ticks = 0;
  const ServoStats all = run_servo_loop(o, Slow::tick, nullptr);
  EXPECT_GE(all.long_ticks, 1);
  EXPECT_GE(all.compute_ns.max, 20e6) << "every tick kept";
}

// Physics of the simulated handle, checked against statics: a constant force F against the hand
// spring k_h comes to rest at F/k_h from the target.
TEST(Device, SimulatedHandleSettlesAtTheHandSpringOffset) {
  SimulatedDeviceOptions o;
  const std::vector<Vec3> targets(1, Vec3(0.01, 0.02, 0.03));
  SimulatedDevice d(o, targets, Vec3::Zero());
  DeviceState s;
  for (int k = 0; k < 3000; ++k) {
    d.begin_frame(s);
    d.end_frame(Vec3(1.0, 0, 0));
  }
  d.begin_frame(s);
  EXPECT_NEAR(s.position.x(), 0.01 + 1.0 / o.hand_stiffness, 1e-6);
  EXPECT_NEAR(s.position.y(), 0.02, 1e-6);
  EXPECT_LT(s.velocity.norm(), 1e-4);
  d.end_frame(Vec3(100, 0, 0));  // saturates at max force
  d.begin_frame(s);
  EXPECT_LT(s.position.x(), 0.01 + 1.0 / o.hand_stiffness + 0.01);
}

TEST(Device, ReplayPlaysTheSculptCsv) {
  const std::string path = (std::filesystem::temp_directory_path() / "hdm_replay_test.csv").string();
  {
    std::ofstream f(path);
    f << "time_s,device_x_m,device_y_m,device_z_m,contact,depth_m,force_x_n,force_y_n,force_z_n\n"
         "0.0000,0.010000,0.020000,0.030000,0,0.0000000,0.00000,0.00000,0.00000\n"
         "0.0010,0.011000,0.020000,0.030000,1,0.0001000,0.10000,0.00000,0.00000\n";
  }
  ReplayDevice d(path);
  ASSERT_EQ(d.size(), 2u);
  DeviceState s;
  ASSERT_TRUE(d.begin_frame(s));
  EXPECT_EQ(s.position, Vec3(0.01, 0.02, 0.03));
  d.end_frame(Vec3::Zero());
  ASSERT_TRUE(d.begin_frame(s));
  EXPECT_NEAR(s.velocity.x(), 1.0, 1e-9);
  d.end_frame(Vec3(0.5, 0, 0));
  EXPECT_EQ(d.last_force(), Vec3(0.5, 0, 0));
  EXPECT_FALSE(d.begin_frame(s));
  {
    std::ofstream f(path);
    f << "t,x,y,z\n0,0,0,0\n";
  }
  EXPECT_THROW(ReplayDevice{path}, InvalidInput);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace hdm
