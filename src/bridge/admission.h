// SPDX-License-Identifier: MIT
#pragma once
// Internal: who may drive the bridge. A hello packet with the shared secret opens a driver session
// (a restarted driver opens a new one and is served at once); a device packet is admitted only
// with the current session's id and a sequence number within the window above the last one.
// One thread judges (UDP's receiver, or the servo thread for shared memory): noexcept, O(1), no
// allocation, no system call.
#include <hdm/bridge/wire_format.h>

#include <cstdint>
#include <string>

namespace hdm::bridge {

/// What admit() made of a datagram or a block's packet.
enum class Verdict : uint8_t {
  Device,        ///< a device packet of the current session, in the window: apply it
  Hello,         ///< a hello with the right secret: a new session (answer it)
  HelloAgain,    ///< the current session's hello once more (a driver that did not see the answer): answer it
  Refused,       ///< malformed (the DecodeStatus says why)
  BadSecret,     ///< a hello whose secret is wrong
  WrongSession,  ///< a device packet of another (or no) session
  OutOfWindow,   ///< a device packet of the session whose sequence number is not 1 to kSequenceWindow ahead
  NotForUs,      ///< a force packet (sent the wrong way)
};

class Admission {
 public:
  explicit Admission(std::string secret) : secret_(std::move(secret)) {}
  /// Judges the packet of @p size bytes at @p raw that came from @p sender (UDP: its address and
  /// port; shared memory: 0); a device packet must come from the sender of its session's hello.
  /// With Device, @p device holds it; with Refused, @p status says why.
  Verdict admit(const std::byte* raw, size_t size, uint64_t sender, DevicePacket& device,
                DecodeStatus& status) noexcept;
  /// The current session's id (0: none yet).
  uint64_t session() const noexcept { return session_; }
  /// The wire format version of the current session's hello (what its answers are encoded in).
  uint16_t version() const noexcept { return version_; }

 private:
  std::string secret_;
  uint64_t session_ = 0, last_sequence_ = 0, sender_ = 0;
  uint16_t version_ = kVersion;
};

}  // namespace hdm::bridge
