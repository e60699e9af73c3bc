// SPDX-License-Identifier: MIT
#include <hdm/bridge/wire_format.h>

#include <bit>
#include <cmath>
#include <cstring>

namespace hdm::bridge {
namespace {

static_assert(std::endian::native == std::endian::little, "the bridge's wire format is little-endian: add byte swaps");

// Fixed offsets of the fields (docs/bridge.md has the table).
constexpr size_t kOffMagic = 0, kOffVersion = 4, kOffKind = 6, kOffSize = 8, kOffFlags = 12, kOffSeq = 16,
                 kOffSession = 24, kOffBody = 32;

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
void put_header(std::byte* out, PacketKind kind, uint32_t flags, uint64_t seq, uint64_t session) noexcept {
  std::memset(out, 0, kPacketBytes);
  put<uint32_t>(out, kOffMagic, kMagic);
  put<uint16_t>(out, kOffVersion, kVersion);
  put<uint16_t>(out, kOffKind, static_cast<uint16_t>(kind));
  put<uint32_t>(out, kOffSize, static_cast<uint32_t>(kPacketBytes));
  put<uint32_t>(out, kOffFlags, flags);
  put<uint64_t>(out, kOffSeq, seq);
  put<uint64_t>(out, kOffSession, session);
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
  if (get<uint16_t>(in, kOffVersion) != kVersion) return DecodeStatus::BadVersion;
  if (size != kPacketBytes || get<uint32_t>(in, kOffSize) != kPacketBytes) return DecodeStatus::BadSize;
  const uint16_t k = get<uint16_t>(in, kOffKind);
  if (k < 1 || k > 3) return DecodeStatus::BadKind;
  kind = static_cast<PacketKind>(k);
  return DecodeStatus::Ok;
}

void encode(const DevicePacket& p, std::byte* out) noexcept {
  put_header(out, PacketKind::Device, p.flags, p.sequence, p.session);
  put<double>(out, kOffBody, p.time_s);
  put3(out, kOffBody + 8, p.position);
  put3(out, kOffBody + 32, p.velocity);
  put<uint32_t>(out, kOffBody + 56, p.buttons);
}

void encode(const ForcePacket& p, std::byte* out) noexcept {
  put_header(out, PacketKind::Force, p.flags, p.sequence, p.session);
  put<uint64_t>(out, kOffBody, p.tick);
  put3(out, kOffBody + 8, p.force);
  put3(out, kOffBody + 32, p.contact_m);
  put<double>(out, kOffBody + 56, p.gain);
}

void encode(const HelloPacket& p, std::byte* out) noexcept {
  put_header(out, PacketKind::Hello, 0, 0, p.session);
  put<uint32_t>(out, kOffBody, p.secret_bytes);
  std::memcpy(out + kOffBody + 4, p.secret.data(), kMaxSecretBytes);
}

DecodeStatus decode(const std::byte* in, size_t size, HelloPacket& p) noexcept {
  if (const DecodeStatus s = check_header(in, size, PacketKind::Hello); s != DecodeStatus::Ok) return s;
  const uint64_t session = get<uint64_t>(in, kOffSession);
  const uint32_t bytes = get<uint32_t>(in, kOffBody);
  if (session == 0 || bytes > kMaxSecretBytes) return DecodeStatus::BadHello;
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
  if (!std::isfinite(t) || !x.allFinite() || !v.allFinite()) return DecodeStatus::NonFinite;
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
  if (!f.allFinite() || !c.allFinite() || !std::isfinite(g)) return DecodeStatus::NonFinite;
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
