// SPDX-License-Identifier: MIT
#include "bake_guard.h"

#include "memory_budget.h"
#include "output_guard.h"

#include <hdm/core/error.h>
#include <hdm/slab/bake.h>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

namespace hdm::app {
namespace {

MemoryBudget& bake_budget() {
  static MemoryBudget budget;
  return budget;
}

// The .hdm loader's limits (src/io/hdm_file.cpp, check_layout_sizes): every count of samples,
// texels and texel grid points fits an int32.
constexpr double kFormatLimit = std::numeric_limits<int32_t>::max();

double grid_points(double slabs, double k) { return slabs * (k + 1) * (k + 2) / 2; }

// 2686494720 as "2,686,494,720", as the loader's messages write counts.
std::string count(double x) {
  std::string digits = std::to_string(static_cast<uint64_t>(x)), out;
  for (size_t k = 0; k < digits.size(); ++k) {
    if (k > 0 && (digits.size() - k) % 3 == 0) out += ',';
    out += digits[k];
  }
  return out;
}

void check_format_limits(const BakeRequest& r) {
  if (r.slabs <= 0) return;  // the slab count follows the input: the bake itself checks it
  const double S = r.slabs, n = r.grid, big = double(r.grid) * r.texels;
  if (grid_points(S, n) > kFormatLimit)
    throw InvalidInput("--slabs " + std::to_string(r.slabs) + " with --grid " + std::to_string(r.grid) + ": " +
                       count(grid_points(S, n)) +
                       " displacement samples, more than a .hdm file holds (2,147,483,647); lower --grid or --slabs");
  if (grid_points(S, big) > kFormatLimit)
    throw InvalidInput("--grid " + std::to_string(r.grid) + " with --texels " + std::to_string(r.texels) + " at --slabs " +
                       std::to_string(r.slabs) + ": " + count(grid_points(S, big)) +
                       " colour texels, more than a .hdm file holds (2,147,483,647); lower --texels or --grid");
}

}  // namespace

void add_bake_budget(CLI::App& bake) { add_memory_budget(&bake, bake_budget()); }

void guard_bake(const BakeRequest& r) {
  check_outputs({r.output}, {r.input});
  check_model_output(r.output);
  check_format_limits(r);
  const uint64_t bytes = file_bytes(r.input);
  // A bake has at most as many slabs as the input has triangles (the coarse mesh decimates it).
  BakeShape shape{bytes, std::min<int64_t>(r.slabs, triangles_in_file(r.input, bytes, true)), r.grid, r.texels};
  if (r.slabs <= 0) {  // the bake's own rule, on the triangles the file may hold
    BakeOptions o;
    o.density = r.density;
    o.grid_n = r.grid;
    shape.slabs = default_slab_count(triangles_in_file(r.input, bytes, false), o);
  }
  require_memory(bake_peak_bytes(shape), bake_budget(), "hdm bake " + r.input,
                 std::to_string(shape.slabs) + (r.slabs > 0 && shape.slabs == r.slabs ? "" : " (estimated)") +
                     " slabs at --grid " +
                     std::to_string(r.grid) + " and --texels " + std::to_string(r.texels) + ", " + count(double(bytes)) +
                     " bytes of input");
}

}  // namespace hdm::app
