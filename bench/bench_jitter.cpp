// What the machine takes from a real-time thread that does nothing: a thread (SCHED_FIFO when
// permitted) spins for a few seconds reading its CPU clock and the wall clock, and counts the jumps
// between consecutive reads. A read costs well under a microsecond, so any jump of tens of
// microseconds is time the thread lost: "preempted" when its CPU clock stood still (another thread
// or the kernel ran), "charged" when its CPU clock advanced too (the virtual CPU was descheduled by
// the host, or interrupts were handled, and the time was billed to the thread). A servo tick that
// meets such a jump overruns or reports a long CPU time whatever the tick computes, which is how
// docs/editing.md reads the overruns of `hdm sculpt`.
//
//   bench_jitter [seconds=10]
#include <pthread.h>
#include <sched.h>
#include <time.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <thread>

namespace {

int64_t read_ns(clockid_t c) {
  timespec ts;
  clock_gettime(c, &ts);
  return int64_t(ts.tv_sec) * 1000000000 + ts.tv_nsec;
}

struct Counts {
  int64_t over20 = 0, over50 = 0, over100 = 0, max_ns = 0;
  void add(int64_t g) {
    over20 += g > 20000, over50 += g > 50000, over100 += g > 100000;
    max_ns = std::max(max_ns, g);
  }
};

}  // namespace

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 10.0;
  if (!(seconds > 0)) {
    std::fprintf(stderr, "usage: bench_jitter [seconds>0]\n");
    return 2;
  }
  bool fifo = false;
  Counts preempted, charged;
  int64_t reads = 0;
  std::thread t([&] {
    sched_param sp{};
    sp.sched_priority = std::max(1, sched_get_priority_max(SCHED_FIFO) - 1);
    fifo = pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp) == 0;
    const int64_t end = read_ns(CLOCK_MONOTONIC) + int64_t(seconds * 1e9);
    int64_t wall = read_ns(CLOCK_MONOTONIC), cpu = read_ns(CLOCK_THREAD_CPUTIME_ID);
    while (wall < end) {
      const int64_t w = read_ns(CLOCK_MONOTONIC), c = read_ns(CLOCK_THREAD_CPUTIME_ID);
      const int64_t dw = w - wall, dc = c - cpu;
      if (dw > 20000) (dc < dw / 2 ? preempted : charged).add(dw);
      wall = w, cpu = c;
      ++reads;
    }
  });
  t.join();
  std::printf("spun %.1f s (%s), %lld clock reads\n", seconds, fifo ? "SCHED_FIFO" : "normal scheduling",
              static_cast<long long>(reads));
  std::printf("preempted (CPU clock stood still): >20 us %lld, >50 us %lld, >100 us %lld, max %.1f us\n",
              static_cast<long long>(preempted.over20), static_cast<long long>(preempted.over50),
              static_cast<long long>(preempted.over100), preempted.max_ns * 1e-3);
  std::printf("charged (CPU clock ran on):         >20 us %lld, >50 us %lld, >100 us %lld, max %.1f us\n",
              static_cast<long long>(charged.over20), static_cast<long long>(charged.over50),
              static_cast<long long>(charged.over100), charged.max_ns * 1e-3);
  return 0;
}
