// SPDX-License-Identifier: MIT
#pragma once
// The servo loop of the studio on its own thread: a SculptSession ticking at 1 or 10 kHz whatever
// the frame rate, with live statistics and the tool's state for the render thread, which never
// blocks it (everything it reads is written wait-free, the model only through SlabSnapshots).
#include "latest_value.h"

#include <hdm/bridge/bridge_device.h>
#include <hdm/haptics/device.h>
#include <hdm/session/sculpt_session.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <thread>

namespace hdm::studio {

/// The tool as the last tick left it, model frame.
struct ToolState {
  Vec3 hip = Vec3::Zero();          ///< haptic interaction point [model units]
  Vec3 proxy = Vec3::Zero();        ///< surface contact point of the proxy [model units] (contact only)
  Vec3 normal = Vec3::UnitZ();      ///< surface normal at the proxy (contact only)
  Vec3 force = Vec3::Zero();        ///< force rendered [N] (device axes = model axes)
  bool contact = false;             ///< the proxy is on the surface
  bool ball = false;                ///< the tool is felt as a ball (RenderMode::Sphere)
  Vec3 ball_centre = Vec3::Zero();  ///< ball: its centre, held outside the surface [model units]
  bool rigid = false;               ///< the tool is a rigid tool with torque (RenderMode::RigidTool)
  /// Rigid tool: the god-object's orientation (tool frame → model frame); its tip is ball_centre.
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  Vec3 torque = Vec3::Zero();  ///< rigid tool: torque rendered [N·m] about the tip
  int32_t tool_contacts = 0;   ///< rigid tool: shell points pushing the god-object
  ToolPartContacts head;       ///< rigid tool: the head's contacts (SessionTick::head)
  ToolPartContacts shaft;      ///< rigid tool: the shaft's contacts (SessionTick::shaft)
  bool tool_on = false;        ///< the tool button is held
  bool edit_pending = false;   ///< edit work carried over to the next tick
  int64_t tick = 0;            ///< tick index
};

/// Live servo figures over the last second, read by the render thread.
struct ServoFigures {
  double rate_hz = 0;      ///< ticks in the last second
  double tick_p99_ns = 0;  ///< 99th percentile of the tick's work (session tick) [ns]
  int64_t late_ticks = 0;  ///< ticks that started a period or more late, since the start
  int64_t ticks = 0;       ///< ticks since the start
  int64_t sweeps = 0;      ///< edit sweeps since the start
};

/// Runs run_session() on a thread of its own until stop().
class ServoThread {
 public:
  /// @brief Starts the loop at @p rate_hz with @p session and @p device, which must outlive it.
  /// @p bridge: the same device when it comes through the bridge, so that each force packet carries
  /// the surface contact point of the tick before (as run_bridge_session sends it); else null.
  /// @p lockstep: the loop runs only the ticks step() grants, back to back (ServoOptions::realtime
  /// false, so no tick counts as late), instead of in real time.
  ServoThread(SculptSession& session, HapticDevice& device, double rate_hz, bridge::BridgeDevice* bridge = nullptr,
              bool lockstep = false);
  /// Stops the loop (ramping the force out) and joins.
  ~ServoThread();
  /// Requests the end, waits for it and returns the run's statistics (the kept window's
  /// medians; every tick's counts). Idempotent.
  const ServoStats& stop();
  /// The newest tool state. Render thread only (one reader).
  const ToolState& tool() noexcept { return tool_.read(); }
  /// Figures over the last second. Any one thread; O(ring).
  ServoFigures figures() const;
  /// True once the device has ended (a replay's last row, the bridge driver's end packet): the loop
  /// then ramps the force out and stops. Any thread.
  bool ended() const noexcept { return ended_.load(std::memory_order_acquire); }
  /// Ticks run so far.
  int64_t ticks() const noexcept { return ticks_.load(std::memory_order_relaxed); }
  /// @brief Lockstep: grants @p n more ticks and waits until the loop has run them (or has ended
  /// or is stopping). Render thread only; without lockstep it returns at once.
  void step(int64_t n);
  double rate_hz() const noexcept { return rate_hz_; }
  /// After stop(): why the servo thread ran without real-time scheduling (null: it had SCHED_FIFO).
  const char* realtime_note() const noexcept { return note_; }

 private:
  static void before(void* user, SculptSession&, const ServoTick& tick) noexcept;
  static void after(void* user, const ServoTick& tick, const SessionTick& result) noexcept;

  static constexpr int kRing = 16384;  // ≥ one second at 10 kHz
  SculptSession& session_;
  bridge::BridgeDevice* bridge_;
  bool ball_;   // the session feels the tool as a ball
  bool rigid_;  // the session feels the tool as a rigid tool with torque
  double rate_hz_;
  bool lockstep_;
  std::atomic<int64_t> granted_{0};  // lockstep: ticks the loop may run
  std::atomic<bool> stop_{false};
  std::thread thread_;
  ServoStats stats_;
  const char* note_ = nullptr;
  bool joined_ = false;
  // servo thread only
  int64_t tick_start_ns_ = 0;
  // written by the servo thread, read by others
  LatestValue<ToolState> tool_;
  std::array<std::atomic<uint32_t>, kRing> work_ns_{};
  std::array<std::atomic<int64_t>, kRing> start_ns_{};  // tick start, steady clock [ns]
  std::atomic<int64_t> ticks_{0}, late_{0}, sweeps_{0};
  std::atomic<bool> ended_{false};
};

}  // namespace hdm::studio
