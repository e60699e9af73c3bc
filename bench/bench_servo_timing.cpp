// How a servo thread keeps its schedule on this machine, with the ways of waiting for the next
// tick side by side: one SCHED_FIFO thread ticks at the rate asked and takes turns (slices of half
// a second, round-robin, so that every method meets the same load) at
//   sleep       std::this_thread::sleep_until(deadline), the default timer slack (50 µs)
//   slack       clock_nanosleep to the deadline (absolute) after prctl(PR_SET_TIMERSLACK, 1)
//   spin        slack 1 ns, clock_nanosleep to 100 µs before the deadline (a quarter period when
//               that is shorter), then spin on the clock to it
//   spin+lock   spin, with mlockall(MCL_CURRENT | MCL_FUTURE) (no page fault can stall a tick)
//   spin+pin    spin+lock, the thread pinned to the last CPU (pthread_setaffinity_np)
// and counts, per method, the ticks that started late: by a period or more (what hdm's servo loop
// and the studio call late), by more than 100 µs, and the lateness's p99 and maximum. Each tick
// also does 3 µs of work, about a servo tick's median (docs/editing.md).
//
//   bench_servo_timing [rate_hz=1000] [seconds_per_method=20]
#include <hdm/core/percentile.h>

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <thread>
#include <vector>

namespace {

int64_t now_ns() {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return int64_t(ts.tv_sec) * 1000000000 + ts.tv_nsec;
}

void sleep_until_ns(int64_t t) {
  timespec ts{static_cast<time_t>(t / 1000000000), static_cast<long>(t % 1000000000)};
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) != 0) {}
}

enum Method { Sleep, Slack, Spin, SpinLock, SpinPin, kMethods };
const char* const kNames[kMethods] = {"sleep", "slack", "spin", "spin+lock", "spin+pin"};

struct Figures {
  int64_t ticks = 0, late = 0, over100us = 0;
  std::vector<int64_t> lateness;  // [ns]
};

}  // namespace

int main(int argc, char** argv) {
  const double rate = argc > 1 ? std::atof(argv[1]) : 1000.0;
  const double seconds = argc > 2 ? std::atof(argv[2]) : 20.0;
  if (!(rate >= 100 && rate <= 100000) || !(seconds > 0)) {
    std::fprintf(stderr, "usage: bench_servo_timing [rate_hz in 100..100000] [seconds_per_method > 0]\n");
    return 2;
  }
  const int64_t period = static_cast<int64_t>(1e9 / rate);
  const int64_t slice_ticks = static_cast<int64_t>(0.5 * rate);
  const int64_t slices = static_cast<int64_t>(seconds / 0.5 + 0.5);
  const int64_t spin_ns = std::min<int64_t>(100000, period / 4);
  std::array<Figures, kMethods> f;
  for (Figures& x : f) x.lateness.reserve(static_cast<size_t>(slices * slice_ticks));
  bool fifo = false;
  const long cpus = sysconf(_SC_NPROCESSORS_ONLN);
  std::thread t([&] {
    sched_param sp{};
    sp.sched_priority = std::max(1, sched_get_priority_max(SCHED_FIFO) - 1);
    fifo = pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp) == 0;
    cpu_set_t all;
    CPU_ZERO(&all);
    for (long c = 0; c < cpus; ++c) CPU_SET(c, &all);
    for (int64_t s = 0; s < slices * kMethods; ++s) {
      const Method m = static_cast<Method>(s % kMethods);
      prctl(PR_SET_TIMERSLACK, m == Sleep ? 50000UL : 1UL, 0, 0, 0);
      if (m == SpinLock || m == SpinPin)
        mlockall(MCL_CURRENT | MCL_FUTURE);
      else
        munlockall();
      cpu_set_t one;
      CPU_ZERO(&one);
      CPU_SET(cpus - 1, &one);
      pthread_setaffinity_np(pthread_self(), sizeof(cpu_set_t), m == SpinPin ? &one : &all);
      Figures& x = f[m];
      const int64_t t0 = now_ns() + period;
      for (int64_t k = 0; k < slice_ticks; ++k) {
        const int64_t due = t0 + k * period;
        if (m == Sleep) {
          std::this_thread::sleep_until(std::chrono::steady_clock::time_point(std::chrono::nanoseconds(due)));
        } else if (m == Slack) {
          sleep_until_ns(due);
        } else {
          if (due - spin_ns > now_ns()) sleep_until_ns(due - spin_ns);
          while (now_ns() < due) {
#if defined(__x86_64__)
            __builtin_ia32_pause();
#endif
          }
        }
        const int64_t start = now_ns(), late = std::max<int64_t>(0, start - due);
        x.lateness.push_back(late);
        x.late += late >= period;
        x.over100us += late > 100000;
        ++x.ticks;
        while (now_ns() - start < 3000) {}
      }
    }
    munlockall();
  });
  t.join();
  double load[3] = {0, 0, 0};
  if (getloadavg(load, 3) < 0) load[0] = -1;
  std::printf("%.0f Hz, %.0f s per method in slices of 0.5 s, %s, load average %.2f\n", rate, seconds,
              fifo ? "SCHED_FIFO" : "normal scheduling (not permitted: the figures mean little)", load[0]);
  std::printf("%-10s %8s %10s %12s %14s %12s\n", "method", "ticks", "late", ">100 us late", "lateness p99", "max");
  for (int m = 0; m < kMethods; ++m) {
    Figures& x = f[m];
    std::vector<int64_t>& v = x.lateness;
    const double q = hdm::percentile(v, 0.99) * 1e-3, mx = *std::max_element(v.begin(), v.end()) * 1e-3;
    std::printf("%-10s %8lld %10lld %12lld %11.1f us %9.1f us\n", kNames[m], static_cast<long long>(x.ticks),
                static_cast<long long>(x.late), static_cast<long long>(x.over100us), q, mx);
  }
  return 0;
}
