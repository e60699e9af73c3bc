// SPDX-License-Identifier: MIT
// hdm: bake, sculpt, inspect, export and render haptic displacement map models.
#include "bake_guard.h"
#include "commands.h"

#include <hdm/io/read_file.h>

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

void hdm::app::add_input_limit(CLI::App* cmd, InputLimit& limit) {
  static_assert(InputLimit{}.mib << 20 == default_max_input_bytes);
  cmd->add_option("--max-input-mb", limit.mib,
                  "refuse input files larger than this many MiB before reading them (default 1024)")
      ->check(CLI::Range(uint64_t{1}, uint64_t{1} << 30));
}

int main(int argc, char** argv) {
  CLI::App app{"hdm: touch, sculpt and paint detailed 3D models with haptic displacement maps"};
  app.require_subcommand(1);
  hdm::app::add_bake_command(app);
  hdm::app::add_bake_budget(*app.get_subcommand("bake"));
  hdm::app::add_sculpt_command(app);
  hdm::app::add_info_command(app);
  hdm::app::add_export_command(app);
  hdm::app::add_render_command(app);
  hdm::app::add_check_command(app);
  hdm::app::add_feel_command(app);
  hdm::app::add_bench_command(app);
  hdm::app::add_subdivide_command(app);
  hdm::app::add_studio_command(app);
  hdm::app::add_bridge_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // CLI11's own codes (105 for a failed validator, ...) become the documented usage code 2.
    return app.exit(e) == 0 ? 0 : 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hdm: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
