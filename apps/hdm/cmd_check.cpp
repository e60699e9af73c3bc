// SPDX-License-Identifier: MIT
// Being written: registers nothing yet.
#include "commands.h"
namespace hdm::app {
void add_check_command(CLI::App&) {}
}  // namespace hdm::app
