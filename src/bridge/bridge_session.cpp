// SPDX-License-Identifier: MIT
#include <hdm/bridge/bridge_session.h>

#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <chrono>
#include <thread>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define HDM_PAUSE() _mm_pause()
#else
#define HDM_PAUSE() ((void)0)
#endif

namespace hdm::bridge {
namespace {

int64_t steady_ns() noexcept {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace

BridgeLoopStats run_bridge_session(SculptSession& session, BridgeDevice& device, const BridgeLoopOptions& o,
                                   const SessionHooks& hooks) {
  BridgeLoopStats st;
  int policy = SCHED_OTHER;
  sched_param before{};
  pthread_getschedparam(pthread_self(), &policy, &before);
  if (o.realtime) {
    sched_param sp{};
    sp.sched_priority = std::max(1, sched_get_priority_max(SCHED_FIFO) - 1);
    st.realtime = pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp) == 0;
  }
  const int64_t start = steady_ns();
  const int64_t idle_ns = static_cast<int64_t>(o.idle_period_s * 1e9);
  const int64_t give_up_ns = static_cast<int64_t>(o.give_up_s * 1e9);
  const int64_t first_packet_ns = static_cast<int64_t>(o.first_packet_s * 1e9);
  bool seen_packet = false;
  const int64_t watchdog_ns = static_cast<int64_t>(device.options().watchdog_s * 1e9);
  int64_t last_tick = start, last_packet_ns = start;
  int spins = 0;
  for (;;) {
    if (o.stop && o.stop->load(std::memory_order_relaxed)) break;
    const bool fresh = device.receive();
    const int64_t now = steady_ns();
    if (fresh) last_packet_ns = now, seen_packet = true;
    const int64_t limit = !seen_packet && first_packet_ns > 0 ? first_packet_ns : give_up_ns;
    if (!fresh && limit > 0 && now - last_packet_ns > limit) {
      st.gave_up = true;
      break;
    }
    // Idle ticks only once the watchdog holds, so a driver that keeps its rate gets exactly one
    // tick per accepted packet (and the watchdog still ramps the force out and ends a stroke).
    const bool idle = !fresh && now - last_tick >= idle_ns && (device.stale() || now - last_packet_ns > watchdog_ns);
    if (!fresh && !idle) {
      if (o.spin) {
        HDM_PAUSE();
        if (++spins % 256 == 0) std::this_thread::yield();
      } else {
        std::this_thread::sleep_for(std::chrono::microseconds(50));
      }
      continue;
    }
    ServoTick t;
    t.tick = st.ticks;
    const bool any = device.last_packet().sequence > 0;
    t.time_s = fresh ? device.last_packet().time_s
                     : (any ? device.last_packet().time_s : 0.0) + double(now - (any ? last_packet_ns : start)) * 1e-9;
    if (hooks.before) hooks.before(hooks.user, session, t);
    const SessionTick r = session.tick(device, t);
    if (r.ended) {
      st.ended = true;
      break;
    }
    const bool contact =
        r.out.contact.in_shell() && r.out.status != ProxyStatus::Free && r.out.status != ProxyStatus::BadInput;
    device.set_contact(session.workspace().to_device(r.out.contact.surface_point), contact);
    if (hooks.after) hooks.after(hooks.user, t, r);
    ++st.ticks;
    st.idle_ticks += !fresh;
    last_tick = now;
  }
  if (st.realtime) pthread_setschedparam(pthread_self(), policy, &before);
  return st;
}

}  // namespace hdm::bridge
