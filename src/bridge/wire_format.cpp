// SPDX-License-Identifier: MIT
#include <hdm/bridge/wire_format.h>

#include <bit>
#include <cmath>
#include <cstring>

namespace hdm::bridge {
namespace {

static_assert(std::endian::native == std::endian::little, "the bridge's wire format is little-endian: add byte swaps");

// Fixed offsets of the fields (docs/bridge.md has the table).
constexpr size_t kOffMagic = 0, kOffVersion = 4, kOffKind = 6, kOffSize = 8, kOffFlags = 12, kOffSeq = 16;

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
void put_header(std::byte* out, PacketKind kind, uint32_t flags, uint64_t seq) noexcept {
  put<uint32_t>(out, kOffMagic, kMagic);
  put<uint16_t>(out, kOffVersion, kVersion);
  put<uint16_t>(out, kOffKind, static_cast<uint16_t>(kind));
  put<uint32_t>(out, kOffSize, static_cast<uint32_t>(kPacketBytes));
  put<uint32_t>(out, kOffFlags, flags);
  put<uint64_t>(out, kOffSeq, seq);
}
DecodeStatus check_header(const std::byte* in, size_t size, PacketKind kind) noexcept {
  if (size < kOffSize + 4) return DecodeStatus::BadSize;
  if (get<uint32_t>(in, kOffMagic) != kMagic) return DecodeStatus::BadMagic;
  if (get<uint16_t>(in, kOffVersion) != kVersion) return DecodeStatus::BadVersion;
  if (size != kPacketBytes || get<uint32_t>(in, kOffSize) != kPacketBytes) return DecodeStatus::BadSize;
  if (get<uint16_t>(in, kOffKind) != static_cast<uint16_t>(kind)) return DecodeStatus::BadKind;
  return DecodeStatus::Ok;
}

}  // namespace

void encode(const DevicePacket& p, std::byte* out) noexcept {
  put_header(out, PacketKind::Device, p.flags, p.sequence);
  put<double>(out, 24, p.time_s);
  put3(out, 32, p.position);
  put3(out, 56, p.velocity);
  put<uint32_t>(out, 80, p.buttons);
  put<uint32_t>(out, 84, 0);
}

void encode(const ForcePacket& p, std::byte* out) noexcept {
  put_header(out, PacketKind::Force, p.flags, p.sequence);
  put<uint64_t>(out, 24, p.tick);
  put3(out, 32, p.force);
  put3(out, 56, p.contact_m);
  put<double>(out, 80, p.gain);
}

DecodeStatus decode(const std::byte* in, size_t size, DevicePacket& p) noexcept {
  if (const DecodeStatus s = check_header(in, size, PacketKind::Device); s != DecodeStatus::Ok) return s;
  const double t = get<double>(in, 24);
  const Vec3 x = get3(in, 32), v = get3(in, 56);
  if (!std::isfinite(t) || !x.allFinite() || !v.allFinite()) return DecodeStatus::NonFinite;
  p.flags = get<uint32_t>(in, kOffFlags);
  p.sequence = get<uint64_t>(in, kOffSeq);
  p.time_s = t;
  p.position = x;
  p.velocity = v;
  p.buttons = get<uint32_t>(in, 80);
  return DecodeStatus::Ok;
}

DecodeStatus decode(const std::byte* in, size_t size, ForcePacket& p) noexcept {
  if (const DecodeStatus s = check_header(in, size, PacketKind::Force); s != DecodeStatus::Ok) return s;
  const Vec3 f = get3(in, 32), c = get3(in, 56);
  const double g = get<double>(in, 80);
  if (!f.allFinite() || !c.allFinite() || !std::isfinite(g)) return DecodeStatus::NonFinite;
  p.flags = get<uint32_t>(in, kOffFlags);
  p.sequence = get<uint64_t>(in, kOffSeq);
  p.tick = get<uint64_t>(in, 24);
  p.force = f;
  p.contact_m = c;
  p.gain = g;
  return DecodeStatus::Ok;
}

}  // namespace hdm::bridge
