// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// A HapticDevice fed by a driver process through the device bridge (docs/bridge.md): device
/// packets in, force packets out, over UDP on localhost or a POSIX shared-memory region. The servo
/// thread never does I/O and never waits: both transports meet it at a pair of seqlocked blocks
/// (the shared-memory region itself, or an in-process copy of it that a receiver thread fills from
/// the socket and a sender thread sends from).

#include <hdm/bridge/wire_format.h>
#include <hdm/haptics/device.h>

#include <cstdint>
#include <memory>
#include <string>

namespace hdm::bridge {

/// Settings of a BridgeDevice.
struct BridgeOptions {
  /// No new device packet for this long [s]: the tool is released (buttons read 0) and the force
  /// ramps out. 5 ms is five periods at 1 kHz: one lost packet never trips it.
  double watchdog_s = 0.005;
  /// The watchdog's gain moves between 0 and 1 at 1/ramp_s per second [s]: out after a trip, back in
  /// when packets resume and at the start (no force step either way).
  double ramp_s = 0.005;
  DeviceSpec spec;  ///< reported capabilities; the force sent is clamped to spec.max_force_n
  /// The shared secret a driver's hello must carry (kMinSecretBytes to kMaxSecretBytes bytes;
  /// load_bridge_secret() reads it from a private file or the environment). Required.
  std::string secret;
};

/// Packets seen by a BridgeDevice since it opened (bad ones are dropped, never applied).
struct BridgeCounters {
  int64_t accepted = 0;     ///< device packets applied
  int64_t bad_size = 0;     ///< short, long, or a size field that disagrees
  int64_t bad_magic = 0;    ///< not "HDMB"
  int64_t bad_version = 0;  ///< another wire format version
  int64_t bad_kind = 0;     ///< not a device packet
  int64_t non_finite = 0;   ///< NaN or infinite time, position or velocity
  int64_t out_of_order =
      0;                   ///< sequence number not 1 to kSequenceWindow above the session's last (duplicates included)
  int64_t bad_secret = 0;  ///< hello packets with a wrong secret (or a malformed hello)
  int64_t wrong_session = 0;   ///< device packets of another session, or from another address than its hello's (UDP)
  int64_t sessions = 0;        ///< hello packets accepted: driver sessions opened
  int64_t watchdog_trips = 0;  ///< times packets stopped for longer than the watchdog
  int64_t forces_sent = 0;     ///< force packets posted by the servo thread (UDP: the sender sends the newest)
  int64_t send_errors = 0;     ///< UDP sends that failed (no peer yet is not one)
  /// Sum of the refusals.
  int64_t dropped() const noexcept {
    return bad_size + bad_magic + bad_version + bad_kind + non_finite + out_of_order + bad_secret + wrong_session;
  }
};

/// The device side of the bridge. Created by open(); begin_frame, end_frame, set_contact and
/// packet_waiting on the servo thread only; counters(), port() and endpoint() from any thread.
class BridgeDevice final : public HapticDevice {
 public:
  /// @brief Opens a bridge endpoint.
  /// @param endpoint  "udp:PORT": a UDP socket bound to 127.0.0.1:PORT (0: a free port, see port());
  ///                  force packets go to the address of the last accepted device packet.
  ///                  "shm:NAME": creates the POSIX shared-memory region "/NAME" (shm_open; NAME of
  ///                  letters, digits, '.', '_', '-'; an existing one is taken over and cleared),
  ///                  unlinked when the device is destroyed; mode 0600, and a region of another
  ///                  user is refused.
  ///                  Either way only a driver whose hello packet carries options.secret is served.
  /// @param options   watchdog, ramp, the device spec reported to the session and the secret.
  /// @throws InvalidInput on a malformed endpoint or options (naming them; a secret shorter than
  /// kMinSecretBytes or longer than kMaxSecretBytes included); IoError when the socket or region
  /// cannot be created (with the system's reason).
  /// @note Starts the receiver and sender threads (UDP); allocates. Not real-time.
  static std::unique_ptr<BridgeDevice> open(const std::string& endpoint, const BridgeOptions& options = {});
  ~BridgeDevice() override;
  BridgeDevice(const BridgeDevice&) = delete;
  BridgeDevice& operator=(const BridgeDevice&) = delete;

