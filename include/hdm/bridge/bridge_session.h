// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// A servo loop clocked by the device: one SculptSession tick per device packet, as soon as it
/// arrives (the driver's own servo loop is the clock, as a vendor scheduler callback would be).
/// The round trip is then the transport plus one tick, not a wait for hdm's next period
/// (docs/bridge.md). hdm::run_session with a BridgeDevice is the other way: hdm's clock, the newest
/// packet each tick.

#include <hdm/bridge/bridge_device.h>
#include <hdm/session/sculpt_session.h>

#include <atomic>
#include <cstdint>

namespace hdm::bridge {

/// Settings of run_bridge_session.
struct BridgeLoopOptions {
  /// While the watchdog holds (packets overdue), tick anyway every this many seconds so the force
  /// ramps out and the stroke ends [s].
  double idle_period_s = 0.001;
  /// Ends the loop when set (from another thread), at once: the driver's own watchdog then ramps its
  /// force out. The loop also ends on the driver's kDeviceEnd.
  std::atomic<bool>* stop = nullptr;
  /// Ends the loop after this long without any device packet [s] (0: never).
  double give_up_s = 0;
  /// Before the first packet, ends the loop after this long instead of give_up_s [s] (0: give_up_s
  /// applies from the start too): a driver process may take seconds to start on a loaded machine.
  double first_packet_s = 0;
  /// true: spin between packets (lowest latency, one core busy); false: sleep 50 µs between looks.
  bool spin = true;
  /// Run the loop at SCHED_FIFO (priority max - 1, as hdm::run_servo_loop) when the process may,
  /// restoring the thread's policy after: on a loaded machine a normal thread waits for the
  /// scheduler's slices (milliseconds) and the watchdog trips. With spin, the thread then keeps a
  /// core to itself (up to the kernel's real-time throttling).
  bool realtime = false;
};

/// What run_bridge_session did.
struct BridgeLoopStats {
  int64_t ticks = 0;       ///< session ticks
  int64_t idle_ticks = 0;  ///< ticks without a new packet (watchdog held)
  bool ended = false;      ///< the driver sent kDeviceEnd
  bool gave_up = false;    ///< give_up_s passed without a packet
  bool realtime = false;   ///< the loop ran at SCHED_FIFO
};

/// @brief Runs @p session on the calling thread, one tick per new device packet of @p device (and
/// every idle_period_s while the watchdog holds), until the driver's end packet, options.stop or
/// options.give_up_s. Calls @p hooks around each tick and BridgeDevice::set_contact after it. Does
/// not call session.finish().
/// @note The caller's thread is the servo thread: no allocation, lock or I/O inside the loop (the
/// waiting is a spin with pause or a 50 µs sleep, never on another thread). ServoTick::time_s is the
/// driver's time of the packet (DevicePacket::time_s: the driver's clock is the servo's clock; an
/// idle tick adds the time since that packet came, and before the first one counts from the start)
/// [s]; force_gain is 1 (the device's watchdog gain ramps the force).
BridgeLoopStats run_bridge_session(SculptSession& session, BridgeDevice& device, const BridgeLoopOptions& options = {},
                                   const SessionHooks& hooks = {});

}  // namespace hdm::bridge
