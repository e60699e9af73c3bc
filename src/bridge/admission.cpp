// SPDX-License-Identifier: MIT
#include "admission.h"

namespace hdm::bridge {

Verdict Admission::admit(const std::byte* raw, size_t size, uint64_t sender, DevicePacket& device,
                         DecodeStatus& status) noexcept {
  PacketKind kind{};
  status = decode_kind(raw, size, kind);
  if (status != DecodeStatus::Ok) return Verdict::Refused;
  if (kind == PacketKind::Force) {
    status = DecodeStatus::BadKind;
    return Verdict::NotForUs;
  }
  if (kind == PacketKind::Hello) {
    HelloPacket hello;
    status = decode(raw, size, hello);
    if (status != DecodeStatus::Ok) return Verdict::Refused;
    if (!secret_matches(hello, secret_)) return Verdict::BadSecret;
    if (session_ != 0 && hello.session == session_ && sender == sender_) return Verdict::HelloAgain;
    session_ = hello.session;
    version_ = hello.version;
    sender_ = sender;
    last_sequence_ = 0;
    return Verdict::Hello;
  }
  DevicePacket p;
  status = decode(raw, size, p);
  if (status != DecodeStatus::Ok) return Verdict::Refused;
  if (session_ == 0 || p.session != session_ || sender != sender_) return Verdict::WrongSession;
  if (!sequence_in_window(last_sequence_, p.sequence)) return Verdict::OutOfWindow;
  last_sequence_ = p.sequence;
  device = p;
  return Verdict::Device;
}

}  // namespace hdm::bridge
