// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// The driver side of the device bridge in C++ (docs/bridge.md): what a vendor driver process links
/// to send device packets to hdm and read the forces back. The wire format is the contract; this is
/// a convenience (examples/python/bridge_client.py speaks it without hdm).

#include <hdm/bridge/wire_format.h>

#include <memory>
#include <string>

namespace hdm::bridge {

/// A connection to a BridgeDevice. One thread uses it (the driver's servo loop).
class BridgeDriver {
 public:
  /// @brief Connects to hdm's endpoint, "udp:PORT" (127.0.0.1) or "shm:NAME" (the region hdm
  /// created; waits up to @p wait_s for it to appear), and opens a session: a hello packet with
  /// @p secret and a fresh random session id, sent again every 5 ms until hdm answers (shared
  /// memory: hdm's servo thread must be running).
  /// @throws InvalidInput on a malformed endpoint or a secret of the wrong size; IoError when the
  /// socket cannot be made, the region does not appear (or is not a bridge region of this
  /// version), or hdm does not answer the hello (a wrong secret) within @p wait_s.
  static std::unique_ptr<BridgeDriver> connect(const std::string& endpoint, const std::string& secret,
                                               double wait_s = 5.0);
  virtual ~BridgeDriver() = default;
  /// @brief Sends @p packet in this driver's session (its session field is set here; encoded in
  /// packet.version, kVersion by default: pose with orientation and angular velocity; UDP: a
  /// non-blocking send; shm: a seqlocked write). noexcept, O(1); false when the UDP send failed.
  bool send(const DevicePacket& packet) noexcept;
  /// @brief The newest valid force packet of this driver's session that came since the last call,
  /// if any. noexcept, O(1) (UDP: drains the socket without waiting; shm: one seqlocked read).
  bool poll_force(ForcePacket& out) noexcept;
  /// The session id of this driver's hello.
  uint64_t session() const noexcept { return session_; }
  /// @brief Waits up to @p timeout_s for a force packet answering @p sequence or a later one (UDP:
  /// ppoll(2); shm: spins). Only forces that come after the call count: one poll_force() already
  /// returned is not seen again. noexcept; false on timeout.
  bool wait_force(ForcePacket& out, uint64_t sequence, double timeout_s) noexcept;

 protected:
  /// Waits until a force may have come or @p timeout_s passed (UDP: ppoll; shm: returns at once).
  virtual void idle(double timeout_s) noexcept = 0;
  /// Sends an encoded packet of @p size bytes (UDP: a datagram of them; shm: the device block,
  /// kPacketBytes bytes from @p raw). noexcept.
  virtual bool send_bytes(const std::byte* raw, size_t size) noexcept = 0;
  /// The newest force packet of @p session since the last call. noexcept.
  virtual bool read_force(ForcePacket& out, uint64_t session) noexcept = 0;

 private:
  void hello(const std::string& endpoint, const std::string& secret, double wait_s);
  uint64_t session_ = 0;
};

}  // namespace hdm::bridge
