// SPDX-License-Identifier: MIT
#pragma once
// The tool drawn over the model: the tool sphere at the device position, the proxy on the
// surface and the force as an arrow. Drawn as projected polylines into a Dear ImGui draw list, so
// they stay out of the model's pixels (and screenshots); the brush's footprint is drawn on the
// surface itself by the slab renderer (SlabRenderer::set_footprint).
#include "servo_thread.h"

#include <hdm/haptics/tool_shell.h>
#include <hdm/render/camera.h>

struct ImDrawList;

namespace hdm::studio {

/// How the glyphs are sized.
struct GlyphOptions {
  double brush_radius = 1;   ///< tool sphere radius [model units]
  double newton_length = 1;  ///< arrow length per newton of force [model units / N]
  /// A rigid tool's point shell (ToolState::rigid): drawn at the god-object's pose. Not owned.
  const ToolShell* shell = nullptr;
};

/// @brief Adds the tool sphere, proxy and force arrow of @p tool to @p list, seen by
/// @p camera (points behind the camera are left out); a rigid tool as its point shell.
void draw_tool_glyphs(ImDrawList* list, const RenderCamera& camera, const ToolState& tool, const GlyphOptions& o);

}  // namespace hdm::studio
