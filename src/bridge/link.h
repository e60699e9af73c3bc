// SPDX-License-Identifier: MIT
#pragma once
// Internal: the seqlocked blocks where the servo thread meets a transport, and the transports.
//
// A block is one 64-bit sequence word followed by a packet (kPacketBytes, as 64-bit words). Its one
// writer makes the word odd, writes the packet, makes it even again; a reader copies the packet
// between two reads of an equal, even word, or tries again later (never waits on the writer).
// Every word is accessed atomically (std::atomic_ref, relaxed, with fences), so the blocks also
// work between processes in shared memory and are clean under ThreadSanitizer.
#include <hdm/bridge/bridge_device.h>

#include "admission.h"

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

namespace hdm::bridge {

inline constexpr size_t kWords = kPacketBytes / 8;
static_assert(kPacketBytes % 8 == 0);

/// Shared-memory region layout (docs/bridge.md): header, then the device block and the force block
/// on cache lines of their own.
inline constexpr uint32_t kRegionMagic = 0x524D4448u;  // "HDMR"
inline constexpr uint16_t kRegionVersion = 3;
inline constexpr size_t kRegionDeviceBlock = 64, kRegionForceBlock = 256, kRegionBytes = 448;
static_assert(kRegionDeviceBlock + 8 + kPacketBytes <= kRegionForceBlock &&
              kRegionForceBlock + 8 + kPacketBytes <= kRegionBytes);

/// Writer side of a block (one writer thread or process). noexcept, O(kWords).
void seqlock_write(uint64_t* block, const std::byte* packet) noexcept;
/// Reader side: copies the packet into @p out and its sequence word into @p version; false when a
/// write was under way on every one of a few tries. noexcept, O(kWords), never waits.
bool seqlock_read(uint64_t* block, std::byte* out, uint64_t& version) noexcept;
/// The block's sequence word (acquire). noexcept.
uint64_t seqlock_version(uint64_t* block) noexcept;

/// What the transports and the servo side count.
struct LinkCounters {
  std::atomic<int64_t> accepted{0}, bad_size{0}, bad_magic{0}, bad_version{0}, bad_kind{0}, non_finite{0},
      out_of_order{0}, bad_secret{0}, wrong_session{0}, hellos{0}, watchdog_trips{0}, forces_sent{0}, send_errors{0};
  void refuse(DecodeStatus s) noexcept;
  /// Counts a packet admit() did not apply (a hello counts as a session opened).
  void count(Verdict v, DecodeStatus s) noexcept;
};

struct BridgeDevice::Link {
  explicit Link(const std::string& secret) : admission(secret) {}
  virtual ~Link() = default;
  uint64_t* device_block = nullptr;  // written by the driver (shm) or the receiver thread (UDP)
  uint64_t* force_block = nullptr;   // written by the servo thread
  LinkCounters counters;
  Admission admission;    // used by one thread: UDP's receiver, or the servo thread (shared memory)
  bool admitted = false;  // the transport writes only admitted device packets (UDP's receiver)
  int port = 0;
  /// Servo thread, after writing the force block: UDP wakes its sender. noexcept, never waits.
  virtual void forces_posted() noexcept {}
};

/// UDP on 127.0.0.1:port (0: any free port), admitting the driver that knows @p secret. Throws IoError.
std::unique_ptr<BridgeDevice::Link> open_udp_link(int port, const std::string& secret);
/// POSIX shared memory "/name" (mode 0600), admitting the driver that knows @p secret. Throws IoError.
std::unique_ptr<BridgeDevice::Link> open_shm_link(const std::string& name, const std::string& secret);

}  // namespace hdm::bridge
