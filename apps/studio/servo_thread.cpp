// SPDX-License-Identifier: MIT
#include "servo_thread.h"

#include <hdm/core/percentile.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <thread>
#include <vector>

namespace hdm::studio {
namespace {

int64_t now_ns() noexcept {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace

ServoThread::ServoThread(SculptSession& session, HapticDevice& device, double rate_hz, bridge::BridgeDevice* bridge,
                         bool lockstep)
    : session_(session),
      bridge_(bridge),
      ball_(session.render_mode() == RenderMode::Sphere),
      rigid_(session.render_mode() == RenderMode::RigidTool),
      rate_hz_(rate_hz),
      lockstep_(lockstep) {
  thread_ = std::thread([this, &device] {
    ServoOptions o;
    o.rate_hz = rate_hz_;
    o.realtime = !lockstep_;
    o.ticks = std::numeric_limits<int64_t>::max();
    o.keep_ticks = static_cast<int64_t>(rate_hz_ * 120);  // medians over the last two minutes
    o.stop = &stop_;
    stats_ = run_session(session_, device, o, SessionHooks{before, after, this}, &note_);
  });
}

ServoThread::~ServoThread() { stop(); }

const ServoStats& ServoThread::stop() {
  if (!joined_) {
    stop_.store(true);
    thread_.join();
    joined_ = true;
  }
  return stats_;
}

void ServoThread::step(int64_t n) {
  if (!lockstep_) return;
  const int64_t target = granted_.fetch_add(n, std::memory_order_release) + n;
  while (ticks_.load(std::memory_order_acquire) < target && !ended_.load(std::memory_order_acquire) &&
         !stop_.load(std::memory_order_relaxed))
    std::this_thread::sleep_for(std::chrono::microseconds(50));
}

void ServoThread::before(void* user, SculptSession&, const ServoTick& t) noexcept {
  ServoThread& s = *static_cast<ServoThread*>(user);
  // Lockstep: wait for the render thread's grant (a stop lets the ramp-out ticks run). Sleeping, not
  // spinning: the loop may hold SCHED_FIFO, and the render thread must get the core.
  while (s.lockstep_ && t.tick >= s.granted_.load(std::memory_order_acquire) &&
         !s.stop_.load(std::memory_order_relaxed))
    std::this_thread::sleep_for(std::chrono::microseconds(20));
  s.tick_start_ns_ = now_ns();
}

void ServoThread::after(void* user, const ServoTick& t, const SessionTick& r) noexcept {
  ServoThread& s = *static_cast<ServoThread*>(user);
  if (r.ended) {
    s.ended_.store(true, std::memory_order_release);
    return;
  }
  const int64_t end = now_ns();
  const size_t slot = static_cast<size_t>(t.tick % kRing);
  s.work_ns_[slot].store(static_cast<uint32_t>(std::min<int64_t>(end - s.tick_start_ns_, UINT32_MAX)),
                         std::memory_order_relaxed);
  s.start_ns_[slot].store(s.tick_start_ns_, std::memory_order_relaxed);
  if (t.missed > 0) s.late_.fetch_add(1, std::memory_order_relaxed);
  s.sweeps_.fetch_add(r.sweeps, std::memory_order_relaxed);
  s.ticks_.store(t.tick + 1, std::memory_order_release);

  const Workspace& ws = s.session_.workspace();
  ToolState tool;
  tool.hip = ws.to_model(r.device.position);
  tool.contact = r.out.contact.in_shell() && r.out.status != ProxyStatus::Free && r.out.status != ProxyStatus::BadInput;
  tool.proxy = tool.contact ? r.out.contact.surface_point : tool.hip;
  tool.normal = r.out.contact.normal;
  tool.force = r.out.force;
  tool.ball = s.ball_;
  tool.ball_centre = s.ball_ && r.out.status != ProxyStatus::Free ? r.ball_centre : tool.hip;
  tool.rigid = s.rigid_;
  if (s.rigid_) {  // the god-object's pose, also out of contact (it follows the handle there)
    tool.ball_centre = r.ball_centre;
    tool.orientation = r.tool_orientation;
    tool.torque = r.torque;
    tool.tool_contacts = r.tool_contacts;
    tool.head = r.head;
    tool.shaft = r.shaft;
    tool.contact = r.tool_contacts > 0;
  }
  tool.tool_on = r.tool_on;
  tool.edit_pending = r.edit_pending;
  tool.tick = t.tick;
  s.tool_.write(tool);
  // The force packet of the next tick carries this tick's surface contact point (device frame).
  if (s.bridge_) s.bridge_->set_contact(ws.to_device(tool.proxy), tool.contact);
}

ServoFigures ServoThread::figures() const {
  ServoFigures f;
  f.ticks = ticks_.load(std::memory_order_acquire);
  f.late_ticks = late_.load(std::memory_order_relaxed);
  f.sweeps = sweeps_.load(std::memory_order_relaxed);
  const int64_t now = now_ns();
  std::vector<double> work;
  work.reserve(kRing);
  // Ticks that started in the last second, newest first (the slots of older ticks are overwritten
  // only by newer ones, so a torn read costs one sample of one statistic at most).
  for (int64_t k = f.ticks - 1; k >= 0 && k > f.ticks - kRing; --k) {
    const size_t slot = static_cast<size_t>(k % kRing);
    if (now - start_ns_[slot].load(std::memory_order_relaxed) > 1'000'000'000) break;
    work.push_back(work_ns_[slot].load(std::memory_order_relaxed));
  }
  f.rate_hz = static_cast<double>(work.size());
  if (!work.empty()) f.tick_p99_ns = percentile(work, 0.99);
  return f;
}

}  // namespace hdm::studio
