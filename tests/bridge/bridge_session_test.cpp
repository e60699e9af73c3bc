// SPDX-License-Identifier: MIT
// Who may drive the bridge (docs/bridge.md, docs/reliability.md): a restarted driver (a new hello,
// sequence numbers from 1 again) is served at once and its old session is ignored; a packet from
// another socket (a forged one, a maximal sequence number, an END) changes nothing; a wrong secret
// is refused and counted; the shared-memory region is private to its user; the secret file is
// created private and refused when others may read it.
#include <hdm/bridge/bridge_device.h>
#include <hdm/bridge/bridge_driver.h>
#include <hdm/bridge/bridge_secret.h>
#include <hdm/bridge/wire_format.h>
#include <hdm/core/error.h>

#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <thread>

namespace hdm::bridge {
namespace {

const std::string kSessionSecret = "session-test-secret-0123456789";

// A device with a servo thread ticking it (each packet: one frame, a force of -100·position).
struct Served {
  explicit Served(const std::string& endpoint) {
    BridgeOptions o;
    o.secret = kSessionSecret;
    o.watchdog_s = 1.0;
    device = BridgeDevice::open(endpoint, o);
    servo = std::thread([this] {
      DeviceState st;
      while (!stop.load()) {
        if (!device->receive()) {
          std::this_thread::sleep_for(std::chrono::microseconds(50));
          continue;
        }
        if (!device->begin_frame(st)) ended = true;
        last_position = st.position.x();
        device->end_frame(-100.0 * st.position);
      }
    });
  }
  ~Served() {
    stop = true;
    servo.join();
  }
  std::string target() const {
    return device->port() > 0 ? "udp:" + std::to_string(device->port()) : device->endpoint();
  }
  std::unique_ptr<BridgeDevice> device;
  std::atomic<bool> stop{false}, ended{false};
  std::atomic<double> last_position{0};
  std::thread servo;
};

DevicePacket at(uint64_t seq, double x, uint32_t flags = 0) {
  DevicePacket p;
  p.sequence = seq;
  p.position = Vec3(x, 0, 0);
  p.flags = flags;
  return p;
}

// Sends @p p and waits for the force that answers it (2 s: a loaded machine, never a timing claim).
bool round_trip(BridgeDriver& d, const DevicePacket& p, ForcePacket& f) {
  return d.send(p) && d.wait_force(f, p.sequence, 2.0) && f.sequence == p.sequence;
}

void restart_is_served(const std::string& endpoint) {
  Served s(endpoint);
  auto first = BridgeDriver::connect(s.target(), kSessionSecret);
  ForcePacket f;
  for (uint64_t seq = 1; seq <= 20; ++seq) ASSERT_TRUE(round_trip(*first, at(seq, 0.001), f));
  // The driver restarts: a new process would start at sequence 1 again, in a new session.
  auto second = BridgeDriver::connect(s.target(), kSessionSecret);
  EXPECT_NE(second->session(), first->session());
  ASSERT_TRUE(round_trip(*second, at(1, 0.002), f)) << "the restarted driver's first packet was not answered";
  EXPECT_EQ(f.session, second->session());
  EXPECT_DOUBLE_EQ(f.force.x(), -100.0 * 0.002 * f.gain);
  // The old session is over: its packets are counted and ignored, the new one goes on.
  first->send(at(21, 0.5));
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  while (s.device->counters().wrong_session < 1 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::microseconds(100));  // the servo's look at the old packet
  ASSERT_TRUE(round_trip(*second, at(2, 0.003), f));
  EXPECT_DOUBLE_EQ(s.last_position.load(), 0.003);
  const BridgeCounters c = s.device->counters();
  EXPECT_EQ(c.sessions, 2);
  EXPECT_EQ(c.wrong_session, 1);
  EXPECT_EQ(c.accepted, 22);
}

TEST(BridgeSession, RestartedDriverIsServedAtOnceOverUdp) { restart_is_served("udp:0"); }
TEST(BridgeSession, RestartedDriverIsServedAtOnceOverSharedMemory) {
  restart_is_served("shm:hdm-test-restart-" + std::to_string(::getpid()));
}

// Raw datagrams from a socket of another process's kind: bound to its own port.
struct Intruder {
  explicit Intruder(int port) : fd(::socket(AF_INET, SOCK_DGRAM, 0)) {
    to.sin_family = AF_INET;
    to.sin_port = htons(static_cast<uint16_t>(port));
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  }
  ~Intruder() { ::close(fd); }
  void send(const std::byte* raw) {
    ASSERT_EQ(::sendto(fd, raw, kPacketBytes, 0, reinterpret_cast<sockaddr*>(&to), sizeof to), ssize_t(kPacketBytes));
  }
  int fd;
  sockaddr_in to{};
};

TEST(BridgeSession, ForgedPacketsFromAnotherSocketChangeNothing) {
  Served s("udp:0");
  auto driver = BridgeDriver::connect(s.target(), kSessionSecret);
  ForcePacket f;
  ASSERT_TRUE(round_trip(*driver, at(1, 0.001), f));
  Intruder intruder(s.device->port());
  alignas(8) std::byte raw[kPacketBytes];
  // The maximal sequence number and an END, with a guessed session and with the driver's own id
  // (as if it had leaked): from another socket, none is applied.
  for (uint64_t session : {uint64_t(1), driver->session()}) {
    DevicePacket p = at(std::numeric_limits<uint64_t>::max(), 0.9);
    p.session = session;
    encode(p, raw);
    intruder.send(raw);
    p = at(2, 0.9, kDeviceEnd);
    p.session = session;
    encode(p, raw);
    intruder.send(raw);
  }
  // A hello with a wrong secret from the intruder opens nothing.
  HelloPacket h;
  h.session = 77;
  h.secret_bytes = 20;
  std::memcpy(h.secret.data(), "not-the-secret-01234", 20);
  encode(h, raw);
  intruder.send(raw);
  // The driver goes on at sequence 2 and is served; the session never ended.
  ASSERT_TRUE(round_trip(*driver, at(2, 0.004), f));
  EXPECT_DOUBLE_EQ(s.last_position.load(), 0.004);
  EXPECT_FALSE(s.ended.load());
  const BridgeCounters c = s.device->counters();
  EXPECT_EQ(c.wrong_session, 4);
  EXPECT_EQ(c.bad_secret, 1);
  EXPECT_EQ(c.sessions, 1);
  EXPECT_EQ(c.accepted, 2);
}

TEST(BridgeSession, ASequenceNumberBeyondTheWindowIsRefusedWithoutLockingTheSession) {
  Served s("shm:hdm-test-window-" + std::to_string(::getpid()));
  auto driver = BridgeDriver::connect(s.target(), kSessionSecret);
  ForcePacket f;
  ASSERT_TRUE(round_trip(*driver, at(1, 0.001), f));
  driver->send(at(std::numeric_limits<uint64_t>::max(), 0.9));
  driver->send(at(2 + kSequenceWindow, 0.9));
  ASSERT_TRUE(round_trip(*driver, at(2, 0.005), f));  // still served in order
  EXPECT_DOUBLE_EQ(s.last_position.load(), 0.005);
  ASSERT_TRUE(round_trip(*driver, at(2 + kSequenceWindow, 0.006), f));  // the window's far edge
}

TEST(BridgeSession, AWrongSecretIsRefusedAndCounted) {
  Served s("udp:0");
  EXPECT_THROW(BridgeDriver::connect(s.target(), "a-wrong-secret-0123456789", 0.05), IoError);
  EXPECT_GE(s.device->counters().bad_secret, 1);
  EXPECT_EQ(s.device->counters().sessions, 0);
  EXPECT_THROW(BridgeDriver::connect(s.target(), "short"), InvalidInput);
}

TEST(BridgeSession, TheSharedMemoryRegionIsPrivate) {
  const std::string name = "hdm-test-mode-" + std::to_string(::getpid());
  BridgeOptions o;
  o.secret = kSessionSecret;
  const mode_t old = ::umask(0);  // whatever the umask, the region is 0600
  auto device = BridgeDevice::open("shm:" + name, o);
  ::umask(old);
  struct stat st {};
  ASSERT_EQ(::stat(("/dev/shm/" + name).c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
}

TEST(BridgeSecret, AMissingFileIsCreatedPrivateAndAnOpenOneRefused) {
  namespace fs = std::filesystem;
  const fs::path d = fs::temp_directory_path() / ("hdm-secret-" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  const std::string file = (d / "bridge.key").string();
  const std::string made = load_bridge_secret(file);
  EXPECT_GE(made.size(), kMinSecretBytes);
  struct stat st {};
  ASSERT_EQ(::stat(file.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
  EXPECT_EQ(load_bridge_secret(file), made);  // read back the same
  fs::permissions(file, fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  EXPECT_THROW(load_bridge_secret(file), InvalidInput);
  fs::create_symlink(file, d / "link.key");
  EXPECT_THROW(load_bridge_secret((d / "link.key").string()), InvalidInput);
  ::setenv(kSecretVariable, "from-the-environment-0123", 1);
  EXPECT_EQ(load_bridge_secret(""), "from-the-environment-0123");
  ::setenv(kSecretVariable, "short", 1);
  EXPECT_THROW(load_bridge_secret(""), InvalidInput);
  ::unsetenv(kSecretVariable);
  EXPECT_THROW(load_bridge_secret(""), InvalidInput);
  fs::remove_all(d);
}

}  // namespace
}  // namespace hdm::bridge
