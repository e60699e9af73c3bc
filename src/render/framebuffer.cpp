// SPDX-License-Identifier: MIT
#include <hdm/core/error.h>
#include <hdm/render/framebuffer.h>

#include "gl.h"

#include <algorithm>
#include <cstring>
#include <string>

namespace hdm {
namespace {

GLuint make_renderbuffer(GLenum format, int samples, int width, int height) {
  GLuint rb = 0;
  glCreateRenderbuffers(1, &rb);
  if (samples > 1)
    glNamedRenderbufferStorageMultisample(rb, samples, format, width, height);
  else
    glNamedRenderbufferStorage(rb, format, width, height);
  return rb;
}

void check_complete(GLuint fbo, const char* which) {
  const GLenum status = glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    throw RenderError(std::string(which) + " framebuffer is incomplete (status 0x" + std::to_string(status) + ")");
}

}  // namespace

Framebuffer::Framebuffer(int width, int height, int samples) : width_(width), height_(height) {
  GLint max_size = 0, max_samples = 1;
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size);
  glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
  if (width < 1 || height < 1 || width > max_size || height > max_size)
    throw InvalidInput("image size " + std::to_string(width) + "x" + std::to_string(height) + " is outside 1.." +
                       std::to_string(max_size) + " pixels per side");
  samples_ = std::clamp(samples, 1, std::max(1, static_cast<int>(max_samples)));

  // Multisampled draw target; with MSAA off it doubles as the read-back target.
  colour_rb_ = make_renderbuffer(GL_RGBA8, samples_, width, height);
  depth_rb_ = make_renderbuffer(GL_DEPTH_COMPONENT24, samples_, width, height);
  glCreateFramebuffers(1, &draw_fbo_);
  glNamedFramebufferRenderbuffer(draw_fbo_, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour_rb_);
  glNamedFramebufferRenderbuffer(draw_fbo_, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_rb_);
  if (samples_ > 1) {
    resolve_rb_ = make_renderbuffer(GL_RGBA8, 1, width, height);
    glCreateFramebuffers(1, &resolve_fbo_);
    glNamedFramebufferRenderbuffer(resolve_fbo_, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, resolve_rb_);
  }
  try {
    render_detail::check_gl("allocating the off-screen framebuffer");
    check_complete(draw_fbo_, "draw");
    if (resolve_fbo_) check_complete(resolve_fbo_, "resolve");
  } catch (...) {
    release();
    throw;
  }
}

Framebuffer::~Framebuffer() { release(); }

void Framebuffer::release() noexcept {
  const GLuint fbos[] = {draw_fbo_, resolve_fbo_};
  const GLuint rbs[] = {colour_rb_, depth_rb_, resolve_rb_};
  glDeleteFramebuffers(2, fbos);  // zero names are ignored
  glDeleteRenderbuffers(3, rbs);
  draw_fbo_ = resolve_fbo_ = colour_rb_ = depth_rb_ = resolve_rb_ = 0;
}

void Framebuffer::begin(const float rgb[3]) {
  glBindFramebuffer(GL_FRAMEBUFFER, draw_fbo_);
  glViewport(0, 0, width_, height_);
  const GLfloat colour[4] = {rgb[0], rgb[1], rgb[2], 1.0f};
  const GLfloat depth = 1.0f;
  glClearNamedFramebufferfv(draw_fbo_, GL_COLOR, 0, colour);
  glClearNamedFramebufferfv(draw_fbo_, GL_DEPTH, 0, &depth);
}

std::vector<uint8_t> Framebuffer::read_rgb() {
  GLuint source = draw_fbo_;
  if (resolve_fbo_) {
    glBlitNamedFramebuffer(draw_fbo_, resolve_fbo_, 0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT,
                           GL_NEAREST);
    source = resolve_fbo_;
  }
  const size_t row = static_cast<size_t>(width_) * 3;
  std::vector<uint8_t> bottom_up(row * height_), image(row * height_);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, source);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width_, height_, GL_RGB, GL_UNSIGNED_BYTE, bottom_up.data());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  render_detail::check_gl("reading the rendered image back");
  // OpenGL's first row is the bottom one; PNG's is the top one.
  for (int y = 0; y < height_; ++y) std::memcpy(&image[row * y], &bottom_up[row * (height_ - 1 - y)], row);
  return image;
}

}  // namespace hdm
