// SPDX-License-Identifier: MIT
// The bridge's packets: the byte layout against the table of docs/bridge.md (written here byte by
// byte, independently of the encoder), bad packets dropped and counted over UDP and shared memory
// (never applied), and the watchdog: packets stop, the tool is released and the force ramps to zero
// within the watchdog window plus the ramp, without a step.
#include <hdm/bridge/bridge_device.h>
#include <hdm/bridge/wire_format.h>
#include <hdm/core/error.h>

#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <sys/mman.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <thread>
#include <vector>

namespace hdm::bridge {
namespace {

using Clock = std::chrono::steady_clock;

constexpr uint64_t kSession = 0x5e5510'0000'0001ull;
const std::string kSecret = "a-test-secret-of-32-characters!!";

BridgeOptions with_secret(BridgeOptions o = {}) {
  o.secret = kSecret;
  return o;
}

// The header of the documented table (offsets, little-endian), not by encode().
std::vector<std::byte> raw_header(uint16_t kind, uint32_t flags, uint64_t seq, uint64_t session) {
  std::vector<std::byte> b(96);
  auto put = [&](size_t off, const void* v, size_t n) { std::memcpy(b.data() + off, v, n); };
  const char magic[4] = {'H', 'D', 'M', 'B'};
  const uint16_t version = 2;
  const uint32_t size = 96;
  put(0, magic, 4);
  put(4, &version, 2);
  put(6, &kind, 2);
  put(8, &size, 4);
  put(12, &flags, 4);
  put(16, &seq, 8);
  put(24, &session, 8);
  return b;
}

// A device packet laid out from the documented table.
std::vector<std::byte> raw_device(uint64_t seq, const Vec3& pos, uint32_t buttons = 0, uint32_t flags = 0,
                                  uint64_t session = kSession) {
  std::vector<std::byte> b = raw_header(1, flags, seq, session);
  const double t = 0.001 * double(seq), v[3] = {0.01, 0.02, 0.03};
  std::memcpy(b.data() + 32, &t, 8);
  for (int i = 0; i < 3; ++i) std::memcpy(b.data() + 40 + 8 * size_t(i), &pos[i], 8);
  std::memcpy(b.data() + 64, v, 24);
  std::memcpy(b.data() + 88, &buttons, 4);
  return b;
}

// A hello packet laid out from the documented table.
std::vector<std::byte> raw_hello(uint64_t session, const std::string& secret = kSecret) {
  std::vector<std::byte> b = raw_header(3, 0, 0, session);
  const auto n = static_cast<uint32_t>(secret.size());
  std::memcpy(b.data() + 32, &n, 4);
  std::memcpy(b.data() + 36, secret.data(), secret.size());
  return b;
}

TEST(BridgeWireFormat, EncodeMatchesTheDocumentedLayout) {
  DevicePacket p;
  p.sequence = 42;
  p.time_s = 0.042;
  p.position = Vec3(0.1, -0.2, 0.3);
  p.velocity = Vec3(0.01, 0.02, 0.03);
  p.buttons = 1;
  p.session = kSession;
  p.version = 2;  // the table's version 2 prefix; version 3 appends to it (bridge_pose_test.cpp)
  std::byte out[kPacketBytes];
  EXPECT_EQ(encode(p, out), kPacketBytesV2);
  const std::vector<std::byte> expected = raw_device(42, p.position, 1);
  EXPECT_EQ(0, std::memcmp(out, expected.data(), kPacketBytesV2));
  DevicePacket back;
  ASSERT_EQ(DecodeStatus::Ok, decode(expected.data(), expected.size(), back));
  EXPECT_EQ(back.position, p.position);
  EXPECT_EQ(back.sequence, 42u);
  EXPECT_EQ(back.session, kSession);
  HelloPacket h;
  h.version = 2;
  h.session = kSession;
  h.secret_bytes = static_cast<uint32_t>(kSecret.size());
  std::memcpy(h.secret.data(), kSecret.data(), kSecret.size());
  encode(h, out);
  EXPECT_EQ(0, std::memcmp(out, raw_hello(kSession).data(), kPacketBytesV2));
  HelloPacket hb;
  ASSERT_EQ(DecodeStatus::Ok, decode(out, kPacketBytesV2, hb));
  EXPECT_TRUE(secret_matches(hb, kSecret));
  EXPECT_FALSE(secret_matches(hb, kSecret.substr(1)));

  ForcePacket f;
  f.flags = kForceContact;
  f.sequence = 7;
  f.tick = 9;
  f.force = Vec3(1, 2, 3);
  f.contact_m = Vec3(4, 5, 6);
  f.gain = 0.5;
  f.version = 2;
  encode(f, out);
  EXPECT_EQ(0, std::memcmp(out, "HDMB", 4));
  uint16_t kind;
  double fz, gain;
  std::memcpy(&kind, out + 6, 2);
  std::memcpy(&fz, out + 56, 8);
  std::memcpy(&gain, out + 88, 8);
  EXPECT_EQ(kind, 2);
  EXPECT_EQ(fz, 3.0);
  EXPECT_EQ(gain, 0.5);
  ForcePacket fb;
  ASSERT_EQ(DecodeStatus::Ok, decode(out, kPacketBytesV2, fb));
  EXPECT_EQ(fb.contact_m, f.contact_m);
  EXPECT_EQ(DecodeStatus::BadKind, decode(out, kPacketBytesV2, back));  // a force packet is not a device packet
}

// Bad packets, each one kind of fault, after a good packet (sequence 5).
struct BadSet {
  std::vector<std::vector<std::byte>> packets;
  BadSet() {
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    std::vector<std::byte> p = raw_device(6, Vec3(0.5, 0.5, 0.5));
    packets.emplace_back(p.begin(), p.begin() + 10);  // short
    p.push_back(std::byte{0});
    packets.push_back(p);  // long
    p = raw_device(6, Vec3(0.5, 0.5, 0.5));
    p[8] = std::byte{80};
    packets.push_back(p);  // size field disagrees
    p = raw_device(6, Vec3(0.5, 0.5, 0.5));
    p[0] = std::byte{'X'};
    packets.push_back(p);  // magic
    p = raw_device(6, Vec3(0.5, 0.5, 0.5));
    p[4] = std::byte{1};
    packets.push_back(p);  // version 1
    p = raw_device(6, Vec3(0.5, 0.5, 0.5));
    p[6] = std::byte{2};
    packets.push_back(p);                               // a force packet sent the wrong way
    packets.push_back(raw_device(6, Vec3(nan, 0, 0)));  // NaN position
    p = raw_device(6, Vec3(0.5, 0.5, 0.5));
    std::memcpy(p.data() + 64, &inf, 8);
    packets.push_back(p);                                   // infinite velocity
    packets.push_back(raw_device(5, Vec3(0.5, 0.5, 0.5)));  // duplicate sequence number
    packets.push_back(raw_device(4, Vec3(0.5, 0.5, 0.5)));  // older sequence number
  }
};

void expect_bad_set_counted(const BridgeCounters& c) {
  EXPECT_EQ(c.bad_size, 3);
  EXPECT_EQ(c.bad_magic, 1);
  EXPECT_EQ(c.bad_version, 1);
  EXPECT_EQ(c.bad_kind, 1);
  EXPECT_EQ(c.non_finite, 2);
  EXPECT_EQ(c.out_of_order, 2);
  EXPECT_EQ(c.dropped(), 10);
}

TEST(BridgeDevice, UdpDropsAndCountsBadPackets) {
  auto dev = BridgeDevice::open("udp:0", with_secret());
  ASSERT_GT(dev->port(), 0);
  const int s = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<uint16_t>(dev->port()));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  auto send = [&](const std::vector<std::byte>& p) {
    ASSERT_EQ(::sendto(s, p.data(), p.size(), 0, reinterpret_cast<sockaddr*>(&a), sizeof a), ssize_t(p.size()));
  };
  // Waits (up to 5 s) until the device has accepted `n` packets, ticking it as a servo would.
  DeviceState st;
  auto ticks_until_accepted = [&](int64_t n) {
    const auto end = Clock::now() + std::chrono::seconds(5);
    while (dev->counters().accepted < n && Clock::now() < end) {
      dev->begin_frame(st);
      dev->end_frame(Vec3::Zero());
      std::this_thread::sleep_for(std::chrono::microseconds(100));
    }
    dev->begin_frame(st);
  };
  send(raw_hello(kSession));
  send(raw_device(5, Vec3(0.01, 0.02, 0.03), 1));
  ticks_until_accepted(1);
  EXPECT_EQ(st.position, Vec3(0.01, 0.02, 0.03));
  for (const auto& p : BadSet().packets) send(p);
  send(raw_device(6, Vec3(0.04, 0.05, 0.06), 1));  // the next good one: sent after the bad ones
  ticks_until_accepted(2);
  EXPECT_EQ(st.position, Vec3(0.04, 0.05, 0.06));
  expect_bad_set_counted(dev->counters());
  EXPECT_EQ(dev->counters().accepted, 2);
  ::close(s);
}

// A driver's view of the shared-memory region, from the documented layout (device block at byte 64:
// its sequence word, then the packet; force block at 256).
struct ShmDriver {
  explicit ShmDriver(const std::string& name) {
    const int fd = ::shm_open(("/" + name).c_str(), O_RDWR, 0);
    EXPECT_GE(fd, 0);
    base = static_cast<std::byte*>(::mmap(nullptr, 4096, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0));
    ::close(fd);
  }
  ~ShmDriver() { ::munmap(base, 4096); }
  void write(const std::vector<std::byte>& p) {  // one thread here: no reader runs meanwhile
    uint64_t c;
    std::memcpy(&c, base + 64, 8);
    c += 2;
    std::memcpy(base + 72, p.data(), std::min<size_t>(p.size(), kPacketBytes));
    std::memcpy(base + 64, &c, 8);
  }
  ForcePacket force() const {
    ForcePacket f;
    EXPECT_EQ(DecodeStatus::Ok, decode(base + 264, declared_bytes(base + 264, kPacketBytes), f));
    return f;
  }
  std::byte* base;
};

std::string shm_name(const char* what) { return std::string("hdm-test-") + what + "-" + std::to_string(::getpid()); }

TEST(BridgeDevice, SharedMemoryDropsAndCountsBadPackets) {
  const std::string name = shm_name("bad");
  auto dev = BridgeDevice::open("shm:" + name, with_secret());
  ShmDriver drv(name);
  EXPECT_EQ(0, std::memcmp(drv.base, "HDMR", 4));
  DeviceState st;
  drv.write(raw_hello(kSession));
  ASSERT_TRUE(dev->begin_frame(st));
  EXPECT_EQ(drv.force().session, kSession);  // the hello is answered at once
  drv.write(raw_device(5, Vec3(0.01, 0.02, 0.03), 1));
  ASSERT_TRUE(dev->begin_frame(st));
  EXPECT_EQ(st.position, Vec3(0.01, 0.02, 0.03));
  EXPECT_EQ(st.buttons, 1u);
  dev->end_frame(Vec3(0, 0, 1));
  EXPECT_EQ(drv.force().sequence, 5u);  // the force answers packet 5
  for (auto p : BadSet().packets) {
    if (p.size() != 96) continue;  // the region holds whole packets: no short or long ones
    drv.write(p);
    ASSERT_TRUE(dev->begin_frame(st));
    EXPECT_EQ(st.position, Vec3(0.01, 0.02, 0.03)) << "a bad packet was applied";
    dev->end_frame(Vec3(0, 0, 1));
    EXPECT_EQ(drv.force().sequence, 5u);
  }
  const BridgeCounters c = dev->counters();
  EXPECT_EQ(c.bad_size, 1);  // the size field that disagrees
  EXPECT_EQ(c.bad_magic, 1);
  EXPECT_EQ(c.bad_version, 1);
  EXPECT_EQ(c.bad_kind, 1);
  EXPECT_EQ(c.non_finite, 2);
  EXPECT_EQ(c.out_of_order, 2);
  EXPECT_EQ(c.accepted, 1);
}

TEST(BridgeDevice, RefusesMalformedEndpoints) {
  EXPECT_THROW(BridgeDevice::open("udp:70000", with_secret()), InvalidInput);
  EXPECT_THROW(BridgeDevice::open("udp:x", with_secret()), InvalidInput);
  EXPECT_THROW(BridgeDevice::open("shm:../etc", with_secret()), InvalidInput);
  EXPECT_THROW(BridgeDevice::open("tcp:1", with_secret()), InvalidInput);
  EXPECT_THROW(BridgeDevice::open("udp:0"), InvalidInput);  // no secret
  BridgeOptions o = with_secret();
  o.watchdog_s = 0;
  EXPECT_THROW(BridgeDevice::open("shm:x", o), InvalidInput);
}

// Packets every 0.5 ms with the tool held, then none: after the watchdog the buttons read 0 and
// the force (2 N asked) falls to zero by watchdog + ramp, each tick's step at most the ramp's rate;
// when packets come back the force ramps in again.
TEST(BridgeDevice, WatchdogReleasesTheToolAndRampsTheForceOut) {
  const std::string name = shm_name("watchdog");
  const BridgeOptions o = with_secret();  // 5 ms watchdog, 5 ms ramp
  auto dev = BridgeDevice::open("shm:" + name, o);
  ShmDriver drv(name);
  const Vec3 asked(0, 0, 2);
  DeviceState st;
  drv.write(raw_hello(kSession));
  ASSERT_TRUE(dev->begin_frame(st));
  uint64_t seq = 1;
  for (int k = 0; k < 40; ++k) {  // 20 ms of packets: the gain ramps in
    drv.write(raw_device(seq++, Vec3(0, 0, 0.01), 1));
    ASSERT_TRUE(dev->begin_frame(st));
    EXPECT_EQ(st.buttons, 1u);
    dev->end_frame(asked);
    std::this_thread::sleep_for(std::chrono::microseconds(500));
  }
  EXPECT_NEAR(drv.force().force.z(), 2.0, 1e-12);
  const auto last_packet = Clock::now();
  double prev = drv.force().force.z();
  Clock::time_point prev_t = Clock::now();
  bool zero_seen = false;
  while (Clock::now() - last_packet < std::chrono::milliseconds(30)) {
    ASSERT_TRUE(dev->begin_frame(st));
    dev->end_frame(asked);
    const auto now = Clock::now();
    const double since = std::chrono::duration<double>(now - last_packet).count();
    const ForcePacket f = drv.force();
    if (since > o.watchdog_s + 0.0005) {  // the device's clock read before ours
      EXPECT_EQ(st.buttons, 0u) << since;
      EXPECT_TRUE(f.flags & kForceWatchdog);
    }
    if (since > o.watchdog_s + o.ramp_s + 0.001) {
      EXPECT_EQ(f.force.z(), 0.0) << since;
    }
    // No step: the gain moves at 1/ramp_s per second at most.
    const double dt = std::chrono::duration<double>(now - prev_t).count();
    EXPECT_LE(std::abs(f.force.z() - prev), 2.0 * (dt + 1e-4) / o.ramp_s);  // 0.1 ms: the two clocks' reads
    zero_seen |= f.force.z() == 0.0;
    prev = f.force.z();
    prev_t = now;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  EXPECT_TRUE(zero_seen);
  EXPECT_EQ(dev->counters().watchdog_trips, 1);
  // Packets again after a servo stall of 4 ms: the tool is back and the force ramps in from zero,
  // with no step for the stalled time.
  std::this_thread::sleep_for(std::chrono::milliseconds(4));
  drv.write(raw_device(seq++, Vec3(0, 0, 0.01), 1));
  ASSERT_TRUE(dev->begin_frame(st));
  dev->end_frame(asked);
  EXPECT_EQ(st.buttons, 1u);
  EXPECT_LT(drv.force().force.z(), 1.0);
  // The end packet ends the device.
  drv.write(raw_device(seq++, Vec3(0, 0, 0.01), 0, kDeviceEnd));
  EXPECT_FALSE(dev->begin_frame(st));
}

}  // namespace
}  // namespace hdm::bridge