  /// @brief The newest device packet of the driver's session (checked: bad, foreign and
  /// out-of-window ones are counted and skipped; shared memory: a hello is answered here).
  /// Before the first packet the position is NaN (zero force, the proxy waits); after watchdog_s
  /// without a new one the last position and orientation are held, the velocity, angular velocity
  /// and buttons read 0. The orientation is the packet's normalised (identity for a version 2
  /// driver or a zero quaternion).
  /// @return false once the driver sent a packet with kDeviceEnd.
  /// @note noexcept; reads the seqlocked block and the steady clock (vDSO): no system call, no wait.
  bool begin_frame(DeviceState& state) noexcept override;
  /// @brief Posts @p force_n [N, device frame] times the watchdog gain (clamped to
  /// spec().max_force_n, NaN → 0) with the session, the last accepted sequence number and this tick.
  /// @note noexcept, O(1). Shared memory: a seqlocked write. UDP: the same, then a futex wake of
  /// the sender thread (a system call that never waits; the send itself is the sender's).
  void end_frame(const Vec3& force_n) noexcept override;
  /// @brief As end_frame(force_n), with @p torque_nm [N·m, device frame, about the tip] times the
  /// watchdog gain, clamped to spec().max_torque_nm (0, the default: none sent; NaN → 0). A
  /// version 2 driver's force packets carry no torque.
  /// @note noexcept, O(1).
  void end_frame(const Vec3& force_n, const Vec3& torque_nm) noexcept override;
  /// The options' spec.
  DeviceSpec spec() const noexcept override { return options_.spec; }

  /// @brief The surface contact point [m, device frame] to report with the next forces (servo
  /// thread, after a tick: the proxy's point when @p contact). noexcept.
  void set_contact(const Vec3& point_m, bool contact) noexcept;
  /// @brief True when a device packet was written since the last begin_frame (it may still be
  /// refused). Servo thread; noexcept, one atomic load.
  bool packet_waiting() const noexcept;
  /// @brief Takes a device packet written since the last look, if any (begin_frame does the same
  /// first); true when one was accepted (a refused one is counted and skipped). Servo thread;
  /// noexcept, O(1), no system call.
  bool receive() noexcept;
  /// The last accepted device packet (sequence 0 and a NaN position before the first). Servo thread.
  const DevicePacket& last_packet() const noexcept { return last_; }
  /// The options given at open().
  const BridgeOptions& options() const noexcept { return options_; }
  /// True while packets are overdue (watchdog tripped) or none came yet. Servo thread.
  bool stale() const noexcept { return stale_; }
  /// The watchdog's gain of the last tick, in [0, 1]. Servo thread.
  double gain() const noexcept { return gain_; }
  /// Counters so far. Any thread; relaxed reads (each counter exact, the set not one instant).
  BridgeCounters counters() const noexcept;
  /// The UDP port bound (0 for shared memory). Any thread.
  int port() const noexcept;
  /// The endpoint as opened ("udp:PORT" with the port bound, or "shm:NAME").
  const std::string& endpoint() const noexcept { return endpoint_; }

  struct Link;  ///< a transport (internal)

 private:
  BridgeDevice(std::unique_ptr<Link> link, const BridgeOptions& options, std::string endpoint);
  bool poll(int64_t now_ns) noexcept;
  void post(ForcePacket& p) noexcept;

  std::unique_ptr<Link> link_;
  BridgeOptions options_;
  std::string endpoint_;
  // servo thread only
  DevicePacket last_;
  uint64_t seen_version_ = 0;
  int64_t last_new_ns_ = 0, last_frame_ns_ = 0;
  uint64_t tick_ = 0, session_ = 0;
  uint16_t version_ = kVersion;  // of the session's last hello or device packet: answers are encoded in it
  double gain_ = 0;
  bool have_ = false, stale_ = true, ended_ = false, contact_ = false;
  Vec3 contact_m_ = Vec3::Zero();
};

}  // namespace hdm::bridge
