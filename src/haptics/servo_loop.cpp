// SPDX-License-Identifier: MIT
#include <hdm/haptics/servo_loop.h>

#include <hdm/core/percentile.h>

#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

#include <time.h>

namespace hdm {

LatencyStats latency_stats(std::vector<double> v) {
  LatencyStats s;
  if (v.empty()) return s;
  s.median = percentile(v, 0.5);
  s.p99 = percentile(v, 0.99);
  s.max = *std::max_element(v.begin(), v.end());
  return s;
}

double ForceEnvelope::update(double period_s, int64_t missed, bool stopping) noexcept {
  const bool tripped = missed > watchdog_ticks;
  const double target = (stopping || tripped) ? 0.0 : 1.0;
  const double ramp = target > gain ? ramp_in_s : ramp_out_s;
  // A ramp of 0 s switches at once; otherwise the gain moves by period/ramp per tick.
  const double step = ramp > 0 ? period_s / ramp : 1.0;
  gain = target > gain ? std::min(target, gain + step) : std::max(target, gain - step);
  if (!std::isfinite(gain)) gain = 0;
  return gain;
}

ServoStats run_servo_loop(const ServoOptions& o, ServoTickFn tick, void* user, const char** realtime_note) {
  using clock = std::chrono::steady_clock;
  const int64_t n = std::max<int64_t>(o.ticks, 0);
  const int64_t keep = std::max<int64_t>(1, o.keep_ticks > 0 ? std::min(n, o.keep_ticks) : n);
  std::vector<double> start_ns(keep), compute_ns(keep), cpu_ns(o.cpu_time ? keep : 0);
  auto thread_cpu_ns = []() noexcept {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e9 + double(t.tv_nsec);
  };
  const double period_s = 1.0 / o.rate_hz;
  // Spin for the last part of each period: sleep_until wakes 50-100 µs late on a stock kernel,
  // which is a whole period at 10 kHz.
  const auto spin = std::chrono::microseconds(o.rate_hz >= 2000 ? 60 : 0);
  bool got_fifo = false;
  int64_t done = 0, trips = 0, overruns = 0, long_ticks = 0, cpu_long_ticks = 0;
  clock::time_point t0, t_end;
  std::thread servo([&] {
    sched_param sp{};
    sp.sched_priority = std::max(1, sched_get_priority_max(SCHED_FIFO) - 1);
    got_fifo = pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp) == 0;
    ForceEnvelope env{o.ramp_in_s, o.ramp_out_s, o.watchdog_ticks, 0.0};
    const int64_t ramp_out_ticks = static_cast<int64_t>(std::ceil(o.ramp_out_s * o.rate_hz));
    int64_t stop_at = n;  // ramp-out ends the run here
    t0 = clock::now();
    for (int64_t k = 0; k < n && k < stop_at; ++k) {
      const auto due = t0 + std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(k * period_s));
      if (o.realtime) {
        std::this_thread::sleep_until(due - spin);
        while (clock::now() < due) std::this_thread::yield();
      }
      const auto a = clock::now();
      ServoTick st;
      st.tick = k;
      st.time_s = k * period_s;
      if (o.realtime) st.missed = static_cast<int64_t>(std::chrono::duration<double>(a - due).count() / period_s);
      if (st.missed > o.watchdog_ticks) ++trips;
      if (o.stop && stop_at == n && o.stop->load(std::memory_order_relaxed))
        stop_at = std::min(n, k + ramp_out_ticks + 1);
      st.stopping = k + ramp_out_ticks >= stop_at;
      st.force_gain = env.update(period_s, st.missed, st.stopping);
      const double cpu0 = o.cpu_time ? thread_cpu_ns() : 0.0;
      tick(user, st);
      const auto b = clock::now();
      const size_t slot = static_cast<size_t>(k % keep);
      if (o.cpu_time) {
        cpu_ns[slot] = thread_cpu_ns() - cpu0;
        cpu_long_ticks += cpu_ns[slot] > period_s * 1e9;
      }
      start_ns[slot] = std::chrono::duration<double, std::nano>(a - t0).count();
      compute_ns[slot] = std::chrono::duration<double, std::nano>(b - a).count();
      if (o.realtime && k > 0 && start_ns[slot] > (k + 1) * period_s * 1e9) ++overruns;
      long_ticks += compute_ns[slot] > period_s * 1e9;
      done = k + 1;
    }
    t_end = clock::now();
  });
  servo.join();
  if (realtime_note)
    *realtime_note = got_fifo ? nullptr
                              : "real-time scheduling (SCHED_FIFO) not permitted here: the servo thread runs at normal "
                                "priority (grant CAP_SYS_NICE or raise RLIMIT_RTPRIO for hard timing)";
  ServoStats s;
  s.ticks = done;
  s.seconds = std::chrono::duration<double>(t_end - t0).count();
  s.rate_hz = s.seconds > 0 ? done / s.seconds : 0;
  s.watchdog_trips = trips;
  s.overruns = overruns;
  s.long_ticks = long_ticks;
  // The kept window: ticks [done - kept, done) in the ring.
  const int64_t kept = std::min(done, keep);
  std::vector<double> period;
  period.reserve(static_cast<size_t>(kept));
  for (int64_t k = done - kept + 1; k < done; ++k) period.push_back(start_ns[k % keep] - start_ns[(k - 1) % keep]);
  s.period_ns = latency_stats(std::move(period));
  compute_ns.resize(static_cast<size_t>(kept));
  if (o.cpu_time) {
    cpu_ns.resize(static_cast<size_t>(kept));
    s.cpu_long_ticks = cpu_long_ticks;
    s.cpu_ns = latency_stats(std::move(cpu_ns));
  }
  s.compute_ns = latency_stats(std::move(compute_ns));
  return s;
}

namespace {
struct LegacyTick {
  TickFn fn;
  void* user;
};
void legacy_tick(void* user, const ServoTick& t) noexcept {
  const auto& l = *static_cast<const LegacyTick*>(user);
  l.fn(l.user, t.tick, t.time_s);
}
}  // namespace

ServoStats run_servo_loop(const ServoOptions& o, TickFn tick, void* user, const char** realtime_note) {
  LegacyTick l{tick, user};
  return run_servo_loop(o, legacy_tick, &l, realtime_note);
}

}  // namespace hdm
