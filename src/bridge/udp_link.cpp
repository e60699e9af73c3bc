// SPDX-License-Identifier: MIT
// The UDP transport: a receiver thread checks each datagram, admits only the driver's (the session
// its hello opened with the shared secret, from the address that sent the hello) and writes the
// good ones into the in-process device block; a sender thread sleeps on a futex until the servo thread posts a force,
// then sends the newest one to the driver. The servo thread only touches the two blocks (and wakes
// the sender).
#include <hdm/core/error.h>

#include "link.h"

#include <arpa/inet.h>
#include <linux/futex.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <thread>

namespace hdm::bridge {
namespace {

long futex(std::atomic<uint32_t>* word, int op, uint32_t value, const timespec* timeout) noexcept {
  static_assert(sizeof(std::atomic<uint32_t>) == sizeof(uint32_t));
  return syscall(SYS_futex, reinterpret_cast<uint32_t*>(word), op, value, timeout, nullptr, 0);
}

struct UdpLink final : BridgeDevice::Link {
  UdpLink(int requested_port, const std::string& secret) : Link(secret) {
    device_block = blocks;
    force_block = blocks + kForceWord;
    admitted = true;
    fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (fd < 0) throw IoError(std::string("bridge udp: cannot create a socket: ") + std::strerror(errno));
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<uint16_t>(requested_port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);  // localhost only: the secret travels in the clear
    if (::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
      const int e = errno;
      ::close(fd);
      throw IoError("bridge udp:" + std::to_string(requested_port) + ": cannot bind 127.0.0.1: " + std::strerror(e));
    }
    socklen_t len = sizeof a;
    ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
    port = ntohs(a.sin_port);
    receiver = std::thread([this] { receive(); });
    sender = std::thread([this] { send(); });
  }

  ~UdpLink() override {
    stop.store(true);
    posted.fetch_add(1, std::memory_order_release);
    futex(&posted, FUTEX_WAKE_PRIVATE, 1, nullptr);
    receiver.join();
    sender.join();
    ::close(fd);
  }

  void forces_posted() noexcept override {
    posted.fetch_add(1, std::memory_order_seq_cst);  // with the flag's load: either side sees the other
    if (sender_sleeping.load(std::memory_order_seq_cst)) futex(&posted, FUTEX_WAKE_PRIVATE, 1, nullptr);
  }

  void receive() noexcept {
    alignas(8) std::byte buf[512];
    while (!stop.load(std::memory_order_relaxed)) {
      pollfd p{fd, POLLIN, 0};
      if (::poll(&p, 1, 20) <= 0) continue;  // wakes up to see stop
      sockaddr_in from{};
      socklen_t len = sizeof from;
      const ssize_t n = ::recvfrom(fd, buf, sizeof buf, 0, reinterpret_cast<sockaddr*>(&from), &len);
      if (n < 0) continue;
      const uint64_t sender_id = (uint64_t(from.sin_addr.s_addr) << 16) | from.sin_port;
      DevicePacket packet;
      DecodeStatus s = DecodeStatus::Ok;
      const Verdict v = admission.admit(buf, static_cast<size_t>(n), sender_id, packet, s);
      counters.count(v, s);
      if (v == Verdict::Hello || v == Verdict::HelloAgain) {
        peer.store(sender_id, std::memory_order_relaxed);
        welcome(from, admission.session());
      }
      if (v == Verdict::Device) seqlock_write(device_block, buf);
    }
  }

  // Answers a hello at once (the servo may not tick before the driver's first device packet): a
  // force packet of the new session, no force.
  void welcome(const sockaddr_in& to, uint64_t session) noexcept {
    ForcePacket f;
    f.session = session;
    f.flags = kForceWatchdog;
    f.gain = 0;
    f.version = admission.version();  // answered in the version the driver speaks
    alignas(8) std::byte raw[kPacketBytes];
    const size_t bytes = encode(f, raw);
    if (::sendto(fd, raw, bytes, MSG_DONTWAIT, reinterpret_cast<const sockaddr*>(&to), sizeof to) < 0)
      counters.send_errors.fetch_add(1, std::memory_order_relaxed);
  }

  void send() noexcept {
    alignas(8) std::byte raw[kPacketBytes];
    // From the count at construction, not at this thread's start: under load the thread may first
    // run after the servo has posted the answer to the first packet, which must still go out.
    uint32_t seen = 0;
    while (!stop.load(std::memory_order_relaxed)) {
      // Sleep until a force is posted (or 20 ms pass, to see stop); the flag spares the servo
      // thread the wake-up call while this thread is awake.
      sender_sleeping.store(true, std::memory_order_seq_cst);
      if (posted.load(std::memory_order_seq_cst) == seen) {
        const timespec timeout{0, 20'000'000};
        futex(&posted, FUTEX_WAIT_PRIVATE, seen, &timeout);
      }
      sender_sleeping.store(false, std::memory_order_relaxed);
      const uint32_t now = posted.load(std::memory_order_acquire);
      if (now == seen) continue;
      seen = now;
      uint64_t version = 0;
      const uint64_t to = peer.load(std::memory_order_relaxed);
      if (to == 0 || !seqlock_read(force_block, raw, version)) continue;
      sockaddr_in a{};
      a.sin_family = AF_INET;
      a.sin_addr.s_addr = static_cast<uint32_t>(to >> 16);
      a.sin_port = static_cast<uint16_t>(to & 0xffff);
      const size_t bytes = declared_bytes(raw, kPacketBytes);
      if (::sendto(fd, raw, bytes, MSG_DONTWAIT, reinterpret_cast<sockaddr*>(&a), sizeof a) < 0)
        counters.send_errors.fetch_add(1, std::memory_order_relaxed);
    }
  }

  // Device block at word 0, force block on the next cache line after it (words: 8 per line).
  static constexpr size_t kForceWord = (1 + kWords + 7) / 8 * 8;
  alignas(64) uint64_t blocks[2 * kForceWord] = {};
  int fd = -1;
  std::atomic<bool> stop{false};
  std::atomic<uint32_t> posted{0};
  std::atomic<bool> sender_sleeping{false};
  std::atomic<uint64_t> peer{0};  // address << 16 | port, network order; 0: none yet
  std::thread receiver, sender;
};

}  // namespace

std::unique_ptr<BridgeDevice::Link> open_udp_link(int port, const std::string& secret) {
  return std::make_unique<UdpLink>(port, secret);
}

}  // namespace hdm::bridge
