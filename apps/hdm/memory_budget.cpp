// SPDX-License-Identifier: MIT
#include "memory_budget.h"

#include <hdm/core/error.h>

#include <CLI/CLI.hpp>

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace hdm::app {
namespace {

constexpr double kMiB = 1024.0 * 1024.0;

// Bytes per unit, fitted to the peak resident size (getrusage's ru_maxrss) of the commands on
// sphere.off, bunny00.off, armadillo.off and refined_elephant.off at 40 to 3,000 slabs, grid 4 to
// 64 and 1 to 16 texels per interval (docs/reliability.md has the table): a least-squares fit gave
// 27 MB + 363 B per sample + 129 B per texel; these round it up so that the estimate is at or above
// every measured peak, by at most a half (twice on tiny models, where the base dominates).
constexpr double kBase = 32 * kMiB;           // the program, its libraries, Embree's and TBB's arenas
constexpr double kPerInputByte = 8;           // the mesh, its repair, orientation, BVH and fidelity
constexpr double kPerSample = 380;            // displacements, fields, normals, slots, bake rays
constexpr double kPerTexel = 135;             // colour, roughness, texel slots and rays, the saved bytes
constexpr double kPerModelByte = 10;          // a loaded .hdm: its bytes and the layouts rebuilt from them
constexpr double kPerContactPoint = 32;       // points, exact and slab answers of hdm check (measured 24)
constexpr double kSculptBase = 64 * kMiB;     // the stroke editor's buffers and undo history (measured 50)

double mib(double bytes) { return bytes / kMiB; }

}  // namespace

uint64_t available_memory_bytes() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  uint64_t kib = 0;
  std::string unit;
  while (in >> key >> kib >> unit)
    if (key == "MemAvailable:") return kib * 1024;
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  return pages > 0 && page > 0 ? uint64_t(pages) * uint64_t(page) : uint64_t(1) << 32;
}

uint64_t MemoryBudget::bytes() const { return mib > 0 ? mib << 20 : available_memory_bytes(); }

void add_memory_budget(CLI::App* cmd, MemoryBudget& budget) {
  cmd->add_option("--max-memory", budget.mib,
                  "refuse to start when the estimated peak memory exceeds this many MiB (default: the "
                  "machine's available memory)")
      ->check(CLI::Range(uint64_t{1}, uint64_t{1} << 30));
}

int64_t triangles_in_file(const std::string& path, uint64_t bytes, bool at_most) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  // Binary STL: 50 bytes a triangle (text STL takes more). Binary PLY: a 13-byte face and half a
  // 12-byte vertex. Text (OFF, OBJ, text PLY): "3 a b c" and half of "x y z", at least 11 bytes,
  // 24 to 35 in the models of data/meshes.
  const double per = ext == ".stl" ? 50 : at_most ? 11 : ext == ".ply" ? 19 : 24;
  return static_cast<int64_t>(double(bytes) / per) + 1;
}

uint64_t bake_peak_bytes(const BakeShape& s) {
  const double n = s.grid, big = double(s.grid) * s.texels, S = double(std::max<int64_t>(s.slabs, 1));
  const double samples = S * (n + 1) * (n + 2) / 2, texels = S * (big + 1) * (big + 2) / 2;
  return static_cast<uint64_t>(kBase + kPerInputByte * double(s.input_bytes) + kPerSample * samples +
                               kPerTexel * texels);
}

uint64_t check_peak_bytes(uint64_t model_bytes, uint64_t input_bytes, int64_t points) {
  return static_cast<uint64_t>(kBase + kPerModelByte * double(model_bytes) + kPerInputByte * double(input_bytes) +
                               kPerContactPoint * double(points));
}

uint64_t sculpt_peak_bytes(uint64_t model_bytes, int64_t ticks, int64_t per_tick) {
  return static_cast<uint64_t>(kBase + kSculptBase + kPerModelByte * double(model_bytes) +
                               double(per_tick) * double(ticks));
}

uint64_t file_bytes(const std::string& path) {
  struct stat st{};
  return !path.empty() && ::stat(path.c_str(), &st) == 0 ? uint64_t(st.st_size) : 0;
}

void require_memory(uint64_t estimate, const MemoryBudget& budget, const std::string& what,
                    const std::string& detail) {
  const uint64_t limit = budget.bytes();
  if (estimate <= limit) return;
  char text[512];
  std::snprintf(text, sizeof text,
                "%s needs about %.0f MiB (%s), more than the memory budget of %.0f MiB (%s); --max-memory MIB "
                "changes the budget",
                what.c_str(), mib(double(estimate)), detail.c_str(), mib(double(limit)),
                budget.mib > 0 ? "--max-memory" : "the memory available now");
  throw InvalidInput(text);
}

}  // namespace hdm::app
