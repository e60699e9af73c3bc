// SPDX-License-Identifier: MIT
// Checks of the studio's lockstep (studio_lockstep.sh runs the same scripted burr session twice with
// --ticks-per-frame): the servo loop runs a fixed number of ticks per frame, so the two runs record
// the same tool state at every probe, drilling included, and each probe sees whole frames of ticks.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

namespace {

std::string g_dir;       // set by main: the session's directory
long g_ticks_per_frame;  // set by main

nlohmann::json probes(const char* run) {
  std::ifstream in(g_dir + "/report_" + run + ".json");
  return nlohmann::json::parse(in)["probes"];
}

TEST(StudioLockstep, TwoRunsRecordTheSameToolState) {
  const nlohmann::json a = probes("a"), b = probes("b");
  ASSERT_TRUE(a.contains("drilled") && a.contains("tilted"));
  // The burr drilled: it pressed on the surface with its head.
  EXPECT_GT(a["drilled"]["head"]["contacts"].get<int>(), 0);
  for (const auto& [name, p] : a.items()) {
    ASSERT_TRUE(b.contains(name)) << name;
    EXPECT_EQ(p, b[name]) << "probe " << name << " differs between the runs";
  }
}

TEST(StudioLockstep, ProbesSeeWholeFramesOfTicks) {
  // A probe records the state the last tick of the frames before it left: tick index k·N - 1.
  const nlohmann::json a = probes("a");
  for (const auto& [name, p] : a.items())
    EXPECT_EQ((p["tick"].get<long>() + 1) % g_ticks_per_frame, 0) << name << ": tick " << p["tick"];
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  if (argc < 3) {
    std::fprintf(stderr, "usage: studio_lockstep_tests DIR TICKS_PER_FRAME\n");
    return 2;
  }
  g_dir = argv[1];
  g_ticks_per_frame = std::atol(argv[2]);
  return RUN_ALL_TESTS();
}
