// SPDX-License-Identifier: MIT
// libFuzzer target for the device bridge's packet parser and admission: the input is decoded as
// every packet kind (versions 2 and 3), then cut into kPacketBytes packets fed to one Admission (hello, session,
// sequence window) as a receiver would. Traps when a packet is applied that the wire format or the
// admission rules (docs/bridge.md) should have refused.
#include <hdm/bridge/wire_format.h>

#include "admission.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

namespace {

const std::string kSecret = "fuzz-secret-0123456789";

// Decoding as each kind: an Ok result has finite numbers, and encoding it gives back a packet that
// decodes to the same values.
void decode_each(const std::byte* in, size_t size) {
  using namespace hdm::bridge;
  alignas(8) std::byte out[kPacketBytes];
  DevicePacket d, d2;
  if (decode(in, size, d) == DecodeStatus::Ok) {
    if (size != packet_bytes(d.version) || !d.position.allFinite() || !d.velocity.allFinite() ||
        !d.orientation.coeffs().allFinite() || !d.angular_velocity.allFinite() || !std::isfinite(d.time_s))
      __builtin_trap();
    encode(d, out);
    if (decode(out, packet_bytes(d.version), d2) != DecodeStatus::Ok || d2.sequence != d.sequence ||
        d2.session != d.session || d2.position != d.position || d2.buttons != d.buttons || d2.flags != d.flags ||
        d2.orientation.coeffs() != d.orientation.coeffs() || d2.angular_velocity != d.angular_velocity)
      __builtin_trap();
  }
  ForcePacket f, f2;
  if (decode(in, size, f) == DecodeStatus::Ok) {
    if (!f.force.allFinite() || !f.torque.allFinite() || !f.contact_m.allFinite() || !std::isfinite(f.gain))
      __builtin_trap();
    encode(f, out);
    if (decode(out, packet_bytes(f.version), f2) != DecodeStatus::Ok || f2.force != f.force || f2.torque != f.torque ||
        f2.session != f.session)
      __builtin_trap();
  }
  HelloPacket h;
  if (decode(in, size, h) == DecodeStatus::Ok && (h.session == 0 || h.secret_bytes > kMaxSecretBytes)) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace hdm::bridge;
  const auto* bytes = reinterpret_cast<const std::byte*>(data);
  decode_each(bytes, size);
  Admission admission(kSecret);
  uint64_t session = 0, last = 0;
  for (size_t at = 0; at + kPacketBytes <= size; at += kPacketBytes) {
    alignas(8) std::byte packet[kPacketBytes];
    std::memcpy(packet, bytes + at, kPacketBytes);
    DevicePacket p;
    DecodeStatus status = DecodeStatus::Ok;
    switch (admission.admit(packet, kPacketBytes, 0, p, status)) {
      case Verdict::Hello: {
        HelloPacket h;
        if (decode(packet, kPacketBytes, h) != DecodeStatus::Ok || !secret_matches(h, kSecret)) __builtin_trap();
        session = h.session, last = 0;
        break;
      }
      case Verdict::Device:  // only the session's, in the window above the last one
        if (session == 0 || p.session != session || !(p.sequence > last && p.sequence - last <= kSequenceWindow))
          __builtin_trap();
        last = p.sequence;
        break;
      default:
        if (admission.session() != session) __builtin_trap();  // a refused packet changes nothing
        break;
    }
  }
  return 0;
}
