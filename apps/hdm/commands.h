// SPDX-License-Identifier: MIT
#pragma once
// Subcommands of the hdm program, one file each (after openvdb_cmd and meshoptimizer's gltfpack).

#include <cstdint>

namespace CLI {
class App;
}

namespace hdm::app {

/// The input size limit of every file a command reads (meshes, models, scripts, recordings).
struct InputLimit {
  uint64_t mib = 1024;  ///< [MiB]; the library's default_max_input_bytes
  uint64_t bytes() const { return mib << 20; }
};
/// Adds `--max-input-mb N` to @p cmd, stored in @p limit.
void add_input_limit(CLI::App* cmd, InputLimit& limit);

void add_bake_command(CLI::App& app);
void add_sculpt_command(CLI::App& app);
void add_info_command(CLI::App& app);
void add_export_command(CLI::App& app);
void add_render_command(CLI::App& app);
void add_check_command(CLI::App& app);
void add_feel_command(CLI::App& app);
void add_bench_command(CLI::App& app);
void add_subdivide_command(CLI::App& app);
void add_studio_command(CLI::App& app);
void add_bridge_command(CLI::App& app);
}  // namespace hdm::app
