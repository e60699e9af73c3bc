// SPDX-License-Identifier: MIT
// hdm: bake, sculpt, inspect, export and render haptic displacement map models.
#include "commands.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
  CLI::App app{"hdm: touch, sculpt and paint detailed 3D models with haptic displacement maps"};
  app.require_subcommand(1);
  hdm::app::add_bake_command(app);
  hdm::app::add_sculpt_command(app);
  hdm::app::add_info_command(app);
  hdm::app::add_export_command(app);
  hdm::app::add_render_command(app);
  hdm::app::add_check_command(app);
  hdm::app::add_feel_command(app);
  hdm::app::add_bench_command(app);
  hdm::app::add_subdivide_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hdm: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
