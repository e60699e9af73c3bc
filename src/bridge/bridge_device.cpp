// SPDX-License-Identifier: MIT
#include <hdm/bridge/bridge_device.h>
#include <hdm/core/error.h>

#include "link.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>

namespace hdm::bridge {
namespace {

int64_t steady_ns() noexcept {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

using Word = std::atomic_ref<uint64_t>;

}  // namespace

void seqlock_write(uint64_t* block, const std::byte* packet) noexcept {
  Word seq(block[0]);
  const uint64_t v = seq.load(std::memory_order_relaxed);
  seq.store(v + 1, std::memory_order_relaxed);
  std::atomic_thread_fence(std::memory_order_release);
  for (size_t i = 0; i < kWords; ++i) {
    uint64_t w;
    std::memcpy(&w, packet + 8 * i, 8);
    Word(block[1 + i]).store(w, std::memory_order_relaxed);
  }
  seq.store(v + 2, std::memory_order_release);
}

bool seqlock_read(uint64_t* block, std::byte* out, uint64_t& version) noexcept {
  Word seq(block[0]);
  for (int attempt = 0; attempt < 4; ++attempt) {
    const uint64_t v1 = seq.load(std::memory_order_acquire);
    if (v1 & 1) continue;
    for (size_t i = 0; i < kWords; ++i) {
      const uint64_t w = Word(block[1 + i]).load(std::memory_order_relaxed);
      std::memcpy(out + 8 * i, &w, 8);
    }
    std::atomic_thread_fence(std::memory_order_acquire);
    if (seq.load(std::memory_order_relaxed) == v1) {
      version = v1;
      return true;
    }
  }
  return false;
}

uint64_t seqlock_version(uint64_t* block) noexcept { return Word(block[0]).load(std::memory_order_acquire); }

void LinkCounters::refuse(DecodeStatus s) noexcept {
  switch (s) {
    case DecodeStatus::Ok:
      break;
    case DecodeStatus::BadSize:
      bad_size.fetch_add(1, std::memory_order_relaxed);
      break;
    case DecodeStatus::BadMagic:
      bad_magic.fetch_add(1, std::memory_order_relaxed);
      break;
    case DecodeStatus::BadVersion:
      bad_version.fetch_add(1, std::memory_order_relaxed);
      break;
    case DecodeStatus::BadKind:
      bad_kind.fetch_add(1, std::memory_order_relaxed);
      break;
    case DecodeStatus::NonFinite:
      non_finite.fetch_add(1, std::memory_order_relaxed);
      break;
    case DecodeStatus::BadHello:  // a malformed hello is a failed attempt at the secret
      bad_secret.fetch_add(1, std::memory_order_relaxed);
      break;
  }
}

void LinkCounters::count(Verdict v, DecodeStatus s) noexcept {
  switch (v) {
    case Verdict::Device:
      break;
    case Verdict::Hello:
      hellos.fetch_add(1, std::memory_order_relaxed);
      break;
    case Verdict::HelloAgain:  // answered again, not a new session
      break;
    case Verdict::Refused:
    case Verdict::NotForUs:
      refuse(s);
      break;
    case Verdict::BadSecret:
      bad_secret.fetch_add(1, std::memory_order_relaxed);
      break;
    case Verdict::WrongSession:
      wrong_session.fetch_add(1, std::memory_order_relaxed);
      break;
    case Verdict::OutOfWindow:
      out_of_order.fetch_add(1, std::memory_order_relaxed);
      break;
  }
}

std::unique_ptr<BridgeDevice> BridgeDevice::open(const std::string& endpoint, const BridgeOptions& options) {
  if (!(options.watchdog_s > 0) || !(options.ramp_s > 0) || !std::isfinite(options.watchdog_s) ||
      !std::isfinite(options.ramp_s))
    throw InvalidInput("bridge " + endpoint + ": the watchdog and ramp times must be positive seconds");
  if (options.secret.size() < kMinSecretBytes || options.secret.size() > kMaxSecretBytes)
    throw InvalidInput("bridge " + endpoint + ": the shared secret has " + std::to_string(options.secret.size()) +
                       " bytes; it needs " + std::to_string(kMinSecretBytes) + " to " +
                       std::to_string(kMaxSecretBytes) + " (docs/bridge.md)");
  const size_t colon = endpoint.find(':');
  const std::string kind = endpoint.substr(0, colon),
                    arg = colon == std::string::npos ? "" : endpoint.substr(colon + 1);
  std::unique_ptr<Link> link;
  std::string name = endpoint;
  if (kind == "udp") {
    char* end = nullptr;
    const long port = std::strtol(arg.c_str(), &end, 10);
    if (arg.empty() || *end != '\0' || port < 0 || port > 65535)
      throw InvalidInput("bridge endpoint '" + endpoint + "': the UDP port must be a number from 0 to 65535");
    link = open_udp_link(static_cast<int>(port), options.secret);
    name = "udp:" + std::to_string(link->port);
  } else if (kind == "shm") {
    const bool ok = !arg.empty() && arg.size() <= 200 && std::all_of(arg.begin(), arg.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-';
    });
    if (!ok || arg[0] == '.')
      throw InvalidInput("bridge endpoint '" + endpoint +
                         "': the shared-memory name must be 1 to 200 letters, digits, '.', '_' or '-' (not "
                         "starting with '.')");
    link = open_shm_link(arg, options.secret);
  } else {
    throw InvalidInput("bridge endpoint '" + endpoint + "': expected udp:PORT or shm:NAME");
  }
  return std::unique_ptr<BridgeDevice>(new BridgeDevice(std::move(link), options, name));
}

BridgeDevice::BridgeDevice(std::unique_ptr<Link> link, const BridgeOptions& options, std::string endpoint)
    : link_(std::move(link)), options_(options), endpoint_(std::move(endpoint)) {
  seen_version_ = seqlock_version(link_->device_block);
  last_.position = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
}

BridgeDevice::~BridgeDevice() = default;

bool BridgeDevice::packet_waiting() const noexcept {
  const uint64_t v = seqlock_version(link_->device_block);
  return v != seen_version_ && !(v & 1);
}

bool BridgeDevice::receive() noexcept { return poll(steady_ns()); }

bool BridgeDevice::poll(int64_t now) noexcept {
  if (!packet_waiting()) return false;
  alignas(8) std::byte raw[kPacketBytes];
  uint64_t version = 0;
  if (!seqlock_read(link_->device_block, raw, version)) return false;  // the writer is busy: next look
  seen_version_ = version;
  DevicePacket p;
  DecodeStatus s = DecodeStatus::Ok;
  // UDP's receiver wrote only admitted packets; shared memory is judged here.
  // A block holds kPacketBytes; the packet's header says how many are its own (version 2: fewer).
  const size_t size = declared_bytes(raw, kPacketBytes);
  const Verdict v = link_->admitted
                        ? (s = decode(raw, size, p)) == DecodeStatus::Ok ? Verdict::Device : Verdict::Refused
                        : link_->admission.admit(raw, size, 0, p, s);
  if (v == Verdict::Hello || v == Verdict::HelloAgain) {  // answer at once: the driver waits for its first force
    session_ = link_->admission.session();
    version_ = link_->admission.version();
    have_ = false;
    ForcePacket welcome;
    welcome.flags = kForceWatchdog;
    welcome.gain = gain_;
    post(welcome);
  }
  if (v != Verdict::Device) {
    link_->counters.count(v, s);
    return false;
  }
  link_->counters.accepted.fetch_add(1, std::memory_order_relaxed);
  session_ = p.session;
  version_ = p.version;
  last_ = p;
  have_ = true;
  last_new_ns_ = now;
  if (p.flags & kDeviceEnd) ended_ = true;
  return true;
}

bool BridgeDevice::begin_frame(DeviceState& state) noexcept {
  const int64_t now = steady_ns();
  poll(now);
  if (ended_) return false;
  const bool stale = !have_ || double(now - last_new_ns_) * 1e-9 > options_.watchdog_s;
  if (stale && !stale_ && have_) link_->counters.watchdog_trips.fetch_add(1, std::memory_order_relaxed);
  const bool resumed = stale_ && !stale;
  stale_ = stale;
  // The gain moves towards its target at 1/ramp_s per second of servo time. The ramp in starts at
  // the first frame that sees packets again: the time the servo spent before it (a stalled tick)
  // must not count, or the force would come back as a step.
  const double dt = last_frame_ns_ > 0 && !resumed ? std::max(0.0, double(now - last_frame_ns_) * 1e-9) : 0.0;
  last_frame_ns_ = now;
  const double step = dt / options_.ramp_s;
  gain_ = stale ? std::max(0.0, gain_ - step) : std::min(1.0, gain_ + step);
  state.position = last_.position;
  state.time_s = last_.time_s;
  state.velocity = stale ? Vec3::Zero() : last_.velocity;
  state.buttons = stale ? 0u : last_.buttons;  // released: no stroke continues on a stale position
  const double qn = last_.orientation.norm();
  state.orientation = qn > 0 ? Eigen::Quaterniond(last_.orientation.coeffs() / qn) : Eigen::Quaterniond::Identity();
  state.angular_velocity = stale ? Vec3::Zero() : last_.angular_velocity;
  return true;
}

void BridgeDevice::end_frame(const Vec3& force_n) noexcept { end_frame(force_n, Vec3::Zero()); }

void BridgeDevice::end_frame(const Vec3& force_n, const Vec3& torque_nm) noexcept {
  Vec3 f = force_n.allFinite() ? Vec3(force_n * gain_) : Vec3::Zero();
  const double n = f.norm(), cap = options_.spec.max_force_n;
  if (n > cap) f *= cap / n;
  Vec3 t = torque_nm.allFinite() ? Vec3(torque_nm * gain_) : Vec3::Zero();
  const double tn = t.norm(), tcap = std::max(0.0, options_.spec.max_torque_nm);
  if (tn > tcap) t *= tcap / tn;
  ForcePacket p;
  p.flags = (contact_ ? kForceContact : 0u) | (stale_ ? kForceWatchdog : 0u) |
            (!stale_ && (last_.buttons & 1u) ? kForceToolOn : 0u);
  p.sequence = have_ ? last_.sequence : 0;
  p.force = f;
  p.torque = t;
  p.contact_m = contact_ ? contact_m_ : (last_.position.allFinite() ? last_.position : Vec3::Zero());
  p.gain = gain_;
  post(p);
}

void BridgeDevice::post(ForcePacket& p) noexcept {
  p.session = session_;
  p.version = version_;
  alignas(8) std::byte raw[kPacketBytes] = {};
  p.tick = tick_++;
  encode(p, raw);
  seqlock_write(link_->force_block, raw);
  link_->counters.forces_sent.fetch_add(1, std::memory_order_relaxed);
  link_->forces_posted();
}

void BridgeDevice::set_contact(const Vec3& point_m, bool contact) noexcept {
  contact_ = contact && point_m.allFinite();
  if (contact_) contact_m_ = point_m;
}

BridgeCounters BridgeDevice::counters() const noexcept {
  const LinkCounters& c = link_->counters;
  const auto r = [](const std::atomic<int64_t>& a) { return a.load(std::memory_order_relaxed); };
  BridgeCounters out;
  out.accepted = r(c.accepted);
  out.bad_size = r(c.bad_size);
  out.bad_magic = r(c.bad_magic);
  out.bad_version = r(c.bad_version);
  out.bad_kind = r(c.bad_kind);
  out.non_finite = r(c.non_finite);
  out.out_of_order = r(c.out_of_order);
  out.bad_secret = r(c.bad_secret);
  out.wrong_session = r(c.wrong_session);
  out.sessions = r(c.hellos);
  out.watchdog_trips = r(c.watchdog_trips);
  out.forces_sent = r(c.forces_sent);
  out.send_errors = r(c.send_errors);
  return out;
}

int BridgeDevice::port() const noexcept { return link_->port; }

}  // namespace hdm::bridge
