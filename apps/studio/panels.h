// SPDX-License-Identifier: MIT
#pragma once
// The studio's Dear ImGui panels: tools (brush settings, undo, redo, save, export, screenshot)
// and the status overlay.
#include "studio.h"

#include <cstdint>
#include <string>

namespace hdm::studio {

/// What the user asked for in the tools panel this frame.
struct PanelActions {
  bool undo = false, redo = false, save = false, export_model = false, screenshot = false, fit = false;
};

/// File names edited in the panel.
struct PanelFiles {
  char save[512] = "studio.hdm";
  char export_path[512] = "studio.glb";
  char screenshot[512] = "studio.png";
};

/// The figures of the status overlay.
struct StatusFigures {
  double servo_rate_hz = 0, target_rate_hz = 0;  ///< achieved over the last second, and asked [Hz]
  double tick_p99_us = 0;                        ///< tick work, 99th percentile over the last second [µs]
  int64_t late_ticks = 0;                        ///< ticks started a period or more late, since the start
  double frame_ms_median = 0, frame_ms_p99 = 0;  ///< frame interval over the last 120 frames [ms]
  int uploaded = 0;                              ///< slabs uploaded for the last frame
  int64_t uploaded_total = 0;                    ///< since the start
  double edits_per_s = 0;                        ///< edit sweeps per second
  uint64_t epoch = 0;                            ///< snapshot epoch drawn
  bool contact = false;                          ///< the proxy is on the surface
  double force_n = 0;                            ///< force rendered [N] (not sent to a mouse)
  int slabs = 0;                                 ///< slabs of the model
  int level = 0, grid = 0;                       ///< level of detail drawn and its grid intervals per slab edge
  const char* bridge = nullptr;                  ///< the bridge's endpoint when the device comes through it
  int64_t bridge_accepted = 0, bridge_dropped = 0, bridge_watchdog_trips = 0;  ///< BridgeCounters
};

/// @brief Draws the tools panel; @p message is shown under it (the last save or error).
PanelActions draw_tools_panel(ToolSettings& tool, PanelFiles& files, const std::string& message);
/// @brief Draws the status overlay in the top-right corner of a @p width pixel wide window.
void draw_status_overlay(const StatusFigures& s, float width);

}  // namespace hdm::studio
