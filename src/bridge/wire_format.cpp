// SPDX-License-Identifier: MIT
#include <hdm/bridge/wire_format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

namespace hdm::bridge {
namespace {

static_assert(std::endian::native == std::endian::little, "the bridge's wire format is little-endian: add byte swaps");

// Fixed offsets of the fields (docs/bridge.md has the table). Version 3 appends to version 2's
// 96 bytes: the device packet's orientation (w, x, y, z) and angular velocity, the force packet's
// torque.
constexpr size_t kOffMagic = 0, kOffVersion = 4, kOffKind = 6, kOffSize = 8, kOffFlags = 12, kOffSeq = 16,
                 kOffSession = 24, kOffBody = 32, kOffOrientation = 96, kOffAngular = 128, kOffTorque = 96;

uint16_t written_version(uint16_t v) noexcept { return packet_bytes(v) > 0 ? v : kVersion; }

template <class T>
void put(std::byte* out, size_t off, T v) noexcept {
  std::memcpy(out + off, &v, sizeof v);
}
template <class T>
T get(const std::byte* in, size_t off) noexcept {
  T v;
  std::memcpy(&v, in + off, sizeof v);
  return v;
}
void put3(std::byte* out, size_t off, const Vec3& v) noexcept {
  for (int i = 0; i < 3; ++i) put<double>(out, off + 8 * size_t(i), v[i]);
}
Vec3 get3(const std::byte* in, size_t off) noexcept {
  return {get<double>(in, off), get<double>(in, off + 8), get<double>(in, off + 16)};
}
// Writes the header of a packet of @p version (one read) and zeroes its body; returns its size.
size_t put_header(std::byte* out, uint16_t version, PacketKind kind, uint32_t flags, uint64_t seq,
                  uint64_t session) noexcept {
  const size_t bytes = packet_bytes(version);
  std::memset(out, 0, bytes);
  put<uint32_t>(out, kOffMagic, kMagic);
  put<uint16_t>(out, kOffVersion, version);
  put<uint16_t>(out, kOffKind, static_cast<uint16_t>(kind));
  put<uint32_t>(out, kOffSize, static_cast<uint32_t>(bytes));
  put<uint32_t>(out, kOffFlags, flags);
  put<uint64_t>(out, kOffSeq, seq);
  put<uint64_t>(out, kOffSession, session);
  return bytes;
}
DecodeStatus check_header(const std::byte* in, size_t size, PacketKind kind) noexcept {
  PacketKind k{};
  if (const DecodeStatus s = decode_kind(in, size, k); s != DecodeStatus::Ok) return s;
  return k == kind ? DecodeStatus::Ok : DecodeStatus::BadKind;
}

}  // namespace

DecodeStatus decode_kind(const std::byte* in, size_t size, PacketKind& kind) noexcept {
  if (size < kOffSize + 4) return DecodeStatus::BadSize;
  if (get<uint32_t>(in, kOffMagic) != kMagic) return DecodeStatus::BadMagic;
  const size_t bytes = packet_bytes(get<uint16_t>(in, kOffVersion));
  if (bytes == 0) return DecodeStatus::BadVersion;
  if (size != bytes || get<uint32_t>(in, kOffSize) != bytes) return DecodeStatus::BadSize;
  const uint16_t k = get<uint16_t>(in, kOffKind);
  if (k < 1 || k > 3) return DecodeStatus::BadKind;
  kind = static_cast<PacketKind>(k);
  return DecodeStatus::Ok;
}

static_assert(kPacketBytes == 152 && kPacketBytesV2 == 96, "describe() names the sizes");

const char* describe(DecodeStatus status) noexcept {
  switch (status) {
    case DecodeStatus::Ok:
      return "ok";
    case DecodeStatus::BadSize:
      return "bad size: a packet is 152 bytes (wire format version 3) or 96 (version 2), as its size field says";
    case DecodeStatus::BadMagic:
      return "bad magic: not an hdm bridge packet (\"HDMB\")";
    case DecodeStatus::BadVersion:
      return "unknown wire format version: this hdm reads versions 2 and 3 (docs/bridge.md)";
    case DecodeStatus::BadKind:
      return "bad kind: not the packet kind expected here";
    case DecodeStatus::NonFinite:
      return "a NaN or infinite number in the packet";
    case DecodeStatus::BadHello:
      return "bad hello: session id 0 or a secret longer than 56 bytes";
  }
  return "unknown decode status";
}

size_t declared_bytes(const std::byte* in, size_t size) noexcept {
  if (size < kOffSize + 4) return 0;
  return std::min<size_t>(get<uint32_t>(in, kOffSize), kPacketBytes);
}

size_t encode(const DevicePacket& p, std::byte* out) noexcept {
  const uint16_t version = written_version(p.version);
  const size_t bytes = put_header(out, version, PacketKind::Device, p.flags, p.sequence, p.session);
  put<double>(out, kOffBody, p.time_s);
  put3(out, kOffBody + 8, p.position);
  put3(out, kOffBody + 32, p.velocity);
  put<uint32_t>(out, kOffBody + 56, p.buttons);
  if (version >= 3) {
    put<double>(out, kOffOrientation, p.orientation.w());
    put3(out, kOffOrientation + 8, p.orientation.vec());
    put3(out, kOffAngular, p.angular_velocity);
  }
  return bytes;
}

size_t encode(const ForcePacket& p, std::byte* out) noexcept {
  const uint16_t version = written_version(p.version);
  const size_t bytes = put_header(out, version, PacketKind::Force, p.flags, p.sequence, p.session);
  put<uint64_t>(out, kOffBody, p.tick);
  put3(out, kOffBody + 8, p.force);
  put3(out, kOffBody + 32, p.contact_m);
  put<double>(out, kOffBody + 56, p.gain);
  if (version >= 3) put3(out, kOffTorque, p.torque);
  return bytes;
}

size_t encode(const HelloPacket& p, std::byte* out) noexcept {
  const size_t bytes = put_header(out, written_version(p.version), PacketKind::Hello, 0, 0, p.session);
  put<uint32_t>(out, kOffBody, p.secret_bytes);
  std::memcpy(out + kOffBody + 4, p.secret.data(), kMaxSecretBytes);
  return bytes;
}

DecodeStatus decode(const std::byte* in, size_t size, HelloPacket& p) noexcept {
  if (const DecodeStatus s = check_header(in, size, PacketKind::Hello); s != DecodeStatus::Ok) return s;
  const uint64_t session = get<uint64_t>(in, kOffSession);
  const uint32_t bytes = get<uint32_t>(in, kOffBody);
  if (session == 0 || bytes > kMaxSecretBytes) return DecodeStatus::BadHello;
  p.version = get<uint16_t>(in, kOffVersion);
  p.session = session;
  p.secret_bytes = bytes;
  std::memcpy(p.secret.data(), in + kOffBody + 4, kMaxSecretBytes);
  return DecodeStatus::Ok;
}

bool secret_matches(const HelloPacket& hello, std::string_view secret) noexcept {
  if (secret.size() > kMaxSecretBytes) return false;
  // Every byte compared, differences or-ed together: the time taken does not tell where a guess
  // went wrong.
  unsigned diff = hello.secret_bytes ^ static_cast<unsigned>(secret.size());
  for (size_t i = 0; i < kMaxSecretBytes; ++i) {
    const auto expected = static_cast<uint8_t>(i < secret.size() ? secret[i] : 0);
    diff |= unsigned(hello.secret[i] ^ expected);
  }
  return diff == 0;
}

bool sequence_in_window(uint64_t last, uint64_t sequence) noexcept {
  return sequence > last && sequence - last <= kSequenceWindow;  // unsigned: no overflow
}

DecodeStatus decode(const std::byte* in, size_t size, DevicePacket& p) noexcept {
  if (const DecodeStatus s = check_header(in, size, PacketKind::Device); s != DecodeStatus::Ok) return s;
  const double t = get<double>(in, kOffBody);
  const Vec3 x = get3(in, kOffBody + 8), v = get3(in, kOffBody + 32);
  const uint16_t version = get<uint16_t>(in, kOffVersion);
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  Vec3 w = Vec3::Zero();
  if (version >= 3) {
    const Vec3 qv = get3(in, kOffOrientation + 8);
    q = Eigen::Quaterniond(get<double>(in, kOffOrientation), qv.x(), qv.y(), qv.z());
    w = get3(in, kOffAngular);
  }
  if (!std::isfinite(t) || !x.allFinite() || !v.allFinite() || !q.coeffs().allFinite() || !w.allFinite())
    return DecodeStatus::NonFinite;
  p.version = version;
  p.orientation = q;
  p.angular_velocity = w;
  p.flags = get<uint32_t>(in, kOffFlags);
  p.sequence = get<uint64_t>(in, kOffSeq);
  p.session = get<uint64_t>(in, kOffSession);
  p.time_s = t;
  p.position = x;
  p.velocity = v;
  p.buttons = get<uint32_t>(in, kOffBody + 56);
  return DecodeStatus::Ok;
}

DecodeStatus decode(const std::byte* in, size_t size, ForcePacket& p) noexcept {
  if (const DecodeStatus s = check_header(in, size, PacketKind::Force); s != DecodeStatus::Ok) return s;
  const Vec3 f = get3(in, kOffBody + 8), c = get3(in, kOffBody + 32);
  const double g = get<double>(in, kOffBody + 56);
  const uint16_t version = get<uint16_t>(in, kOffVersion);
  const Vec3 torque = version >= 3 ? get3(in, kOffTorque) : Vec3::Zero();
  if (!f.allFinite() || !c.allFinite() || !std::isfinite(g) || !torque.allFinite()) return DecodeStatus::NonFinite;
  p.version = version;
  p.torque = torque;
  p.flags = get<uint32_t>(in, kOffFlags);
  p.sequence = get<uint64_t>(in, kOffSeq);
  p.session = get<uint64_t>(in, kOffSession);
  p.tick = get<uint64_t>(in, kOffBody);
  p.force = f;
  p.contact_m = c;
  p.gain = g;
  return DecodeStatus::Ok;
}

}  // namespace hdm::bridge
