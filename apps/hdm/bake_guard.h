// SPDX-License-Identifier: MIT
#pragma once
// What `hdm bake` checks before it reads its input: the output is not the input and is named as a
// model, the options fit the .hdm format's limits, and the estimated peak memory fits the budget.
#include <cstdint>
#include <string>

namespace CLI {
class App;
}

namespace hdm::app {

/// The options of a bake that decide its output and its size.
struct BakeRequest {
  std::string input, output;
  int slabs = 0;  ///< --slabs (0: from the input and --density)
  int grid = 16, texels = 2;
  double density = 4;
  uint64_t max_input_bytes = 0;  ///< --max-input-mb
};

/// Adds the bake's `--max-memory` to @p bake (the budget guard_bake() compares with).
void add_bake_budget(CLI::App& bake);

/// Throws InvalidInput when the output is the input or has a mesh's extension, when --slabs,
/// --grid and --texels ask for more samples or texels than a .hdm file holds (naming them), or
/// when the estimated peak memory exceeds the budget (naming --max-memory). O(1) plus a stat of
/// each file.
void guard_bake(const BakeRequest& r);

}  // namespace hdm::app
