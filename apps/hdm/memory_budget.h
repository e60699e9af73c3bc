// SPDX-License-Identifier: MIT
#pragma once
// Peak memory of a command, estimated before it allocates, against a budget (docs/reliability.md):
// the machine's available memory unless --max-memory says otherwise. The estimates are fitted to
// peak resident sizes measured with getrusage (the figures are in memory_budget.cpp).
#include <cstdint>
#include <string>

namespace CLI {
class App;
}

namespace hdm::app {

/// The memory a command may use.
struct MemoryBudget {
  uint64_t mib = 0;        ///< --max-memory [MiB]; 0: the available memory (MemAvailable of /proc/meminfo)
  uint64_t bytes() const;  ///< the budget [bytes]
};

/// Adds `--max-memory MIB` to @p cmd, stored in @p budget.
void add_memory_budget(CLI::App* cmd, MemoryBudget& budget);

/// MemAvailable of /proc/meminfo [bytes]; the physical memory (sysconf) when it cannot be read.
uint64_t available_memory_bytes();

/// What a bake builds: slabs, grid n and texels per interval.
struct BakeShape {
  uint64_t input_bytes = 0;  ///< size of the input mesh file
  int64_t slabs = 0;         ///< slab count (estimated from the input when not given)
  int grid = 16, texels = 2;
};
/// Triangles a mesh file @p path of @p bytes bytes holds, by its extension: with @p at_most, the
/// most its densest layout can hold (a text face line and half a vertex line take at least 11
/// bytes); otherwise the usual count (24 bytes a triangle in text, 19 in binary PLY, 50 in STL).
int64_t triangles_in_file(const std::string& path, uint64_t bytes, bool at_most);
/// Peak memory of a bake [bytes] (the model, its layouts and texture, the input and its BVH).
uint64_t bake_peak_bytes(const BakeShape& shape);
/// Peak memory of `hdm check` [bytes]: the model file, the input and @p points contact points.
uint64_t check_peak_bytes(uint64_t model_bytes, uint64_t input_bytes, int64_t points);
/// Peak memory of `hdm sculpt` [bytes]: the model file and @p ticks ticks of @p per_tick bytes each
/// (trajectory, records; the caller counts what its options add).
uint64_t sculpt_peak_bytes(uint64_t model_bytes, int64_t ticks, int64_t per_tick);
/// Size of the file @p path [bytes]; 0 when it cannot be read (the reader then names the error).
uint64_t file_bytes(const std::string& path);

/// Throws InvalidInput "<what> needs about X MiB (<detail>), more than the memory budget of Y MiB
/// (...); --max-memory MIB changes it" when @p estimate exceeds @p budget.
void require_memory(uint64_t estimate, const MemoryBudget& budget, const std::string& what,
                    const std::string& detail);

}  // namespace hdm::app
