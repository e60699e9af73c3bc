// SPDX-License-Identifier: MIT
// Wire format version 3: the pose (position, orientation, angular velocity) in and the wrench
// (force, torque) out, against the table of docs/bridge.md written here byte by byte; bit-exact
// round trips through encode/decode and through a BridgeDevice; version 2 still read (identity
// orientation, torque dropped); truncated and unknown-version packets refused with a message.
#include <hdm/bridge/bridge_device.h>
#include <hdm/bridge/wire_format.h>

#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

namespace hdm::bridge {
namespace {

constexpr uint64_t kPoseSession = 0x5e5510'0000'0003ull;
const std::string kPoseSecret = "a-test-secret-of-32-characters!!";

// A packet of @p version laid out from the documented table (not by encode()).
struct Raw {
  std::vector<std::byte> b;
  Raw(uint16_t version, uint16_t kind, uint64_t seq, size_t bytes) : b(bytes) {
    const char magic[4] = {'H', 'D', 'M', 'B'};
    const auto size = static_cast<uint32_t>(bytes);
    put(0, magic, 4);
    put(4, &version, 2);
    put(6, &kind, 2);
    put(8, &size, 4);
    put(16, &seq, 8);
    put(24, &kPoseSession, 8);
  }
  void put(size_t off, const void* v, size_t n) { std::memcpy(b.data() + off, v, n); }
  void put3(size_t off, const Vec3& v) { put(off, v.data(), 24); }
};

// A version 3 device packet: time 32, position 40, velocity 64, buttons 88, orientation (w, x, y, z)
// 96, angular velocity 128; 152 bytes.
Raw raw_device_v3(uint64_t seq, const Vec3& x, const Eigen::Quaterniond& q, const Vec3& w) {
  Raw r(3, 1, seq, 152);
  const double t = 0.001 * double(seq), qw = q.w();
  const uint32_t buttons = 1;
  r.put(32, &t, 8);
  r.put3(40, x);
  r.put3(64, Vec3(0.01, 0.02, 0.03));
  r.put(88, &buttons, 4);
  r.put(96, &qw, 8);
  r.put3(104, q.vec());
  r.put3(128, w);
  return r;
}

Raw raw_pose_hello(uint16_t version) {
  Raw r(version, 3, 0, version == 3 ? 152 : 96);
  const auto n = static_cast<uint32_t>(kPoseSecret.size());
  r.put(32, &n, 4);
  r.put(36, kPoseSecret.data(), kPoseSecret.size());
  return r;
}

TEST(BridgeWireFormat, Version3CarriesThePoseAndTheWrenchBitExactly) {
  DevicePacket p;
  p.sequence = 42;
  p.session = kPoseSession;
  p.time_s = 0.042;
  p.position = Vec3(0.1, -0.2, 0.3);
  p.velocity = Vec3(0.01, 0.02, 0.03);
  p.buttons = 1;
  p.orientation = Eigen::Quaterniond(0.9, 0.1 / 3, -0.2, std::sqrt(0.07));  // not unit: sent as is
  p.angular_velocity = Vec3(1.0 / 3, -2.5, 1e-300);
  std::byte out[kPacketBytes];
  ASSERT_EQ(encode(p, out), kPacketBytes);
  const Raw expected = raw_device_v3(42, p.position, p.orientation, p.angular_velocity);
  EXPECT_EQ(0, std::memcmp(out, expected.b.data(), kPacketBytes));
  DevicePacket back;
  ASSERT_EQ(DecodeStatus::Ok, decode(out, kPacketBytes, back));
  EXPECT_EQ(back.version, 3);
  EXPECT_EQ(back.position, p.position);
  EXPECT_EQ(back.orientation.coeffs(), p.orientation.coeffs());
  EXPECT_EQ(back.angular_velocity, p.angular_velocity);

  ForcePacket f;
  f.force = Vec3(1.0 / 3, 2, -3);
  f.torque = Vec3(0.01 / 7, -0.02, 0.125);
  f.gain = 0.75;
  ASSERT_EQ(encode(f, out), kPacketBytes);
  Vec3 torque;
  std::memcpy(torque.data(), out + 96, 24);  // the table: torque at 96, zero padding after it
  EXPECT_EQ(torque, f.torque);
  for (size_t i = 120; i < kPacketBytes; ++i) EXPECT_EQ(out[i], std::byte{0}) << i;
  ForcePacket fb;
  ASSERT_EQ(DecodeStatus::Ok, decode(out, kPacketBytes, fb));
  EXPECT_EQ(fb.force, f.force);
  EXPECT_EQ(fb.torque, f.torque);
  EXPECT_EQ(fb.gain, f.gain);
}

TEST(BridgeWireFormat, Version2IsStillReadWithoutOrientationOrTorque) {
  DevicePacket p;
  p.version = 2;
  p.session = kPoseSession;
  p.sequence = 3;
  p.position = Vec3(0.01, 0.02, 0.03);
  p.orientation = Eigen::Quaterniond(0, 1, 0, 0);  // not written in version 2
  p.angular_velocity = Vec3(1, 2, 3);
  std::byte out[kPacketBytes];
  ASSERT_EQ(encode(p, out), kPacketBytesV2);
  DevicePacket back;
  back.orientation = Eigen::Quaterniond(0, 0, 1, 0);
  back.angular_velocity = Vec3::Ones();
  ASSERT_EQ(DecodeStatus::Ok, decode(out, kPacketBytesV2, back));
  EXPECT_EQ(back.version, 2);
  EXPECT_EQ(back.position, p.position);
  EXPECT_EQ(back.orientation.coeffs(), Eigen::Quaterniond::Identity().coeffs());
  EXPECT_EQ(back.angular_velocity, Vec3::Zero());
  ForcePacket f;
  f.version = 2;
  f.force = Vec3(0, 0, 1);
  f.torque = Vec3(0.1, 0, 0);
  ASSERT_EQ(encode(f, out), kPacketBytesV2);
  ForcePacket fb;
  ASSERT_EQ(DecodeStatus::Ok, decode(out, kPacketBytesV2, fb));
  EXPECT_EQ(fb.force, f.force);
  EXPECT_EQ(fb.torque, Vec3::Zero()) << "version 2 carries no torque";
}

TEST(BridgeWireFormat, TruncatedAndUnknownVersionsAreRefused) {
  const Raw good = raw_device_v3(5, Vec3::Zero(), Eigen::Quaterniond::Identity(), Vec3::Zero());
  DevicePacket p;
  ASSERT_EQ(DecodeStatus::Ok, decode(good.b.data(), good.b.size(), p));
  EXPECT_EQ(DecodeStatus::BadSize, decode(good.b.data(), kPacketBytesV2, p)) << "a version 3 packet cut to 96 bytes";
  EXPECT_EQ(DecodeStatus::BadSize, decode(good.b.data(), kPacketBytes - 8, p));
  EXPECT_EQ(DecodeStatus::BadSize, decode(good.b.data(), 10, p));
  for (const uint16_t version : {uint16_t(1), uint16_t(4), uint16_t(0xffff)}) {
    Raw r = good;
    r.put(4, &version, 2);
    EXPECT_EQ(DecodeStatus::BadVersion, decode(r.b.data(), r.b.size(), p)) << version;
  }
  Raw nan = good;
  const double bad = std::nan("");
  nan.put(104, &bad, 8);
  EXPECT_EQ(DecodeStatus::NonFinite, decode(nan.b.data(), nan.b.size(), p)) << "a NaN orientation";
  EXPECT_NE(std::string(describe(DecodeStatus::BadVersion)).find("versions 2 and 3"), std::string::npos);
  EXPECT_NE(std::string(describe(DecodeStatus::BadSize)).find("152"), std::string::npos);
}

// A driver writing into the shared-memory region (device block at 64, force block at 256).
struct Region {
  explicit Region(const std::string& name) {
    const int fd = ::shm_open(("/" + name).c_str(), O_RDWR, 0);
    EXPECT_GE(fd, 0);
    base = static_cast<std::byte*>(::mmap(nullptr, 4096, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0));
    ::close(fd);
  }
  ~Region() { ::munmap(base, 4096); }
  void write(const std::vector<std::byte>& p) {
    uint64_t c;
    std::memcpy(&c, base + 64, 8);
    c += 2;
    std::memcpy(base + 72, p.data(), p.size());
    std::memcpy(base + 64, &c, 8);
  }
  size_t force(ForcePacket& f) const {
    const size_t n = declared_bytes(base + 264, kPacketBytes);
    EXPECT_EQ(DecodeStatus::Ok, decode(base + 264, n, f));
    return n;
  }
  std::byte* base;
};

// Through a BridgeDevice: the pose read is the packet's (orientation normalised), the wrench sent
// is the one commanded, bit for bit once the watchdog's gain is 1; a version 2 driver is answered
// in version 2, without torque.
TEST(BridgeDevice, PoseInWrenchOutThroughSharedMemory) {
  BridgeOptions o;
  o.secret = kPoseSecret;
  o.spec.max_torque_nm = 1.0;
  const std::string name = "hdm-test-pose-" + std::to_string(::getpid());
  auto dev = BridgeDevice::open("shm:" + name, o);
  Region drv(name);
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.5, Vec3(1, 2, 3).normalized()));
  const Vec3 w(0.25, -0.5, 2.0), force(0.5, -0.25, 1.0 / 3), torque(0.01 / 3, 0.02, -0.0625);
  DeviceState st;
  drv.write(raw_pose_hello(3).b);
  ASSERT_TRUE(dev->begin_frame(st));
  for (uint64_t seq = 1; seq <= 30; ++seq) {  // 15 ms: the gain ramps in (5 ms)
    drv.write(raw_device_v3(seq, Vec3(0, 0, 0.01), q, w).b);
    ASSERT_TRUE(dev->begin_frame(st));
    dev->end_frame(force, torque);
    std::this_thread::sleep_for(std::chrono::microseconds(500));
  }
  ASSERT_EQ(dev->gain(), 1.0);
  EXPECT_EQ(st.orientation.coeffs(), q.normalized().coeffs());  // the packet's, normalised
  EXPECT_EQ(st.angular_velocity, w);
  ForcePacket f;
  EXPECT_EQ(drv.force(f), kPacketBytes);
  EXPECT_EQ(f.version, 3);
  EXPECT_EQ(f.force, force);
  EXPECT_EQ(f.torque, torque);
  dev->end_frame(force, Vec3(0, 0, 5.0));
  drv.force(f);
  EXPECT_EQ(f.torque, Vec3(0, 0, 1.0)) << "clamped to max_torque_nm";

  // A version 2 driver (a new session): identity orientation, answers without torque.
  Raw hello = raw_pose_hello(2);
  const uint64_t other = kPoseSession + 1;
  hello.put(24, &other, 8);
  drv.write(hello.b);
  ASSERT_TRUE(dev->begin_frame(st));
  Raw d2(2, 1, 1, 96);
  d2.put(24, &other, 8);
  d2.put3(40, Vec3(0, 0, 0.02));
  drv.write(d2.b);
  ASSERT_TRUE(dev->begin_frame(st));
  EXPECT_EQ(st.position, Vec3(0, 0, 0.02));
  EXPECT_EQ(st.orientation.coeffs(), Eigen::Quaterniond::Identity().coeffs());
  EXPECT_EQ(st.angular_velocity, Vec3::Zero());
  dev->end_frame(force, torque);
  EXPECT_EQ(drv.force(f), kPacketBytesV2);
  EXPECT_EQ(f.version, 2);
  EXPECT_EQ(f.torque, Vec3::Zero());
}

}  // namespace
}  // namespace hdm::bridge
