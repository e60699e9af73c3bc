// Round trip of the device bridge (docs/bridge.md): a driver thread sends a device packet every
// period (1 kHz, 10 kHz) and waits for the force packet that answers it; a servo thread clocked by
// the packets (the loop of run_bridge_session, without a model: a spring to the workspace centre,
// so the figure is the bridge's own) reads each packet and posts its force. Reported: median, p99
// and maximum of send → force received [µs] over every packet, and how many took longer than a
// period ("late": the driver then sends its next packet late) or never came within 100 ms ("lost").
//
//   bench_bridge [seconds per case=3]
//   bench_bridge --serve ENDPOINT SECONDS   (only the hdm side, for another driver such as
//                                            examples/python/bridge_client.py)
// Both threads spin, so the two cores of a small machine are busy; the figures are the transport's
// plus the scheduler's (other processes' load shows in the p99 and the maximum).
#include <hdm/bridge/bridge_device.h>
#include <hdm/bridge/bridge_driver.h>
#include <hdm/core/percentile.h>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

using namespace hdm;
using namespace hdm::bridge;
using Clock = std::chrono::steady_clock;

namespace {

struct Result {
  double median_us = 0, p99_us = 0, max_us = 0;
  int64_t sent = 0, late = 0, lost = 0;
};

Result run(const std::string& endpoint, double rate_hz, double seconds) {
  BridgeOptions o;
  o.secret = "bench-bridge-secret-0123456789";
  o.watchdog_s = 1.0;  // the bench measures latency, not the watchdog
  auto device = BridgeDevice::open(endpoint, o);
  const std::string target = device->port() > 0 ? "udp:" + std::to_string(device->port()) : endpoint;
  std::atomic<bool> stop{false};
  std::thread servo([&] {  // the servo loop clocked by the packets
    DeviceState st;
    while (!stop.load(std::memory_order_relaxed)) {
      if (!device->receive()) continue;
      device->begin_frame(st);
      device->end_frame(-200.0 * st.position);
    }
  });
  auto driver = BridgeDriver::connect(target, o.secret);
  const double period = 1.0 / rate_hz;
  std::vector<double> rtt;
  rtt.reserve(size_t(rate_hz * seconds) + 1);
  Result r;
  const auto start = Clock::now();
  for (int64_t k = 0; k < int64_t(rate_hz * seconds); ++k) {
    const auto due = start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(k * period));
    while (Clock::now() < due) {}
    DevicePacket p;
    p.sequence = uint64_t(k + 1);
    p.time_s = k * period;
    p.position = Vec3(0.01 * std::sin(k * period), 0, 0.01);
    const auto t0 = Clock::now();
    driver->send(p);
    ++r.sent;
    ForcePacket f;
    if (driver->wait_force(f, p.sequence, 0.1)) {
      rtt.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
      r.late += rtt.back() > period * 1e6;
    } else {
      ++r.lost;
    }
  }
  stop = true;
  servo.join();
  if (!rtt.empty()) {
    r.max_us = *std::max_element(rtt.begin(), rtt.end());
    r.median_us = percentile(rtt, 0.5);
    r.p99_us = percentile(rtt, 0.99);
  }
  return r;
}

}  // namespace

int serve(const std::string& endpoint, double seconds) {
  auto device = BridgeDevice::open(endpoint);
  std::printf("serving %s for %.0f s\n", device->endpoint().c_str(), seconds);
  std::fflush(stdout);
  DeviceState st;
  const auto end = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
  while (Clock::now() < end) {
    if (!device->receive()) continue;
    if (!device->begin_frame(st)) break;
    device->end_frame(-200.0 * st.position);
  }
  const BridgeCounters c = device->counters();
  std::printf("accepted %lld, dropped %lld\n", static_cast<long long>(c.accepted), static_cast<long long>(c.dropped()));
  return 0;
}

int main(int argc, char** argv) {
  if (argc == 4 && std::string(argv[1]) == "--serve") return serve(argv[2], std::atof(argv[3]));
  const double seconds = argc > 1 ? std::atof(argv[1]) : 3.0;
  if (!(seconds > 0)) {
    std::fprintf(stderr, "usage: bench_bridge [seconds per case > 0]\n");
    return 2;
  }
  std::printf("%-6s %8s %12s %10s %10s %8s %8s %8s\n", "link", "rate_hz", "median_us", "p99_us", "max_us", "sent",
              "late", "lost");
  const std::string shm = "hdm-bench-bridge-" + std::to_string(::getpid());
  for (const std::string& endpoint : {std::string("udp:0"), "shm:" + shm})
    for (double rate : {1000.0, 10000.0}) {
      const Result r = run(endpoint, rate, seconds);
      std::printf("%-6s %8.0f %12.1f %10.1f %10.1f %8lld %8lld %8lld\n", endpoint.substr(0, 3).c_str(), rate,
                  r.median_us, r.p99_us, r.max_us, static_cast<long long>(r.sent), static_cast<long long>(r.late),
                  static_cast<long long>(r.lost));
    }
  return 0;
}
