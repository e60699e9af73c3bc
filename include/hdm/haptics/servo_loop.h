// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// The haptic servo loop: a dedicated thread that calls a tick function at a fixed rate and records
/// tick-period and compute-time statistics in preallocated storage.

#include <cstdint>
#include <vector>

namespace hdm {

/// Servo-loop settings.
struct ServoOptions {
  double rate_hz = 1000.0;  ///< tick rate [Hz]; 1 kHz is the haptic floor
  bool realtime = true;     ///< true: sleep to the next tick; false: run ticks back to back (--fast)
  int64_t ticks = 1000;     ///< number of ticks to run
};

/// Median, 99th percentile and maximum of a duration [ns].
struct LatencyStats {
  double median = 0, p99 = 0, max = 0;
};

/// Timing of a finished run.
struct ServoStats {
  int64_t ticks = 0;        ///< ticks run
  double seconds = 0;       ///< wall time [s]
  double rate_hz = 0;       ///< achieved rate: ticks / seconds [Hz]
  LatencyStats period_ns;   ///< time between tick starts [ns]
  LatencyStats compute_ns;  ///< time inside the tick function [ns]
  int64_t overruns = 0;     ///< ticks that started more than one period late
};

/// Tick function: called on the servo thread with the tick index and its scheduled time [s].
/// It must not allocate, lock or do I/O.
using TickFn = void (*)(void* user, int64_t tick, double time_s) noexcept;

/// @brief Runs @p options.ticks ticks of @p tick on a new thread (best effort SCHED_FIFO when the
/// process may use it) and waits for it.
/// @param[out] realtime_note  set to a message when real-time scheduling was unavailable.
/// @return timing statistics, computed after the loop from preallocated per-tick records.
/// @note Allocates only before the loop starts (per-tick timing buffers).
ServoStats run_servo_loop(const ServoOptions& options, TickFn tick, void* user, const char** realtime_note = nullptr);

/// @brief Median, p99 and maximum of @p values (copied and partially sorted).
LatencyStats latency_stats(std::vector<double> values);

}  // namespace hdm
