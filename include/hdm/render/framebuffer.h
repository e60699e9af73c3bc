// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// An off-screen render target: multisampled colour + depth renderbuffers, resolved into a
/// single-sample framebuffer for read-back.

#include <cstdint>
#include <vector>

namespace hdm {

/// Off-screen framebuffer of a fixed size with optional MSAA.
///
/// Colour is RGBA8 holding display-ready (sRGB-encoded) values, as SlabRenderer writes them.
/// @note Needs a current OpenGL 4.5 context on the calling thread for its whole life (construct,
///       use and destroy with the same context current). Not copyable or movable.
class Framebuffer {
 public:
  /// @brief Allocates the target.
  /// @param width,height size [pixels], 1 .. GL_MAX_RENDERBUFFER_SIZE.
  /// @param samples      requested MSAA samples (1 = none); clamped to GL_MAX_SAMPLES.
  /// @throws InvalidInput if the size is out of range; RenderError if the framebuffer is
  ///         incomplete.
  Framebuffer(int width, int height, int samples = 4);
  /// Deletes the GL objects.
  ~Framebuffer();
  Framebuffer(const Framebuffer&) = delete;
  Framebuffer& operator=(const Framebuffer&) = delete;

  /// @brief Binds the (multisampled) draw target, sets the viewport and clears colour to
  /// @p rgb (already display-encoded values in [0,1]) and depth to 1.
  void begin(const float rgb[3]);

  /// @brief Resolves MSAA and reads the image back as tightly packed 8-bit RGB, top row first
  /// (PNG order).
  /// @return width·height·3 bytes.
  /// @throws RenderError if OpenGL reports an error.
  std::vector<uint8_t> read_rgb();

  int width() const noexcept { return width_; }      ///< [pixels]
  int height() const noexcept { return height_; }    ///< [pixels]
  int samples() const noexcept { return samples_; }  ///< MSAA samples actually used

 private:
  void release() noexcept;
  int width_, height_, samples_;
  unsigned draw_fbo_ = 0, resolve_fbo_ = 0;
  unsigned colour_rb_ = 0, depth_rb_ = 0, resolve_rb_ = 0;
};

}  // namespace hdm
