// SPDX-License-Identifier: MIT
#pragma once
// A one-line progress bar on stderr for long CLI work (only when stderr is a terminal or forced).

#include <cstdio>
#include <string>
#include <unistd.h>

namespace hdm::app {

class ProgressBar {
 public:
  explicit ProgressBar(bool enabled = isatty(2) != 0) : enabled_(enabled) {}
  ~ProgressBar() { finish(); }
  void operator()(const char* stage, double fraction) {
    if (!enabled_) return;
    const int width = 30, filled = static_cast<int>(fraction * width + 0.5);
    std::fprintf(stderr, "\r%-12s [%s%s] %3d%%", stage, std::string(filled, '#').c_str(),
                 std::string(width - filled, ' ').c_str(), static_cast<int>(fraction * 100 + 0.5));
    std::fflush(stderr);
    open_ = true;
  }
  void finish() {
    if (open_) std::fprintf(stderr, "\n");
    open_ = false;
  }

 private:
  bool enabled_;
  bool open_ = false;
};

}  // namespace hdm::app
