// SPDX-License-Identifier: MIT
// hdm render MODEL.hdm -o VIEW.png [--size WxH] [--view AZ,EL] [--edges]: headless PNG of a model.
#include "commands.h"
#include "output_guard.h"

#include <hdm/core/error.h>
#include <hdm/io/hdm_file.h>
#include <hdm/query/slab_query.h>
#include <hdm/render/render_png.h>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <type_traits>

namespace hdm::app {
namespace {

struct RenderArgs {
  std::string model, output, size = "1280x960", view = "0,15", focus = "0.5,0.5,0.5";
  double zoom = 1;
  std::string surface = "displaced", colour_by = "paint";
  bool edges = false;
  InputLimit limit;
};

// Colour map for displacement magnitude: blue (δ = 0, inner face) through white to red (δ = 1,
// outer face), as the paper's Fig. 2 marks the largest displacement in red.
Vec3f displacement_colour(double d) {
  d = std::clamp(d, 0.0, 1.0);
  const Vec3f blue(0.05f, 0.2f, 0.9f), white(0.9f, 0.9f, 0.9f), red(0.9f, 0.05f, 0.05f);
  return d < 0.5 ? Vec3f(blue + float(2 * d) * (white - blue)) : Vec3f(white + float(2 * d - 1) * (red - white));
}

// Shows the shell instead of the surface, or colours texels by the displacement under them.
void restyle(SlabModel& m, const RenderArgs& a) {
  if (a.colour_by == "displacement") {
    const SampleLayout& T = m.texels;
    for (int t = 0; t < T.count; ++t) {
      const int local = T.home(t).index;
      SlabCoordinates c;
      c.bary = Vec3(1 - double(T.point_i[local] + T.point_j[local]) / T.n, double(T.point_j[local]) / T.n,
                    double(T.point_i[local]) / T.n);
      Contact at;
      evaluate_surface(m, T.home(t).slab, c, at);
      m.colour.set(t, encode_srgb8(displacement_colour(at.delta)));
    }
  }
  if (a.surface != "displaced") {
    std::fill(m.displacement.begin(), m.displacement.end(), a.surface == "outer" ? 1.0f : 0.0f);
    rebuild_derived(m);
  }
}

// Parses "A<sep>B" into two numbers with nothing left over; false on any junk.
template <class T>
bool parse_pair(const std::string& text, char sep, T& a, T& b) {
  const size_t at = text.find(sep);
  if (at == std::string::npos) return false;
  try {
    size_t used_a = 0, used_b = 0;
    const std::string first = text.substr(0, at), second = text.substr(at + 1);
    if constexpr (std::is_same_v<T, int>) {
      a = std::stoi(first, &used_a);
      b = std::stoi(second, &used_b);
    } else {
      a = std::stod(first, &used_a);
      b = std::stod(second, &used_b);
    }
    return !first.empty() && !second.empty() && used_a == first.size() && used_b == second.size();
  } catch (const std::exception&) {
    return false;
  }
}

std::string check_size(const std::string& text) {
  int w = 0, h = 0;
  if (!parse_pair(text, 'x', w, h)) return "expected WIDTHxHEIGHT in pixels, for example 1280x960, got '" + text + "'";
  if (w < 1 || h < 1 || w > 16384 || h > 16384) return "width and height must be in 1..16384, got '" + text + "'";
  return {};
}

std::string check_view(const std::string& text) {
  double az = 0, el = 0;
  if (!parse_pair(text, ',', az, el))
    return "expected AZIMUTH,ELEVATION in degrees, for example 30,15, got '" + text + "'";
  if (!std::isfinite(az) || !std::isfinite(el) || std::abs(el) > 90)
    return "azimuth must be finite and elevation in [-90, 90] degrees, got '" + text + "'";
  return {};
}

void run_render(const RenderArgs& a) {
  check_outputs({a.output}, {a.model});
  RenderOptions o;
  parse_pair(a.size, 'x', o.width, o.height);  // validated by check_size
  parse_pair(a.view, ',', o.azimuth_deg, o.elevation_deg);
  o.show_slab_edges = a.edges;
  o.zoom = a.zoom;
  if (std::sscanf(a.focus.c_str(), "%lf,%lf,%lf", &o.focus.x(), &o.focus.y(), &o.focus.z()) != 3 ||
      !o.focus.allFinite())
    throw InvalidInput("--focus: expected X,Y,Z in normalised box coordinates, for example 0.6,0.45,1, got '" +
                       a.focus + "'");
  SlabModel model = load_model(a.model, {a.limit.bytes()});
  restyle(model, a);
  render_png(model, a.output, o);
  std::printf("%s\n", a.output.c_str());
}

}  // namespace

void add_render_command(CLI::App& app) {
  auto args = std::make_shared<RenderArgs>();
  CLI::App* sub = app.add_subcommand("render", "Render a .hdm model to a PNG image (headless OpenGL via EGL)");
  sub->add_option("model", args->model, "model file (.hdm)")->required()->check(CLI::ExistingFile);
  sub->add_option("-o,--output", args->output, "output image (.png)")->required();
  sub->add_option("--size", args->size, "image size WIDTHxHEIGHT [pixels]")
      ->capture_default_str()
      ->check(CLI::Validator(check_size, "WxH", "size"));
  sub->add_option("--view", args->view,
                  "view direction AZIMUTH,ELEVATION [degrees]: azimuth about +Y (0 = from +Z), elevation above "
                  "the XZ plane in [-90, 90]")
      ->capture_default_str()
      ->check(CLI::Validator(check_view, "AZ,EL", "view"));
  sub->add_flag("--edges", args->edges, "draw the coarse slab boundaries");
  sub->add_option("--zoom", args->zoom, "close-up: move the camera this many times closer (1: the whole model)")
      ->check(CLI::Range(0.01, 1000.0));
  sub->add_option("--focus", args->focus,
                  "close-up: the point looked at, in the model's bounding box normalised to [0,1] (X,Y,Z)")
      ->capture_default_str();
  sub->add_option("--surface", args->surface, "what to draw: the displaced surface, or the inner or outer shell")
      ->capture_default_str()
      ->check(CLI::IsMember({"displaced", "inner", "outer"}));
  sub->add_option("--colour-by", args->colour_by,
                  "paint: the model's colours; displacement: δ from blue (0) to red (1)")
      ->capture_default_str()
      ->check(CLI::IsMember({"paint", "displacement"}));
  add_input_limit(sub, args->limit);
  sub->callback([args] { run_render(*args); });
}

}  // namespace hdm::app
