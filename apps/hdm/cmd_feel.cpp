// SPDX-License-Identifier: MIT
// Being written: registers nothing yet.
#include "commands.h"
namespace hdm::app {
void add_feel_command(CLI::App&) {}
}  // namespace hdm::app
