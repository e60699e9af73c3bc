// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// The haptic servo loop: a dedicated thread that calls a tick function at a fixed rate and records
/// tick-period and compute-time statistics in preallocated storage.

#include <atomic>
#include <cstdint>
#include <vector>

namespace hdm {

/// Servo-loop settings.
struct ServoOptions {
  double rate_hz = 1000.0;  ///< tick rate [Hz]; 1 kHz is the haptic floor
  bool realtime = true;     ///< true: sleep to the next tick; false: run ticks back to back (--fast)
  int64_t ticks = 1000;     ///< number of ticks to run
  double ramp_in_s = 0.1;   ///< force gain rises 0 → 1 over this time after the start [s] (no jolt at start)
  double ramp_out_s = 0.1;  ///< force gain falls 1 → 0 over this time before the end or after a stop [s]
  int watchdog_ticks = 3;   ///< a tick starting more than this many periods late counts as missed ticks:
                            ///< the gain ramps to zero (over ramp_out_s) until ticks are on time again
  std::atomic<bool>* stop = nullptr;  ///< optional: set from another thread to ramp out and end early
  /// Also read the servo thread's CPU clock around each tick (two system calls a tick): tells a tick
  /// that computed longer than a period from one that was preempted (ServoStats::cpu_long_ticks).
  bool cpu_time = false;
  /// Per-tick timing kept for ServoStats' medians and percentiles: the last this many ticks
  /// (0: every tick, 24 bytes a tick allocated before the loop). A long-running loop (an
  /// interactive session with `ticks` = INT64_MAX) keeps a window; the counts (overruns, long
  /// ticks, watchdog trips) always cover every tick.
  int64_t keep_ticks = 0;
};

/// What the servo loop tells the tick function on every tick.
struct ServoTick {
  int64_t tick = 0;       ///< tick index
  double time_s = 0;      ///< scheduled time of the tick [s]
  double force_gain = 1;  ///< factor in [0,1] to apply to the commanded force (ramp-in/out, watchdog)
  int64_t missed = 0;     ///< periods this tick started late by (0 when on time)
  bool stopping = false;  ///< a stop was requested: the gain is ramping out
};

/// Gain envelope of the commanded force: ramp-in, ramp-out and the watchdog. Used by
/// run_servo_loop(); usable on its own inside a vendor scheduler callback.
///
/// The gain moves at most period/ramp per tick towards its target (1 in normal running, 0 when
/// stopping or when the watchdog fired), so the force never steps.
struct ForceEnvelope {
  double ramp_in_s = 0.1;   ///< [s], see ServoOptions
  double ramp_out_s = 0.1;  ///< [s]
  int watchdog_ticks = 3;   ///< see ServoOptions
  double gain = 0;          ///< current gain in [0,1]
  /// @brief Advances one tick.
  /// @param period_s  servo period [s]. @param missed periods the tick started late.
  /// @param stopping  ramp out. @return the new gain.
  /// @note noexcept, O(1), real-time safe.
  double update(double period_s, int64_t missed, bool stopping) noexcept;
};

/// Median, 99th percentile and maximum of a duration [ns].
struct LatencyStats {
  /// @{ Median, 99th percentile and maximum [ns].
  double median = 0, p99 = 0, max = 0;
  /// @}
};

/// Timing of a finished run.
struct ServoStats {
  int64_t ticks = 0;            ///< ticks run
  double seconds = 0;           ///< wall time [s]
  double rate_hz = 0;           ///< achieved rate: ticks / seconds [Hz]
  LatencyStats period_ns;       ///< time between tick starts [ns]
  LatencyStats compute_ns;      ///< time inside the tick function [ns]
  int64_t overruns = 0;         ///< ticks that started more than one period late
  int64_t long_ticks = 0;       ///< ticks whose wall time from start to end exceeded the period
  int64_t cpu_long_ticks = -1;  ///< with ServoOptions::cpu_time: ticks whose CPU time exceeded the period (a long
                                ///< tick that is not one was preempted); -1 when not measured
  LatencyStats cpu_ns;          ///< with ServoOptions::cpu_time: the servo thread's CPU time per tick [ns]
  int64_t watchdog_trips = 0;   ///< ticks that started more than watchdog_ticks periods late
};

/// Tick function: called on the servo thread with the tick index and its scheduled time [s].
/// It must not allocate, lock or do I/O.
using TickFn = void (*)(void* user, int64_t tick, double time_s) noexcept;

/// Tick function with the servo context (force gain, missed ticks). Same real-time rules as TickFn.
using ServoTickFn = void (*)(void* user, const ServoTick& tick) noexcept;

/// @brief Runs the servo loop with a ServoTickFn: like the TickFn overload, plus the force envelope
/// (ramp-in at the start, ramp-out over the last ramp_out_s or after options.stop is set, the
/// watchdog) passed to every tick as ServoTick::force_gain.
/// @note At 10 kHz and above, sleep_until's wake-up jitter dominates; the loop spins (yield) for
/// the last 50 µs before each tick. Allocates only before the loop starts.
ServoStats run_servo_loop(const ServoOptions& options, ServoTickFn tick, void* user,
                          const char** realtime_note = nullptr);

/// @brief Runs @p options.ticks ticks of @p tick on a new thread (best effort SCHED_FIFO when the
/// process may use it) and waits for it.
/// @param options  rate, ticks, stop flag, watchdog and envelope settings.
/// @param tick     called once per tick on the servo thread (real-time rules).
/// @param user     passed to @p tick unchanged.
/// @param[out] realtime_note  set to a message when real-time scheduling was unavailable.
/// @return timing statistics, computed after the loop from preallocated per-tick records.
/// @note Allocates only before the loop starts (per-tick timing buffers).
ServoStats run_servo_loop(const ServoOptions& options, TickFn tick, void* user, const char** realtime_note = nullptr);

/// @brief Median, p99 and maximum of @p values (copied and partially sorted).
LatencyStats latency_stats(std::vector<double> values);

}  // namespace hdm
