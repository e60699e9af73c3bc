// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// One-call headless rendering of a slab model to a PNG image (paper §6).

#include <hdm/core/types.h>

#include <string>

namespace hdm {

struct SlabModel;

/// What render_png() draws and how.
struct RenderOptions {
  int width = 1280;  ///< image width [pixels], 1 .. GL_MAX_RENDERBUFFER_SIZE
  int height = 960;  ///< image height [pixels], 1 .. GL_MAX_RENDERBUFFER_SIZE
  /// View direction [degrees]: the camera looks at the centre of the displaced surface's
  /// bounding box from azimuth (about +Y; 0 = from +Z, 90 = from +X) and elevation (above the
  /// XZ plane, in [−90, 90]), Y up, and is placed so the whole surface fits (fit_camera()).
  double azimuth_deg = 0;
  double elevation_deg = 15;  ///< see azimuth_deg
  /// Background colour, linear RGB in [0,1] like SlabModel::colour; written sRGB-encoded, so a
  /// background pixel is linear_to_srgb8() of each channel.
  Vec3f background{1, 1, 1};
  bool show_slab_edges = false;  ///< overlay the coarse slab boundaries as dark lines
  /// Close-up: the camera looks at this point, in coordinates normalised to the surface's bounding
  /// box ([0,1]³; the centre is (0.5, 0.5, 0.5)), from `zoom` times closer (zoom_camera()).
  Vec3 focus = Vec3::Constant(0.5);
  double zoom = 1;       ///< > 0; 1: the whole surface fits
  int msaa_samples = 4;  ///< multisample anti-aliasing (1 = off; clamped to GL_MAX_SAMPLES)
};

/// @brief Renders the displaced surface of @p model with its colours and writes it as an 8-bit
/// RGB PNG to @p path.
///
/// Creates a headless OpenGL 4.5 context (EglContext), draws with SlabRenderer into an
/// off-screen Framebuffer from the camera fit_camera() gives, reads the pixels back and writes
/// the PNG atomically (temporary file renamed into place).
/// @param model  slab model; rebuild_derived() has run.
/// @param path   output `.png` file; an existing file is replaced only on success.
/// @param opt    image size, view, background and overlay.
/// @throws InvalidInput on bad options or a model without (current) derived data;
///         RenderError when EGL/OpenGL is unavailable ("no EGL display: install libegl1 and
///         libgl1-mesa-dri", ...) or fails; IoError "<path>: <reason>" when the PNG cannot be
///         written.
/// @note Creates and destroys its own context on the calling thread; any context current on
///       that thread before the call is not current afterwards. About 0.28 s for 72k triangles
///       at 1280×960 on llvmpipe (2 cores): ~0.17 s draw + read-back with 4x MSAA (~0.06 s
///       without), ~0.07 s PNG encoding, ~0.05 s context and upload. Prints nothing.
/// @see paper §6
void render_png(const SlabModel& model, const std::string& path, const RenderOptions& opt = {});

}  // namespace hdm
