// SPDX-License-Identifier: MIT
// hdm-studio MODEL.hdm: sculpt and paint a slab model in a window, with the mouse as a 3-DOF
// haptic device and the servo loop on its own thread; or run a scripted session and exit.
#include "bake_window.h"
#include "output_guard.h"
#include "studio.h"

#include <hdm/core/error.h>
#include <hdm/io/hdm_file.h>

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <filesystem>

int main(int argc, char** argv) {
  CLI::App app{"hdm studio: sculpt and paint a slab model interactively (GLFW window, OpenGL 4.5 core)"};
  hdm::studio::StudioOptions o;
  std::string model, size = "1280x720";
  app.add_option("model", model,
                 "slab model (.hdm), or a mesh (OBJ, PLY, OFF, STL, ...) baked first as `hdm bake` does, with its "
                 "progress in the window")
      ->required();
  app.add_option("--size", size, "window size WxH [pixels]");
  app.add_option("--rate", o.rate_hz, "servo rate [Hz]: 1000 (default) or 10000")
      ->check(CLI::IsMember({1000.0, 10000.0}));
  app.add_option("--stiffness", o.stiffness, "proxy stiffness as felt at the device [N/m]")
      ->check(CLI::Range(1.0, 1e5));
  app.add_option("--friction", o.friction_scale, "factor on the model's friction coefficients")
      ->check(CLI::Range(0.0, 10.0));
  app.add_flag("--ball", o.ball,
               "feel the brush as a ball of its radius held outside the surface (a sphere proxy) instead of a point");
  app.add_flag("--burr", o.burr,
               "feel the tool as a rigid dental burr (a sphere head on a shaft) with torque, a 6-DOF god-object; "
               "the mouse turns it with Alt held")
      ->excludes("--ball");
  app.add_option("--script", o.script, "scripted session (JSON, docs/studio.md): device and UI actions, then exit");
  app.add_option("--replay", o.replay,
                 "play this recorded trajectory (hdm sculpt --forces CSV) as the device instead of the mouse");
  app.add_option("--device", o.device,
                 "take the device from the bridge (docs/bridge.md): udp:PORT (127.0.0.1) or shm:NAME, fed by a driver "
                 "process such as examples/python/bridge_client.py")
      ->excludes("--replay");
  app.add_option("--secret-file", o.secret_file,
                 "with --device: the bridge's shared secret, created with mode 0600 when missing (default: the "
                 "HDM_BRIDGE_SECRET environment variable)");
  app.add_option("--watchdog-ms", o.watchdog_ms,
                 "with --device: release the tool and ramp the force out after this silence of the driver [ms] "
                 "(default 5; a replay driver that waits for each answer, --lockstep, may pause longer)")
      ->check(CLI::Range(0.1, 60000.0));
  app.add_option("--ticks-per-frame", o.ticks_per_frame,
                 "with --script: run exactly this many servo ticks per frame, in lockstep with the frames, so that the "
                 "script's run is the same every time (default: the servo runs in real time beside the frames)")
      ->check(CLI::Range(1, 100000));
  app.add_option("--frames", o.frames, "stop after this many frames")->check(CLI::Range(1L, 100000000L));
  app.add_option("--screenshot", o.screenshot, "write the model view of the last frame here (PNG)");
  app.add_option("--report", o.report, "write the session's figures here (JSON): frame times, uploads, servo timing");
  app.add_flag("--verify-uploads", o.verify_uploads,
               "compare every slab's data each frame and count the slabs that really changed (tests; costs a copy of "
               "the model)");
  app.add_flag("!--no-vsync", o.vsync, "draw frames as fast as possible in an interactive session");
  std::string lod = "auto";
  app.add_option("--lod", lod,
                 "level of detail: auto (from the frame time) or 0 (every grid triangle), 1, 2, ... "
                 "(the grid of every 2^k-th point)");
  app.add_option("--frame-budget-ms", o.frame_budget_ms, "frame time the automatic level of detail aims under [ms]")
      ->check(CLI::Range(1.0, 10000.0));
  try {
    app.parse(argc, argv);
    hdm::app::check_outputs({o.screenshot, o.report}, {model, o.replay, o.script}, "--screenshot/--report");
    int w = 0, h = 0;
    char x = 0;
    if (std::sscanf(size.c_str(), "%d%c%d", &w, &x, &h) != 3 || (x != 'x' && x != 'X') || w < 1 || h < 1)
      throw CLI::ValidationError("--size", size + ": expected WxH, e.g. 1280x720");  // usage: exit 2
    o.width = w, o.height = h;
    o.model_name = std::filesystem::path(model).filename().string();
    if (lod != "auto") {
      if (lod.empty() || lod.find_first_not_of("0123456789") != std::string::npos || lod.size() > 2)
        throw CLI::ValidationError("--lod", lod + ": expected auto or a level 0, 1, 2, ...");
      o.lod = std::stoi(lod);
    }
    if (!hdm::studio::is_slab_model_path(model)) return hdm::studio::run_studio_baking(model, o);
    hdm::SlabModel m = hdm::load_model(model);
    return hdm::studio::run_studio(std::move(m), o);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;  // usage, whatever CLI11's own code
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hdm-studio: error: %s\n", e.what());
    return 1;
  }
}
