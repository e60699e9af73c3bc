// SPDX-License-Identifier: MIT
#include <hdm/core/error.h>
#include <hdm/atlas/texture_atlas.h>
#include <hdm/render/camera.h>
#include <hdm/render/egl_context.h>
#include <hdm/render/framebuffer.h>
#include <hdm/render/render_png.h>
#include <hdm/render/slab_renderer.h>
#include <hdm/slab/slab_model.h>

#include "png_write.h"

#include <string>

namespace hdm {

void render_png(const SlabModel& model, const std::string& path, const RenderOptions& opt) {
  if (opt.width < 1 || opt.height < 1)
    throw InvalidInput("render: image size " + std::to_string(opt.width) + "x" + std::to_string(opt.height) +
                       " must be positive");
  if (!opt.background.allFinite()) throw InvalidInput("render: the background colour is not finite");
  if (path.empty()) throw InvalidInput("render: empty output path");
  // Camera first: it validates the view without touching EGL.
  RenderCamera camera = fit_camera(model, opt.width, opt.height, opt.azimuth_deg, opt.elevation_deg);
  if (opt.zoom != 1 || opt.focus != Vec3::Constant(0.5)) {
    const Aabb box = surface_box(model);
    camera = zoom_camera(camera, box.min + opt.focus.cwiseProduct(box.max - box.min), opt.zoom);
  }

  std::vector<uint8_t> rgb;
  {
    EglContext context;
    // Declared after the context, so they are destroyed while it is still current.
    Framebuffer target(opt.width, opt.height, opt.msaa_samples);
    SlabRenderer renderer;
    renderer.upload_all(model);
    // The framebuffer holds display values, so the clear colour is encoded like the shader output.
    const float clear[3] = {linear_to_srgb8(opt.background.x()) / 255.0f, linear_to_srgb8(opt.background.y()) / 255.0f,
                            linear_to_srgb8(opt.background.z()) / 255.0f};
    target.begin(clear);
    renderer.draw(camera, opt.show_slab_edges);
    rgb = target.read_rgb();
  }
  render_detail::write_png_rgb(path, opt.width, opt.height, rgb);
}

}  // namespace hdm
