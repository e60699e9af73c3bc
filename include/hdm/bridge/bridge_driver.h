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
  /// @brief Connects to hdm's endpoint: "udp:PORT" (127.0.0.1) or "shm:NAME" (the region hdm
  /// created; waits up to @p wait_s for it to appear).
  /// @throws InvalidInput on a malformed endpoint; IoError when the socket cannot be made or the
  /// region does not appear (or is not a bridge region of this version) within @p wait_s.
  static std::unique_ptr<BridgeDriver> connect(const std::string& endpoint, double wait_s = 5.0);
  virtual ~BridgeDriver() = default;
  /// @brief Sends @p packet (UDP: a non-blocking send; shm: a seqlocked write). noexcept, O(1);
  /// false when the UDP send failed.
  virtual bool send(const DevicePacket& packet) noexcept = 0;
  /// @brief The newest valid force packet that came since the last call, if any. noexcept, O(1)
  /// (UDP: drains the socket without waiting; shm: one seqlocked read).
  virtual bool poll_force(ForcePacket& out) noexcept = 0;
  /// @brief Waits up to @p timeout_s for a force packet answering @p sequence or a later one (UDP:
  /// ppoll(2); shm: spins). Only forces that come after the call count: one poll_force() already
  /// returned is not seen again. noexcept; false on timeout.
  bool wait_force(ForcePacket& out, uint64_t sequence, double timeout_s) noexcept;

 protected:
  /// Waits until a force may have come or @p timeout_s passed (UDP: ppoll; shm: returns at once).
  virtual void idle(double timeout_s) noexcept = 0;
};

}  // namespace hdm::bridge
