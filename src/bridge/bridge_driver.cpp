// SPDX-License-Identifier: MIT
#include <hdm/bridge/bridge_driver.h>
#include <hdm/core/error.h>

#include "link.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/mman.h>
#include <sys/random.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <thread>

namespace hdm::bridge {
namespace {

using Clock = std::chrono::steady_clock;

struct UdpDriver final : BridgeDriver {
  explicit UdpDriver(int port) {
    fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    if (fd < 0) throw IoError(std::string("bridge driver udp: cannot create a socket: ") + std::strerror(errno));
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<uint16_t>(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
      const int e = errno;
      ::close(fd);
      throw IoError("bridge driver udp:" + std::to_string(port) + ": " + std::strerror(e));
    }
  }
  ~UdpDriver() override { ::close(fd); }
  bool send_bytes(const std::byte* raw, size_t size) noexcept override {
    return ::send(fd, raw, size, MSG_DONTWAIT) == ssize_t(size);
  }
  bool read_force(ForcePacket& out, uint64_t session) noexcept override {
    alignas(8) std::byte raw[256];
    bool any = false;
    for (;;) {
      const ssize_t n = ::recv(fd, raw, sizeof raw, MSG_DONTWAIT);
      if (n < 0) return any;
      ForcePacket f;
      if (decode(raw, size_t(n), f) == DecodeStatus::Ok && f.session == session) out = f, any = true;
    }
  }
  void idle(double timeout_s) noexcept override {
    pollfd p{fd, POLLIN, 0};
    const timespec t{static_cast<time_t>(timeout_s), static_cast<long>((timeout_s - double(time_t(timeout_s))) * 1e9)};
    ::ppoll(&p, 1, &t, nullptr);
  }
  int fd = -1;
};

struct ShmDriver final : BridgeDriver {
  ShmDriver(const std::string& name, double wait_s) {
    const auto deadline = Clock::now() + std::chrono::duration<double>(wait_s);
    int fd = -1;
    while ((fd = ::shm_open(("/" + name).c_str(), O_RDWR | O_CLOEXEC, 0)) < 0) {
      if (Clock::now() > deadline)
        throw IoError("bridge driver shm:" + name + ": no such region (is hdm listening?): " + std::strerror(errno));
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    void* p = ::mmap(nullptr, 4096, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    ::close(fd);
    if (p == MAP_FAILED) throw IoError("bridge driver shm:" + name + ": cannot map the region");
    base = static_cast<std::byte*>(p);
    std::atomic_ref<uint32_t> magic(*reinterpret_cast<uint32_t*>(base));
    while (magic.load(std::memory_order_acquire) != kRegionMagic) {
      if (Clock::now() > deadline) {
        ::munmap(base, 4096);
        throw IoError("bridge driver shm:" + name + ": the region is not a bridge region");
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    uint16_t version;
    std::memcpy(&version, base + 4, 2);
    if (version != kRegionVersion) {
      ::munmap(base, 4096);
      throw IoError("bridge driver shm:" + name + ": region version " + std::to_string(version) + ", expected " +
                    std::to_string(kRegionVersion));
    }
    device_block = reinterpret_cast<uint64_t*>(base + kRegionDeviceBlock);
    force_block = reinterpret_cast<uint64_t*>(base + kRegionForceBlock);
  }
  ~ShmDriver() override { ::munmap(base, 4096); }
  bool send_bytes(const std::byte* raw, size_t) noexcept override {
    seqlock_write(device_block, raw);
    return true;
  }
  bool read_force(ForcePacket& out, uint64_t session) noexcept override {
    const uint64_t v = seqlock_version(force_block);
    if (v == seen || (v & 1)) return false;
    alignas(8) std::byte raw[kPacketBytes];
    uint64_t version = 0;
    if (!seqlock_read(force_block, raw, version)) return false;
    seen = version;
    ForcePacket f;
    if (decode(raw, declared_bytes(raw, kPacketBytes), f) != DecodeStatus::Ok || f.session != session) return false;
    out = f;
    return true;
  }
  void idle(double) noexcept override {}
  std::byte* base = nullptr;
  uint64_t *device_block = nullptr, *force_block = nullptr;
  uint64_t seen = 0;
};

}  // namespace

std::unique_ptr<BridgeDriver> BridgeDriver::connect(const std::string& endpoint, const std::string& secret,
                                                    double wait_s) {
  if (secret.size() < kMinSecretBytes || secret.size() > kMaxSecretBytes)
    throw InvalidInput("bridge driver " + endpoint + ": the shared secret has " + std::to_string(secret.size()) +
                       " bytes; it needs " + std::to_string(kMinSecretBytes) + " to " +
                       std::to_string(kMaxSecretBytes));
  std::unique_ptr<BridgeDriver> d;
  if (endpoint.rfind("udp:", 0) == 0) {
    char* end = nullptr;
    const long port = std::strtol(endpoint.c_str() + 4, &end, 10);
    if (endpoint.size() == 4 || *end != '\0' || port <= 0 || port > 65535)
      throw InvalidInput("bridge driver endpoint '" + endpoint + "': the UDP port must be a number from 1 to 65535");
    d = std::make_unique<UdpDriver>(static_cast<int>(port));
  } else if (endpoint.rfind("shm:", 0) == 0 && endpoint.size() > 4 && endpoint.find('/') == std::string::npos) {
    d = std::make_unique<ShmDriver>(endpoint.substr(4), wait_s);
  } else {
    throw InvalidInput("bridge driver endpoint '" + endpoint + "': expected udp:PORT or shm:NAME");
  }
  d->hello(endpoint, secret, wait_s);
  return d;
}

void BridgeDriver::hello(const std::string& endpoint, const std::string& secret, double wait_s) {
  while (session_ == 0)
    if (::getrandom(&session_, sizeof session_, 0) != ssize_t(sizeof session_))
      throw IoError("bridge driver " + endpoint + ": cannot draw a session id: " + std::strerror(errno));
  HelloPacket h;
  h.session = session_;
  h.secret_bytes = static_cast<uint32_t>(secret.size());
  std::memcpy(h.secret.data(), secret.data(), secret.size());
  alignas(8) std::byte raw[kPacketBytes];
  const size_t bytes = encode(h, raw);
  const auto deadline = Clock::now() + std::chrono::duration<double>(wait_s);
  ForcePacket f;
  do {
    send_bytes(raw, bytes);
    if (wait_force(f, 0, 0.005)) return;  // a force of this session: admitted
  } while (Clock::now() < deadline);
  throw IoError("bridge driver " + endpoint + ": hdm did not answer the hello within " + std::to_string(wait_s) +
                " s (is it listening, with the same secret?)");
}

bool BridgeDriver::send(const DevicePacket& packet) noexcept {
  DevicePacket p = packet;
  p.session = session_;
  alignas(8) std::byte raw[kPacketBytes] = {};
  const size_t bytes = encode(p, raw);
  return send_bytes(raw, bytes);
}

bool BridgeDriver::poll_force(ForcePacket& out) noexcept { return session_ != 0 && read_force(out, session_); }

bool BridgeDriver::wait_force(ForcePacket& out, uint64_t sequence, double timeout_s) noexcept {
  const auto deadline = Clock::now() + std::chrono::duration<double>(timeout_s);
  ForcePacket f;
  for (;;) {
    if (poll_force(f) && f.sequence >= sequence) {
      out = f;
      return true;
    }
    const double left = std::chrono::duration<double>(deadline - Clock::now()).count();
    if (left <= 0) return false;
    idle(left);
  }
}

}  // namespace hdm::bridge
