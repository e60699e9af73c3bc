// SPDX-License-Identifier: MIT
// The device bridge's threads under ThreadSanitizer (scripts/test_tsan.sh): a driver thread sends
// device packets as fast as it can over UDP (hdm's receiver thread fills the block, its sender thread
// sends the forces) and over shared memory (the driver writes the block the servo thread reads),
// while the servo thread answers each packet and a third thread reads the counters as the studio's
// overlay does. Every force received must be the one computed from the very packet it answers (no
// torn packet either way), and the sequence numbers answered never go back.
#include <hdm/bridge/bridge_device.h>
#include <hdm/bridge/bridge_driver.h>

#include <gtest/gtest.h>

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <string>
#include <thread>

namespace hdm::bridge {
namespace {

// Under 2 cm from the centre: the force (100 N/m) stays under the 3.3 N clamp.
Vec3 position_of(uint64_t seq) { return Vec3(1e-5 * double(seq % 1000), -1e-4 * double(seq % 77), 0.01); }

void drive(const std::string& endpoint) {
  BridgeOptions o;
  o.secret = "concurrency-test-secret-0123";
  o.watchdog_s = 1.0;
  auto device = BridgeDevice::open(endpoint, o);
  std::atomic<bool> stop{false};
  std::thread servo([&] {
    DeviceState st;
    while (!stop.load(std::memory_order_relaxed)) {
      if (!device->receive()) {
        std::this_thread::yield();
        continue;
      }
      device->begin_frame(st);
      device->end_frame(-100.0 * st.position);  // 1 N at most: under the clamp
    }
  });
  std::thread overlay([&] {
    int64_t last = 0;
    while (!stop.load(std::memory_order_relaxed)) {
      const BridgeCounters c = device->counters();
      EXPECT_GE(c.accepted, last);
      last = c.accepted;
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
  });
  auto driver =
      BridgeDriver::connect(device->port() > 0 ? "udp:" + std::to_string(device->port()) : endpoint, o.secret);
  uint64_t answered = 0;
  int checked = 0, waited = 0;
  auto check = [&](const ForcePacket& f) {
    EXPECT_GE(f.sequence, answered);
    answered = f.sequence;
    EXPECT_EQ(f.force, Vec3(Vec3(-100.0 * position_of(f.sequence)) * f.gain)) << "a torn packet at " << f.sequence;
    ++checked;
  };
  // Bursts of 16 packets sent back to back (the servo and the transport threads race with the
  // driver), then a wait for the burst's last answer (so UDP's buffers never overflow).
  for (uint64_t seq = 1; seq <= 2000; ++seq) {
    DevicePacket p;
    p.sequence = seq;
    p.position = position_of(seq);
    driver->send(p);
    ForcePacket f;
    if (driver->poll_force(f) && f.sequence > 0) check(f);
    if (seq % 16 == 0) {
      if (answered >= seq || driver->wait_force(f, seq, 2.0)) ++waited;  // the poll above may have had it
      if (answered < seq && f.sequence >= seq) check(f);
    }
  }
  stop = true;
  servo.join();
  overlay.join();
  EXPECT_GT(waited, 100);  // of 125 bursts (localhost UDP may still drop a datagram)
  EXPECT_EQ(device->counters().dropped(), 0);
}

TEST(BridgeConcurrency, UdpReceiverSenderAndServo) { drive("udp:0"); }
TEST(BridgeConcurrency, SharedMemoryDriverAndServo) { drive("shm:hdm-test-tsan-" + std::to_string(::getpid())); }

}  // namespace
}  // namespace hdm::bridge
