// SPDX-License-Identifier: MIT
#pragma once
// Subcommands of the hdm program, one file each (after openvdb_cmd and meshoptimizer's gltfpack).

namespace CLI {
class App;
}

namespace hdm::app {
void add_bake_command(CLI::App& app);
void add_sculpt_command(CLI::App& app);
void add_info_command(CLI::App& app);
void add_export_command(CLI::App& app);
void add_render_command(CLI::App& app);
void add_check_command(CLI::App& app);
void add_feel_command(CLI::App& app);
void add_bench_command(CLI::App& app);
void add_subdivide_command(CLI::App& app);
}  // namespace hdm::app
