// SPDX-License-Identifier: MIT
#pragma once
// The studio's session report (--report): what the render thread measured frame by frame, the
// servo loop's and the session's figures, the probes a script took and the bake in the window.

#include "bake_window.h"
#include "mouse_device.h"
#include "studio.h"

#include <hdm/haptics/servo_loop.h>
#include <hdm/session/sculpt_session.h>

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace hdm::studio {

/// Figures the render thread gathers while the studio runs.
struct StudioFigures {
  std::vector<double> frame_ms;                      ///< time from one frame's start to the next's [ms]
  std::vector<int> uploads;                          ///< slabs uploaded for each frame
  std::vector<int> levels;                           ///< level of detail drawn in each frame
  int64_t dirty_total = 0;                           ///< --verify-uploads: slabs flagged dirty in all
  int64_t mismatched_total = 0;                      ///< --verify-uploads: uploads that differed from the snapshot
  long frames = 0;                                   ///< frames drawn
  std::vector<std::string> screenshot_files;         ///< pictures written, in order
  nlohmann::json probes = nlohmann::json::object();  ///< the script's probes by name
  double max_frame_step_m = 0;                       ///< the mouse handle's largest move from one frame to the next [m]
};

/// What the report reads besides the servo's and the session's figures.
struct StudioReportContext {
  const StudioOptions& options;        ///< the session's options (report path, size, rate, level of detail)
  const StudioFigures& figures;        ///< the render thread's figures
  int slabs = 0;                       ///< slabs of the model
  int level_count = 1;                 ///< levels of detail the renderer has
  const Workspace& workspace;          ///< device metres to model units
  std::string realtime;                ///< how the servo thread was scheduled
  const MouseDevice* mouse = nullptr;  ///< the device when it is the mouse
  const WindowBake* bake = nullptr;    ///< the bake in the window, if the studio baked its model
};

/// @brief Writes the report as JSON to options.report (write_file_atomic).
/// @param st  the servo loop's figures, after it stopped.
/// @param ss  the session's figures, read after the servo stopped.
/// @throws IoError naming the path when it cannot be written.
void write_studio_report(const StudioReportContext& c, const ServoStats& st, const SessionStats& ss);

}  // namespace hdm::studio
