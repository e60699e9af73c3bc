// SPDX-License-Identifier: MIT
// Render tests: properties of the image (coverage, background, colours, locality of slab
// re-uploads), never golden images. Every test draws with the real headless EGL/llvmpipe path.
#include <hdm/core/error.h>
#include <hdm/atlas/texture_atlas.h>
#include <hdm/render/camera.h>
#include <hdm/render/egl_context.h>
#include <hdm/render/framebuffer.h>
#include <hdm/render/render_png.h>
#include <hdm/render/slab_renderer.h>
#include <hdm/slab/slab_model.h>
#include <hdm/slab/slab_snapshots.h>

#include <gtest/gtest.h>

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#endif
#include <stb/stb_image.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>
#include <string>
#include <unistd.h>
#include <vector>

namespace hdm {
namespace {

namespace fs = std::filesystem;
constexpr double kDeg = std::numbers::pi / 180;

// ---- test models -----------------------------------------------------------------------------

struct CoarseMesh {
  std::vector<Vec3> vertices;  // on the unit sphere
  std::vector<Tri> faces;      // CCW from outside
};

CoarseMesh icosahedron() {
  const double p = (1 + std::sqrt(5.0)) / 2;
  CoarseMesh m;
  m.vertices = {{-1, p, 0},  {1, p, 0},  {-1, -p, 0}, {1, -p, 0}, {0, -1, p},  {0, 1, p},
                {0, -1, -p}, {0, 1, -p}, {p, 0, -1},  {p, 0, 1},  {-p, 0, -1}, {-p, 0, 1}};
  for (Vec3& v : m.vertices) v.normalize();
  m.faces = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
             {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
             {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  return m;
}

// One 4-to-1 split with the new vertices pushed onto the unit sphere.
CoarseMesh subdivide(const CoarseMesh& in) {
  CoarseMesh out{in.vertices, {}};
  std::map<std::pair<int, int>, int> midpoint;
  auto mid = [&](int a, int b) {
    auto [it, fresh] = midpoint.try_emplace({std::min(a, b), std::max(a, b)}, 0);
    if (fresh) {
      it->second = static_cast<int>(out.vertices.size());
      out.vertices.push_back((in.vertices[a] + in.vertices[b]).normalized());
    }
    return it->second;
  };
  for (const Tri& f : in.faces) {
    const int ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
    out.faces.push_back({f[0], ab, ca});
    out.faces.push_back({ab, f[1], bc});
    out.faces.push_back({ca, bc, f[2]});
    out.faces.push_back({ab, bc, ca});
  }
  return out;
}

// The brief's test model: inner 0.8·v, outer 1.2·v, displacement 0.5 (so the surface is the coarse
// mesh itself), white everywhere.
SlabModel make_model(const CoarseMesh& mesh, int n, int m) {
  SlabModel model;
  model.grid_n = n;
  model.texel_density = m;
  for (const Vec3& v : mesh.vertices) {
    model.inner.push_back(0.8 * v);
    model.outer.push_back(1.2 * v);
  }
  model.slabs = mesh.faces;
  const size_t C = mesh.vertices.size(), S = mesh.faces.size(), E = 3 * S / 2;  // closed mesh
  const int N = n * m;
  const size_t samples = C + (n - 1) * E + (n - 1) * (n - 2) / 2 * S;
  const size_t texels = C + (N - 1) * E + (N - 1) * (N - 2) / 2 * S;
  model.displacement.assign(samples, 0.5f);
  model.colour.assign(texels, Srgb8{255, 255, 255});
  rebuild_derived(model);
  return model;
}

void paint_slab(SlabModel& model, int slab, const Vec3f& colour) {
  const SampleLayout& L = model.texels;
  for (int k = 0; k < L.per_slab; ++k) model.colour.set(L.id(slab, k), encode_srgb8(colour));
}

Vec3 towards_eye(double az_deg, double el_deg) {
  const double az = az_deg * kDeg, el = el_deg * kDeg;
  return {std::sin(az) * std::cos(el), std::sin(el), std::cos(az) * std::cos(el)};
}

// The slab whose outward face normal points most nearly at the camera.
int facing_slab(const SlabModel& model, const Vec3& to_eye) {
  int best = 0;
  double best_dot = -2;
  for (int s = 0; s < model.slab_count(); ++s) {
    const Tri& t = model.slabs[s];
    const Vec3 c = (model.inner[t[0]] + model.inner[t[1]] + model.inner[t[2]]).normalized();
    if (c.dot(to_eye) > best_dot) best_dot = c.dot(to_eye), best = s;
  }
  return best;
}

// Surface corners of a slab (displacement 0.5 everywhere: the coarse vertex itself).
std::array<Vec3, 3> surface_corners(const SlabModel& model, int slab) {
  std::array<Vec3, 3> c;
  for (int k = 0; k < 3; ++k) c[k] = sample_position(model, model.slabs[slab][k]);
  return c;
}

// ---- images ----------------------------------------------------------------------------------

struct Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;  // top row first
  const uint8_t* at(int x, int y) const { return &rgb[(static_cast<size_t>(y) * width + x) * 3]; }
};

Image read_png(const std::string& path) {
  Image im;
  int channels = 0;
  uint8_t* data = stbi_load(path.c_str(), &im.width, &im.height, &channels, 3);
  if (!data) throw IoError(path + ": cannot read back the PNG");
  im.rgb.assign(data, data + static_cast<size_t>(im.width) * im.height * 3);
  stbi_image_free(data);
  return im;
}

std::string temp_png(const std::string& name) {
  return (fs::temp_directory_path() / ("hdm_render_test_" + std::to_string(::getpid()) + "_" + name + ".png")).string();
}

// Distance from pixel centre q to triangle abc in the image plane [pixels] (0 inside).
double distance_to_triangle(const Eigen::Vector2d& q, const std::array<Eigen::Vector2d, 3>& t) {
  auto cross = [](const Eigen::Vector2d& u, const Eigen::Vector2d& v) { return u.x() * v.y() - u.y() * v.x(); };
  const double area = cross(t[1] - t[0], t[2] - t[0]);
  bool inside = true;
  double d = 1e300;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector2d a = t[k], b = t[(k + 1) % 3];
    if (cross(b - a, q - a) * area < 0) inside = false;
    const double s = std::clamp((q - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    d = std::min(d, (a + s * (b - a) - q).norm());
  }
  return inside ? 0.0 : d;
}

// Draws with an explicit context, for the tests that re-upload slabs between frames.
struct Scene {
  EglContext context;
  Framebuffer target;
  SlabRenderer renderer;
  RenderCamera camera;
  Scene(const SlabModel& model, int w, int h, double az, double el)
      : target(w, h, 4), camera(fit_camera(model, w, h, az, el)) {
    renderer.upload_all(model);
  }
  Image frame(bool edges = false, int level = 0) {
    const float white[3] = {1, 1, 1};
    target.begin(white);
    renderer.draw(camera, edges, level);
    return Image{target.width(), target.height(), target.read_rgb()};
  }
};

// ---- tests -----------------------------------------------------------------------------------

TEST(RenderCamera, FramesTheBoundingSphereAsDocumented) {
  const SlabModel model = make_model(icosahedron(), 4, 2);
  const RenderCamera cam = fit_camera(model, 320, 240, 30, 20);
  const double half = kRenderFovYDeg / 2 * kDeg;  // the vertical field is the smaller one at 4:3
  // The vertices at 0.8 + 0.4·δ of the unit icosahedron's, δ = 0.5 as stored (its unorm16 code).
  const double radius = 0.8 + 0.4 * double(float(Unorm16(0.5f)));
  const double D = radius / std::sin(std::atan(kRenderFill * std::tan(half)));
  EXPECT_NEAR(cam.radius, radius, 1e-6);
  EXPECT_NEAR((cam.eye - cam.target).norm(), D, 1e-6);
  EXPECT_NEAR((cam.eye - cam.target).normalized().dot(towards_eye(30, 20)), 1.0, 1e-9);
  const Eigen::Vector2d centre = cam.project(cam.target);
  EXPECT_NEAR(centre.x(), 160, 1e-3);
  EXPECT_NEAR(centre.y(), 120, 1e-3);
  // A point straight above the target (Y up) lands above the centre (smaller row).
  EXPECT_LT(cam.project(cam.target + Vec3(0, 0.5, 0)).y(), 120);
  EXPECT_THROW(fit_camera(model, 320, 240, 0, 91), InvalidInput);
  EXPECT_THROW(fit_camera(model, 0, 240, 0, 0), InvalidInput);
  // Straight down is allowed and well defined.
  const RenderCamera top = fit_camera(model, 64, 64, 0, 90);
  EXPECT_TRUE(top.view.allFinite());
}

TEST(RenderPng, SilhouetteLiesBetweenInscribedAndCircumscribedSpheres) {
  const int W = 320, H = 240;
  const SlabModel model = make_model(icosahedron(), 4, 2);
  RenderOptions o;
  o.width = W;
  o.height = H;
  o.azimuth_deg = 25;
  o.elevation_deg = 20;
  o.background = {0.2f, 0.3f, 0.4f};
  const std::string path = temp_png("silhouette");
  render_png(model, path, o);
  const Image im = read_png(path);
  fs::remove(path);
  ASSERT_EQ(im.width, W);
  ASSERT_EQ(im.height, H);

  // Analytic silhouettes of spheres about the target (see fit_camera): radius
  // (H/2)·tan(asin(r/D))/tan(fov/2) pixels. The icosahedron contains its inscribed sphere and lies
  // in its circumscribed (unit) sphere, so its silhouette lies between their discs.
  const double half = kRenderFovYDeg / 2 * kDeg;
  const double D = 1.0 / std::sin(std::atan(kRenderFill * std::tan(half)));
  auto disc = [&](double r) { return H / 2.0 * std::tan(std::asin(r / D)) / std::tan(half); };
  const std::array<Vec3, 3> face = surface_corners(model, 0);
  const double inradius = std::abs((face[1] - face[0]).cross(face[2] - face[0]).normalized().dot(face[0]));
  const double r_in = disc(inradius), r_out = disc(1.0);
  EXPECT_NEAR(r_out, kRenderFill * H / 2, 1e-9);

  const uint8_t bg[3] = {linear_to_srgb8(0.2f), linear_to_srgb8(0.3f), linear_to_srgb8(0.4f)};
  long covered = 0, bad_outside = 0, bad_inside = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const uint8_t* p = im.at(x, y);
      const bool background = p[0] == bg[0] && p[1] == bg[1] && p[2] == bg[2];
      const double r = std::hypot(x + 0.5 - W / 2.0, y + 0.5 - H / 2.0);
      covered += !background;
      if (r > r_out + 1.0 && !background) ++bad_outside;
      if (r < r_in - 1.0 && background) ++bad_inside;
    }
  EXPECT_EQ(bad_outside, 0) << "model pixels outside the circumscribed sphere's silhouette";
  EXPECT_EQ(bad_inside, 0) << "background pixels inside the inscribed sphere's silhouette";
  const double fraction = static_cast<double>(covered) / (W * H);
  EXPECT_GT(fraction, std::numbers::pi * r_in * r_in / (W * H) * 0.98);
  EXPECT_LT(fraction, std::numbers::pi * r_out * r_out / (W * H) * 1.02);
  // Corners are far outside: exactly the background colour.
  for (auto [x, y] : {std::pair{0, 0}, {W - 1, 0}, {0, H - 1}, {W - 1, H - 1}})
    EXPECT_TRUE(im.at(x, y)[0] == bg[0] && im.at(x, y)[1] == bg[1] && im.at(x, y)[2] == bg[2]);
}

TEST(RenderPng, RedSlabFacingTheCameraLooksRed) {
  const double az = -40, el = 10;
  SlabModel model = make_model(icosahedron(), 4, 2);
  const int red = facing_slab(model, towards_eye(az, el));
  paint_slab(model, red, {1, 0, 0});
  paint_slab(model, (red + 7) % model.slab_count(), {1, 0, 0});  // a second red slab, elsewhere
  rebuild_derived(model);
  RenderOptions o;
  o.width = 200;
  o.height = 200;
  o.azimuth_deg = az;
  o.elevation_deg = el;
  const std::string path = temp_png("red");
  render_png(model, path, o);
  const Image im = read_png(path);
  fs::remove(path);

  const RenderCamera cam = fit_camera(model, o.width, o.height, az, el);
  const std::array<Vec3, 3> c = surface_corners(model, red);
  const Eigen::Vector2d centre = cam.project((c[0] + c[1] + c[2]) / 3);
  const uint8_t* p = im.at(static_cast<int>(centre.x()), static_cast<int>(centre.y()));
  EXPECT_GT(p[0], 150);
  EXPECT_LT(p[1], p[0] / 4);
  EXPECT_LT(p[2], p[0] / 4);
  // A white slab next to it stays grey-white: the colour comes from the right tile.
  const int white = model.edge_neighbour[red][0] != (red + 7) % model.slab_count() ? model.edge_neighbour[red][0]
                                                                                   : model.edge_neighbour[red][1];
  ASSERT_GE(white, 0);
  const std::array<Vec3, 3> w = surface_corners(model, white);
  const Eigen::Vector2d wc = cam.project((w[0] + w[1] + w[2]) / 3);
  const uint8_t* q = im.at(static_cast<int>(wc.x()), static_cast<int>(wc.y()));
  EXPECT_GT(q[1], 80);
  EXPECT_NEAR(q[0], q[1], 3);
  EXPECT_NEAR(q[1], q[2], 3);
}

TEST(SlabRenderer, UploadSlabChangesOnlyThatSlabsPixels) {
  const int W = 240, H = 240;
  const double az = 15, el = 25;
  SlabModel model = make_model(icosahedron(), 4, 2);
  Scene scene(model, W, H, az, el);
  const Image before = scene.frame();

  const int slab = facing_slab(model, towards_eye(az, el));
  paint_slab(model, slab, {0, 0.6f, 0});  // edge texels too: the neighbours' copies stay old on the GPU
  scene.renderer.upload_slab(model, slab);
  const Image after = scene.frame();

  const std::array<Vec3, 3> c = surface_corners(model, slab);
  const std::array<Eigen::Vector2d, 3> tri = {scene.camera.project(c[0]), scene.camera.project(c[1]),
                                              scene.camera.project(c[2])};
  const double area =
      std::abs((tri[1] - tri[0]).x() * (tri[2] - tri[0]).y() - (tri[1] - tri[0]).y() * (tri[2] - tri[0]).x()) / 2;
  long changed = 0, changed_outside = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      if (std::equal(before.at(x, y), before.at(x, y) + 3, after.at(x, y))) continue;
      ++changed;
      // MSAA may blend a pixel whose centre is just outside the edge.
      if (distance_to_triangle({x + 0.5, y + 0.5}, tri) > 1.5) ++changed_outside;
    }
  EXPECT_EQ(changed_outside, 0);
  EXPECT_GT(changed, 0.8 * area) << "projected area " << area << " pixels";
  const Eigen::Vector2d centre = (tri[0] + tri[1] + tri[2]) / 3;
  const uint8_t* p = after.at(static_cast<int>(centre.x()), static_cast<int>(centre.y()));
  EXPECT_GT(p[1], 2 * p[0]);
  EXPECT_GT(p[1], 2 * p[2]);
}

TEST(SlabRenderer, ReuploadingUnchangedSlabsLeavesTheImageIdentical) {
  // upload_slab fills vertices and the atlas tile on its own; it must agree with upload_all
  // (build_texture_atlas) bit for bit wherever the image samples them.
  SlabModel model = make_model(subdivide(icosahedron()), 3, 3);
  for (int s = 0; s < model.slab_count(); s += 3)
    paint_slab(model, s, {0.1f * (s % 10), 0.5f, 1.0f - 0.05f * (s % 20)});
  Scene scene(model, 160, 120, 60, -30);
  const Image first = scene.frame(true);
  for (int s = 0; s < model.slab_count(); ++s) scene.renderer.upload_slab(model, s);
  const Image second = scene.frame(true);
  EXPECT_TRUE(first.rgb == second.rgb);
}

TEST(SlabRenderer, UploadFromASnapshotDrawsWhatTheModelDraws) {
  // The studio's render thread uploads from snapshots while the servo edits the live model: the
  // snapshot path must give the model path's pixels, for an edit the snapshot published, and a
  // reader pinned before the edit the unedited pixels.
  SlabModel model = make_model(subdivide(icosahedron()), 3, 2);
  SnapshotOptions options;
  options.spare_versions = model.slab_count();
  SlabSnapshots snapshots(model, options);
  Scene scene(model, 160, 120, 30, 20);
  const Image unedited = scene.frame(true);
  const SnapshotReader before(snapshots);
  for (int s = 0; s < model.slab_count(); ++s) ASSERT_TRUE(snapshots.before_write(s));
  // Edit: paint every third slab, push one slab's samples in, thicken the under-layer under another.
  for (int s = 0; s < model.slab_count(); s += 3) paint_slab(model, s, {0.9f, 0.2f * (s % 5), 0.1f});
  const int P = model.samples.per_slab;
  std::vector<int32_t> moved(P);
  for (int k = 0; k < P; ++k) moved[k] = model.samples.id(5, k);
  for (int32_t id : moved) model.displacement[id] = 0.5f * model.displacement[id];
  update_displacements(model, moved.data(), moved.size());
  update_normals(model, moved.data(), moved.size());
  for (int k = 0; k < P; ++k) model.layer_displacement.set(model.samples.id(7, k), 1.0f);
  EXPECT_EQ(snapshots.publish_commit(), 1u);

  for (int s = 0; s < model.slab_count(); ++s) scene.renderer.upload_slab(model, s);
  const Image from_model = scene.frame(true);
  EXPECT_FALSE(from_model.rgb == unedited.rgb) << "the edit shows";
  scene.renderer.upload_all(make_model(subdivide(icosahedron()), 3, 2));  // back to the unedited data
  {
    SnapshotReader reader(snapshots);
    for (int s = 0; s < model.slab_count(); ++s) scene.renderer.upload_slab(model, reader.slab(s), s);
  }
  const Image from_snapshot = scene.frame(true);
  EXPECT_TRUE(from_snapshot.rgb == from_model.rgb);
  for (int s = 0; s < model.slab_count(); ++s) scene.renderer.upload_slab(model, before.slab(s), s);
  EXPECT_TRUE(scene.frame(true).rgb == unedited.rgb) << "the reader pinned before the edit";

  SnapshotReader reader(snapshots);
  SlabView wrong = reader.slab(0);
  wrong.per_slab += 1;
  EXPECT_THROW(scene.renderer.upload_slab(model, wrong, 0), InvalidInput);
}

TEST(SlabRenderer, CoarserLevelsDrawTheSameFlatSurface) {
  // Flat slabs (δ = 0.5 everywhere: each slab's surface is the coarse triangle): every level of
  // detail is a triangulation of the same triangles, so the model covers the same pixels.
  const SlabModel model = make_model(icosahedron(), 4, 2);
  Scene scene(model, 200, 200, 20, 10);
  ASSERT_EQ(scene.renderer.level_count(), 3);  // n = 4: grids of 4, 2 and 1 intervals
  auto covered = [](const Image& im) {
    std::vector<bool> mask(static_cast<size_t>(im.width) * im.height);
    for (int y = 0; y < im.height; ++y)
      for (int x = 0; x < im.width; ++x)
        mask[static_cast<size_t>(y) * im.width + x] = im.at(x, y)[0] < 250 || im.at(x, y)[2] < 250;
    return mask;
  };
  const std::vector<bool> fine = covered(scene.frame(false, 0));
  const long area = std::count(fine.begin(), fine.end(), true);
  ASSERT_GT(area, 5000);
  for (int level = 1; level < 3; ++level) {
    const std::vector<bool> coarse = covered(scene.frame(false, level));
    long differ = 0;
    for (size_t k = 0; k < fine.size(); ++k) differ += fine[k] != coarse[k];
    EXPECT_LE(differ, area / 500) << "level " << level;
  }
  EXPECT_TRUE(scene.frame(false, 7).rgb == scene.frame(false, 2).rgb) << "levels beyond the coarsest are clamped";
}

TEST(SlabRenderer, SlabEdgeOverlayDarkensBoundariesOnly) {
  const double az = 0, el = 15;
  const SlabModel model = make_model(icosahedron(), 4, 2);
  Scene scene(model, 240, 240, az, el);
  const Image plain = scene.frame(false), edges = scene.frame(true);
  const int slab = facing_slab(model, towards_eye(az, el));
  const std::array<Vec3, 3> c = surface_corners(model, slab);
  const Eigen::Vector2d mid = scene.camera.project((c[0] + c[1]) / 2),
                        centre = scene.camera.project((c[0] + c[1] + c[2]) / 3);
  const uint8_t* on_edge = edges.at(static_cast<int>(mid.x()), static_cast<int>(mid.y()));
  EXPECT_LT(on_edge[0], 100);
  const int cx = static_cast<int>(centre.x()), cy = static_cast<int>(centre.y());
  EXPECT_TRUE(std::equal(plain.at(cx, cy), plain.at(cx, cy) + 3, edges.at(cx, cy)));
}

TEST(SlabRenderer, RejectsBadCallsWithClearErrors) {
  SlabModel model = make_model(icosahedron(), 2, 1);
  Scene scene(model, 32, 32, 0, 0);
  EXPECT_THROW(scene.renderer.upload_slab(model, model.slab_count()), InvalidInput);
  EXPECT_THROW(scene.renderer.upload_slab(model, -1), InvalidInput);
  SlabModel other = make_model(icosahedron(), 3, 1);
  EXPECT_THROW(scene.renderer.upload_slab(other, 0), InvalidInput);
  SlabModel stale = model;
  stale.samples = {};
  EXPECT_THROW(scene.renderer.upload_all(stale), InvalidInput);
  EXPECT_EQ(scene.renderer.triangle_count(), 20 * 4);
}

TEST(RenderPng, ReportsBadOptionsAndUnwritablePaths) {
  const SlabModel model = make_model(icosahedron(), 2, 1);
  RenderOptions o;
  o.width = 16;
  o.height = 16;
  try {
    render_png(model, "/nonexistent-dir/x/view.png", o);
    FAIL() << "expected IoError";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-dir/x/view.png"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists("/nonexistent-dir/x/view.png.tmp"));
  o.width = 0;
  EXPECT_THROW(render_png(model, temp_png("bad"), o), InvalidInput);
  o.width = 16;
  o.elevation_deg = -95;
  EXPECT_THROW(render_png(model, temp_png("bad"), o), InvalidInput);
  EXPECT_FALSE(fs::exists(temp_png("bad")));
}

TEST(RenderPng, LargeModelAtDefaultSize) {
  // 320 slabs x n = 15 (the paper's 225 triangles per slab) = 72,000 triangles at 1280x960.
  const SlabModel model = make_model(subdivide(subdivide(icosahedron())), 15, 2);
  const std::string path = temp_png("large");
  RenderOptions o;
  o.show_slab_edges = true;
  o.background = {0, 0, 0};
  const auto start = std::chrono::steady_clock::now();
  render_png(model, path, o);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  RecordProperty("render_seconds", std::to_string(seconds));
  const Image im = read_png(path);
  fs::remove(path);
  EXPECT_EQ(im.width, 1280);
  EXPECT_EQ(im.height, 960);
  long covered = 0;
  for (size_t k = 0; k < im.rgb.size(); k += 3) covered += (im.rgb[k] | im.rgb[k + 1] | im.rgb[k + 2]) != 0;
  // The geodesic sphere nearly fills its unit bounding sphere's disc of radius 0.9·480 pixels.
  const double disc = std::numbers::pi * std::pow(0.9 * 480, 2);
  EXPECT_GT(covered, 0.9 * disc);
  EXPECT_LT(covered, 1.02 * disc);
}

}  // namespace
}  // namespace hdm
