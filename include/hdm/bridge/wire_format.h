// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// The device bridge's wire format (docs/bridge.md): fixed-size, little-endian packets with a
/// versioned header, the same bytes over UDP and in the shared-memory region. A device packet
/// (handle position, velocity, orientation, angular velocity, buttons, time, sequence number) goes
/// from the driver process to hdm; a force packet (force, torque, surface contact point, the
/// sequence number echoed, the servo tick) comes back. Version 3 is version 2 (96 bytes, no
/// orientation or torque) with the 6-DOF fields appended; both are read, and hdm answers a driver in
/// the version it speaks. A driver session starts with a hello packet carrying the shared secret and a fresh
/// session id; every packet of the session carries that id.

#include <hdm/core/types.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace hdm::bridge {

/// First four bytes of every packet: "HDMB" (0x42 0x4D 0x44 0x48 as a little-endian u32 is 0x424D4448).
inline constexpr uint32_t kMagic = 0x424D4448u;
/// Wire format version written by default; a packet of a version other than kVersion or
/// kOldestVersion is dropped (counted as bad_version).
inline constexpr uint16_t kVersion = 3;
/// Oldest version still read: version 2 packets (kPacketBytesV2 long, no orientation, angular
/// velocity or torque) decode with the identity orientation and zero angular velocity, and a force
/// packet encoded as version 2 carries no torque.
inline constexpr uint16_t kOldestVersion = 2;
/// Size of every version 3 packet [bytes], all kinds alike (a multiple of 8: the shared-memory
/// region copies it as 64-bit words); the largest packet of any version read.
inline constexpr size_t kPacketBytes = 152;
/// Size of every version 2 packet [bytes]: the first kPacketBytesV2 bytes of a version 3 packet
/// laid out alike, the version and size fields aside.
inline constexpr size_t kPacketBytesV2 = 96;

/// @brief The size [bytes] of a packet of wire format @p version: kPacketBytes for 3,
/// kPacketBytesV2 for 2, 0 for a version not read. noexcept, O(1).
constexpr size_t packet_bytes(uint16_t version) noexcept {
  return version == 3 ? kPacketBytes : version == 2 ? kPacketBytesV2 : 0;
}
/// Most bytes a shared secret may have (what a hello packet carries).
inline constexpr size_t kMaxSecretBytes = 56;
/// Fewest bytes a shared secret may have: a shorter one is refused when the bridge opens.
inline constexpr size_t kMinSecretBytes = 16;
/// A device packet is accepted when its sequence number lies 1 to kSequenceWindow above the last
/// accepted one of its session (the first of a session: 1 to kSequenceWindow): a packet from far
/// ahead can neither lock the session out nor be taken for a later one.
inline constexpr uint64_t kSequenceWindow = 65536;

/// Packet kinds (header field `kind`).
enum class PacketKind : uint16_t { Device = 1, Force = 2, Hello = 3 };

/// Flags of a device packet.
enum DeviceFlags : uint32_t {
  kDeviceEnd = 1u << 0,  ///< the driver is closing: the packet's state is not applied, the session ends
};

/// Flags of a force packet.
enum ForceFlags : uint32_t {
  kForceContact = 1u << 0,   ///< the proxy is on the surface (contact_m is the surface contact point)
  kForceWatchdog = 1u << 1,  ///< packets stopped: the force is ramping out and the tool is released
  kForceToolOn = 1u << 2,    ///< the tool button is held as hdm sees it
};

/// Device → hdm: one reading of the handle, hdm's device frame (right-handed, metres, the
/// workspace centre at the origin; the driver maps its vendor's axes and units).
struct DevicePacket {
  uint16_t version = kVersion;   ///< wire format version (kOldestVersion or kVersion); encode() writes it
  uint32_t flags = 0;            ///< DeviceFlags
  uint64_t sequence = 0;         ///< strictly increasing per driver session (≥ 1); older or equal ones are dropped
  uint64_t session = 0;          ///< the session id of the driver's hello packet
  double time_s = 0;             ///< device time of the reading [s] (informative)
  Vec3 position = Vec3::Zero();  ///< handle position [m]
  Vec3 velocity = Vec3::Zero();  ///< handle velocity [m/s]
  uint32_t buttons = 0;          ///< button bit mask (bit 0: the tool button)
  /// Handle orientation, tool frame → device frame, as sent (w, x, y, z on the wire; need not be
  /// unit: BridgeDevice normalises it). Version 2: identity.
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  Vec3 angular_velocity = Vec3::Zero();  ///< handle angular velocity [rad/s]; version 2: zero
};

