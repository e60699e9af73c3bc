// SPDX-License-Identifier: MIT
#include <hdm/haptics/servo_loop.h>

#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <chrono>
#include <thread>

namespace hdm {

LatencyStats latency_stats(std::vector<double> v) {
  LatencyStats s;
  if (v.empty()) return s;
  const size_t mid = v.size() / 2, p99 = std::min(v.size() - 1, static_cast<size_t>(0.99 * double(v.size())));
  std::nth_element(v.begin(), v.begin() + mid, v.end());
  s.median = v[mid];
  std::nth_element(v.begin(), v.begin() + p99, v.end());
  s.p99 = v[p99];
  s.max = *std::max_element(v.begin(), v.end());
  return s;
}

ServoStats run_servo_loop(const ServoOptions& o, TickFn tick, void* user, const char** realtime_note) {
  using clock = std::chrono::steady_clock;
  const int64_t n = std::max<int64_t>(o.ticks, 0);
  std::vector<double> start_ns(n), compute_ns(n);
  const double period_s = 1.0 / o.rate_hz;
  bool got_fifo = false;
  clock::time_point t0, t_end;
  std::thread servo([&] {
    sched_param sp{};
    sp.sched_priority = std::max(1, sched_get_priority_max(SCHED_FIFO) - 1);
    got_fifo = pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp) == 0;
    t0 = clock::now();
    for (int64_t k = 0; k < n; ++k) {
      const auto due = t0 + std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(k * period_s));
      if (o.realtime) std::this_thread::sleep_until(due);
      const auto a = clock::now();
      tick(user, k, k * period_s);
      const auto b = clock::now();
      start_ns[k] = std::chrono::duration<double, std::nano>(a - t0).count();
      compute_ns[k] = std::chrono::duration<double, std::nano>(b - a).count();
    }
    t_end = clock::now();
  });
  servo.join();
  if (realtime_note)
    *realtime_note = got_fifo ? nullptr
                              : "real-time scheduling (SCHED_FIFO) not permitted here: the servo thread runs at normal "
                                "priority (grant CAP_SYS_NICE or raise RLIMIT_RTPRIO for hard timing)";
  ServoStats s;
  s.ticks = n;
  s.seconds = std::chrono::duration<double>(t_end - t0).count();
  s.rate_hz = s.seconds > 0 ? n / s.seconds : 0;
  std::vector<double> period;
  period.reserve(n);
  for (int64_t k = 1; k < n; ++k) {
    period.push_back(start_ns[k] - start_ns[k - 1]);
    if (o.realtime && start_ns[k] > (k + 1) * period_s * 1e9) ++s.overruns;
  }
  s.period_ns = latency_stats(std::move(period));
  s.compute_ns = latency_stats(compute_ns);
  return s;
}

}  // namespace hdm
