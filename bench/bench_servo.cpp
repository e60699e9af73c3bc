// SPDX-License-Identifier: MIT
// The servo loop's achieved rate and timing with an empty tick, at 1 kHz and 10 kHz: what
// run_servo_loop itself delivers on this machine (the timing the tests leave out: tests do not
// time). Counters: achieved rate [Hz], period p99 and max [ns], overruns and watchdog trips per
// run. Compare with bench_jitter, which shows what the machine takes from a real-time thread.
//
//   build/bin/bench_servo --benchmark_repetitions=3
#include <hdm/haptics/servo_loop.h>

#include <benchmark/benchmark.h>

namespace {

void empty_tick(void*, const hdm::ServoTick&) noexcept {}

void BM_ServoLoop(benchmark::State& state) {
  hdm::ServoOptions o;
  o.rate_hz = static_cast<double>(state.range(0));
  o.ticks = static_cast<int64_t>(o.rate_hz);  // one second per run
  o.watchdog_ticks = 1 << 30;                 // measure lateness, do not fade
  hdm::ServoStats st;
  for (auto _ : state) st = hdm::run_servo_loop(o, empty_tick, nullptr);
  state.counters["rate_hz"] = st.rate_hz;
  state.counters["rate_ratio"] = st.rate_hz / o.rate_hz;
  state.counters["period_p99_ns"] = st.period_ns.p99;
  state.counters["period_max_ns"] = st.period_ns.max;
  state.counters["overruns"] = static_cast<double>(st.overruns);
}
BENCHMARK(BM_ServoLoop)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond)->Iterations(1)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
