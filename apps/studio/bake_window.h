// SPDX-License-Identifier: MIT
#pragma once
// `hdm studio MESH`: a mesh that is not a slab model yet is baked first, on a worker thread, as
// `hdm bake MESH` bakes it (repair, orientation, the error-bounded bake against the input), while
// the window shows the stage and its progress.
#include <hdm/slab/slab_model.h>

#include <string>
#include <vector>

struct GLFWwindow;

namespace hdm::studio {

/// What the bake in the window did (for the session's report).
struct WindowBake {
  std::string input;                ///< the mesh baked
  double seconds = 0;               ///< wall time of the bake, reading and repair included [s]
  long frames = 0;                  ///< frames drawn with the progress bar while it ran
  std::vector<std::string> stages;  ///< the bake's stages, in the order the progress bar showed them
  int slabs = 0, grid = 0;          ///< the model's slab count and grid intervals per edge
  /// Fidelity of the model against the input [% of the input's bounding-box diagonal], measured
  /// with Embree on the input (Fidelity::max_pct, max_back_pct, rms_pct, rms_back_pct).
  double max_pct = 0, max_back_pct = 0, rms_pct = 0, rms_back_pct = 0;
  bool met = false;     ///< the fidelity bound of `hdm bake` (0.2 % max, 0.02 % RMS, both ways) holds
  bool closed = false;  ///< the window was closed while baking (the studio then exits)
};

/// @brief Bakes @p mesh_path on a worker thread with `hdm bake`'s defaults while drawing its
/// progress in @p window (Dear ImGui, initialised on it) every frame.
/// @throws what `hdm bake` throws for the mesh (IoError, InvalidInput naming the file).
SlabModel bake_in_window(GLFWwindow* window, const std::string& mesh_path, WindowBake& report);

/// True when @p path names a slab model (.hdm) rather than a mesh to bake.
bool is_slab_model_path(const std::string& path);

}  // namespace hdm::studio
