// SPDX-License-Identifier: MIT
// hdm studio ARGS...: starts hdm-studio (the interactive window, its own executable so that the
// command-line program needs no window system) from the same directory, with the same arguments.
#include "commands.h"

#include <hdm/core/error.h>

#include <CLI/CLI.hpp>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <unistd.h>

namespace hdm::app {

void add_studio_command(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand(
      "studio",
      "Sculpt and paint a model in a window with the mouse (runs hdm-studio; `hdm studio --help` for its options)");
  cmd->prefix_command();  // every argument goes to hdm-studio, --help included
  cmd->set_help_flag();
  cmd->callback([cmd] {
    std::error_code ec;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
    const std::string studio = ((ec ? std::filesystem::path(".") : self.parent_path()) / "hdm-studio").string();
    std::vector<std::string> args = cmd->remaining();
    std::vector<char*> argv;
    argv.push_back(const_cast<char*>(studio.c_str()));
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(studio.c_str(), argv.data());
    throw IoError(studio + ": cannot start the studio (" + std::strerror(errno) +
                  "); it is built with the hdm program unless -DHDM_BUILD_STUDIO=OFF");
  });
}

}  // namespace hdm::app