/// hdm → device: the force to command until the next packet.
struct ForcePacket {
  uint16_t version = kVersion;    ///< wire format version (kOldestVersion or kVersion); encode() writes it
  uint32_t flags = 0;             ///< ForceFlags
  uint64_t sequence = 0;          ///< sequence number of the device packet this force answers (0: none yet)
  uint64_t session = 0;           ///< the session admitted (0: none yet); a driver ignores other sessions' forces
  uint64_t tick = 0;              ///< servo tick that computed it
  Vec3 force = Vec3::Zero();      ///< force [N], device frame, after the watchdog's gain
  Vec3 contact_m = Vec3::Zero();  ///< surface contact point of the proxy [m, device frame] of the previous
                                  ///< tick (kForceContact), else the handle position
  double gain = 1;                ///< watchdog gain applied to the force, in [0, 1]
  /// Torque [N·m] about the handle's tip point, device frame, after the watchdog's gain; version 2
  /// carries none (encoded: dropped; decoded: zero).
  Vec3 torque = Vec3::Zero();
};

/// Driver → hdm: opens a driver session (a restarted driver sends a new one and is served at once;
/// packets of the old session are ignored from then on).
struct HelloPacket {
  uint16_t version = kVersion;                    ///< wire format version the driver speaks
  uint64_t session = 0;                           ///< fresh random id, not 0, chosen by the driver
  uint32_t secret_bytes = 0;                      ///< bytes of @ref secret used (≤ kMaxSecretBytes)
  std::array<uint8_t, kMaxSecretBytes> secret{};  ///< the shared secret (docs/bridge.md), zero-padded
};

/// Why a packet was refused (or Ok).
enum class DecodeStatus : uint8_t {
  Ok,
  BadSize,     ///< not packet_bytes(version) long (truncated or padded), or the header's size field disagrees
  BadMagic,    ///< the first four bytes are not "HDMB"
  BadVersion,  ///< a version other than kOldestVersion and kVersion
  BadKind,     ///< not the kind expected here
  NonFinite,   ///< a NaN or infinite time, position, velocity, orientation, angular velocity, force or torque
  BadHello,    ///< a hello packet whose session id is 0, or with a secret length beyond kMaxSecretBytes
};

/// @brief What @p status means, for a log line or an error message: names the versions read for
/// BadVersion and the sizes expected for BadSize. noexcept; a static string.
const char* describe(DecodeStatus status) noexcept;
/// @brief Writes @p p in wire format p.version (kVersion when it is not one read) as little-endian
/// bytes into @p out, which holds kPacketBytes.
/// @return the bytes written: packet_bytes() of the version. noexcept, O(1), no allocation.
size_t encode(const DevicePacket& p, std::byte* out) noexcept;
/// @brief Writes @p p as encode(const DevicePacket&, std::byte*) does (version 2: the torque dropped).
/// @return the bytes written. noexcept, O(1), no allocation.
size_t encode(const ForcePacket& p, std::byte* out) noexcept;
/// @brief Writes @p p as encode(const DevicePacket&, std::byte*) does. @return the bytes written.
/// noexcept, O(1), no allocation.
size_t encode(const HelloPacket& p, std::byte* out) noexcept;
/// @brief The kind of the packet at @p in after checking size, magic and version (not the body);
/// anything but Ok leaves @p kind unchanged. noexcept, O(1).
/// @param in    the packet's bytes.
/// @param size  how many: packet_bytes() of the header's version.
/// @param[out] kind  the packet's kind (when Ok).
DecodeStatus decode_kind(const std::byte* in, size_t size, PacketKind& kind) noexcept;
/// @brief The packet size the header at @p in declares (its size field), at most kPacketBytes;
/// 0 when @p size is too short to hold the field. How a reader of a shared-memory block, which
/// always holds kPacketBytes, learns how many of them the packet has. noexcept, O(1).
size_t declared_bytes(const std::byte* in, size_t size) noexcept;
/// @brief Reads a device packet (version 2 or 3) from @p size bytes at @p in, checking size, magic,
/// version, kind and that every number is finite; @p p is written only when the result is Ok.
/// Version 2 gives the identity orientation and zero angular velocity. noexcept, O(1).
DecodeStatus decode(const std::byte* in, size_t size, DevicePacket& p) noexcept;
/// @brief Reads a force packet, with the same checks as the device packet's decode (version 2:
/// zero torque). noexcept, O(1).
DecodeStatus decode(const std::byte* in, size_t size, ForcePacket& p) noexcept;
/// @brief Reads a hello packet (session not 0, secret length within kMaxSecretBytes). noexcept, O(1).
DecodeStatus decode(const std::byte* in, size_t size, HelloPacket& p) noexcept;
/// @brief True when @p hello carries exactly @p secret. Compares every byte whatever differs first
/// (no timing tells how much of a guess was right). noexcept, O(kMaxSecretBytes).
bool secret_matches(const HelloPacket& hello, std::string_view secret) noexcept;
/// @brief True when @p sequence may follow @p last in one session: 1 to kSequenceWindow above it
/// (@p last = 0 before the session's first packet). noexcept, O(1).
bool sequence_in_window(uint64_t last, uint64_t sequence) noexcept;

}  // namespace hdm::bridge
