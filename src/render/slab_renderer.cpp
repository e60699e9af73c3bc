// SPDX-License-Identifier: MIT
#include <hdm/core/error.h>
#include <hdm/atlas/texture_atlas.h>
#include <hdm/render/camera.h>
#include <hdm/render/slab_renderer.h>
#include <hdm/slab/slab_model.h>
#include <hdm/slab/slab_snapshots.h>
#include <hdm/slab/triangle_grid.h>

#include "gl.h"
#include "model_check.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace hdm {
namespace {

// One vertex per (slab, grid point). 44 bytes.
struct Vertex {
  float position[3];  // world [model units]
  float normal[3];    // world, unit
  float uv[2];        // atlas coordinates
  float bary[2];      // (wT, wS) within the slab, for the slab-edge overlay
  float layer;        // depth of the surface below the under-layer's top [model units]: > 0 where exposed
};

// Shading happens in linear RGB; the atlas is an sRGB texture, so sampling decodes it, and the
// output is encoded once at the end (the framebuffer is plain RGBA8).
const char* const kVertexShader = R"(#version 450 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;
layout(location = 3) in vec2 a_bary;
layout(location = 4) in float a_layer;
layout(location = 0) uniform mat4 u_view;
layout(location = 1) uniform mat4 u_projection;
out vec3 v_normal;
out vec3 v_view;
out vec2 v_uv;
out vec2 v_bary;
out float v_layer;
out vec3 v_model;
void main() {
  v_normal = mat3(u_view) * a_normal;  // the view matrix is rigid
  v_model = a_position;
  v_uv = a_uv;
  v_bary = a_bary;
  v_layer = a_layer;
  vec4 p = u_view * vec4(a_position, 1.0);
  v_view = -p.xyz;
  gl_Position = u_projection * p;
}
)";

const char* const kFragmentShader = R"(#version 450 core
in vec3 v_normal;
in vec3 v_view;
in vec2 v_uv;
in vec2 v_bary;
in float v_layer;
in vec3 v_model;
layout(location = 2) uniform int u_edges;
layout(location = 3) uniform vec4 u_layer;  // the under-layer's linear colour and roughness
layout(location = 4) uniform vec4 u_footprint;  // brush sphere: centre [model units], radius (<= 0: none)
layout(binding = 0) uniform sampler2D u_atlas;
out vec4 o_colour;
// View space: +Z points at the viewer.
const vec3 kKey = normalize(vec3(-0.4, 0.6, 1.0));
const vec3 kFill = normalize(vec3(0.7, -0.3, 0.6));
vec3 encode_srgb(vec3 c) {
  c = clamp(c, 0.0, 1.0);
  return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}
void main() {
  vec3 n = normalize(v_normal);
  if (!gl_FrontFacing) n = -n;  // open models show their inside
  // At most about 0.88, so white albedo never saturates into a white background.
  float light = 0.2 + 0.6 * max(dot(n, kKey), 0.0) + 0.25 * max(dot(n, kFill), 0.0);
  // The under-layer where the surface lies below its top: the boundary is the zero line of the
  // interpolated depth, anti-aliased over one pixel.
  vec4 paint = texture(u_atlas, v_uv);  // rgb: colour, a: roughness
  float exposed = clamp(v_layer / max(fwidth(v_layer), 1e-12), 0.0, 1.0);
  vec3 albedo = mix(paint.rgb, u_layer.rgb, exposed);
  float rough = mix(paint.a, u_layer.a, exposed);
  vec3 colour = albedo * light;
  // Blinn-Phong highlight of the key light, strong and tight on smooth surfaces, none at roughness 1.
  vec3 h = normalize(kKey + normalize(v_view));
  float gloss = 1.0 - rough;
  colour += vec3(0.5 * gloss * gloss * pow(max(dot(n, h), 0.0), mix(8.0, 96.0, gloss)));
  if (u_edges != 0) {
    vec3 w = vec3(v_bary, 1.0 - v_bary.x - v_bary.y);
    vec3 pixels = w / max(fwidth(w), vec3(1e-7));  // distance to each slab edge [pixels]
    float d = min(pixels.x, min(pixels.y, pixels.z));
    colour = mix(vec3(0.02), colour, clamp(d - 1.0, 0.0, 1.0));
  }
  if (u_footprint.w > 0.0) {
    // The brush's footprint: the surface inside the brush sphere lightly tinted, its rim (where the
    // surface crosses the sphere) a line about 2 pixels wide.
    float d = distance(v_model, u_footprint.xyz) - u_footprint.w;
    // (and never farther than a quarter radius from it: at silhouettes fwidth can span the model)
    float rim = (1.0 - clamp(abs(d) / max(fwidth(d), 1e-12) - 1.0, 0.0, 1.0)) * step(abs(d), 0.25 * u_footprint.w);
    colour = mix(colour, vec3(1.0, 0.45, 0.0), 0.15 * step(d, 0.0));
    colour = mix(colour, vec3(1.0, 0.35, 0.0), rim);
  }
  o_colour = vec4(encode_srgb(colour), 1.0);
}
)";

}  // namespace

struct SlabRenderer::State {
  GLuint program = 0, vao = 0, vbo = 0, ebo = 0, atlas = 0;
  int slabs = 0, n = 0, texel_density = 0, per_slab = 0;
  float layer[4] = {0, 0, 0, 1};      // the under-layer's colour and roughness
  float footprint[4] = {0, 0, 0, 0};  // brush sphere (centre, radius); radius 0: none
  struct Level {
    size_t first;   // first index in the element buffer
    GLsizei count;  // indices
  };
  std::vector<Level> levels;     // level k: every 2^k-th grid point
  TextureAtlas layout;           // sizes and tile placement; rgba is dropped after upload
  std::vector<Vertex> vertices;  // staging for upload_slab
  std::vector<uint8_t> tile;     // staging for upload_slab

  void delete_buffers() {
    const GLuint buffers[] = {vbo, ebo};
    glDeleteBuffers(2, buffers);
    glDeleteTextures(1, &atlas);
    vbo = ebo = atlas = 0;
  }

  // Vertices of slab s into out[0 .. per_slab). at(k) gives grid point k's displacement, normal
  // and under-layer top (from the live model or a snapshot); positions are evaluated on the
  // sample's home projection line, so shared samples land on the same point in every slab.
  template <class At>
  void fill_vertices(const SlabModel& m, int s, Vertex* out, At&& at) const {
    const SampleLayout& L = m.samples;
    const SlabIds ids = L.slab_ids(s);
    for (int k = 0; k < per_slab; ++k) {
      const double wT = static_cast<double>(L.point_i[k]) / n, wS = static_cast<double>(L.point_j[k]) / n;
      Vec3 p0, p1;
      projection_line(m, L.home(ids[k]).slab, L.home(ids[k]).index, p0, p1);
      float delta_f, layer_delta;
      Vec3f nrm;
      at(k, ids[k], delta_f, nrm, layer_delta);
      const double delta = delta_f;
      const Vec3f p = (p0 + delta * (p1 - p0)).cast<float>();  // = sample_position()
      const Eigen::Vector2f uv = layout.uv(s, wT, wS);
      const float layer = static_cast<float>((layer_delta - delta) * (p1 - p0).norm());
      out[k] = Vertex{{p.x(), p.y(), p.z()},
                      {nrm.x(), nrm.y(), nrm.z()},
                      {uv.x(), uv.y()},
                      {static_cast<float>(wT), static_cast<float>(wS)},
                      layer};
    }
  }
  void fill_vertices(const SlabModel& m, int s, Vertex* out) const {
    fill_vertices(m, s, out, [&m](int, int32_t id, float& delta, Vec3f& nrm, float& layer) {
      delta = m.displacement[id], nrm = sample_normal(m, id), layer = m.layer_displacement[id];
    });
  }

  void check_layout(const SlabModel& model, int slab, const char* what) const {
    if (slab < 0 || slab >= slabs)
      throw InvalidInput(std::string(what) + ": slab " + std::to_string(slab) + " is outside [0, " +
                         std::to_string(slabs) + ") (call upload_all first)");
    if (model.slab_count() != slabs || model.grid_n != n || model.texel_density != texel_density ||
        model.samples.per_slab != per_slab)
      throw InvalidInput(std::string(what) + ": the model's slabs or grid changed since upload_all");
  }

  void upload(int slab) {
    glNamedBufferSubData(vbo, static_cast<GLintptr>(static_cast<size_t>(slab) * per_slab * sizeof(Vertex)),
                         static_cast<GLsizeiptr>(per_slab * sizeof(Vertex)), vertices.data());
    const Eigen::Vector2i origin = layout.origin(slab);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(atlas, 0, origin.x() - 1, origin.y() - 1, layout.tile, layout.tile, GL_RGBA, GL_UNSIGNED_BYTE,
                        tile.data());
    render_detail::check_gl("re-uploading a slab");
  }
};

SlabRenderer::SlabRenderer() : state_(std::make_unique<State>()) {
  state_->program = render_detail::link_program(kVertexShader, kFragmentShader);
  glCreateVertexArrays(1, &state_->vao);
  const GLuint vao = state_->vao;
  const struct {
    GLuint location;
    GLint size;
    size_t offset;
  } attributes[] = {{0, 3, offsetof(Vertex, position)},
                    {1, 3, offsetof(Vertex, normal)},
                    {2, 2, offsetof(Vertex, uv)},
                    {3, 2, offsetof(Vertex, bary)},
                    {4, 1, offsetof(Vertex, layer)}};
  for (const auto& a : attributes) {
    glEnableVertexArrayAttrib(vao, a.location);
    glVertexArrayAttribFormat(vao, a.location, a.size, GL_FLOAT, GL_FALSE, static_cast<GLuint>(a.offset));
    glVertexArrayAttribBinding(vao, a.location, 0);
  }
  render_detail::check_gl("creating the slab renderer");
}

SlabRenderer::~SlabRenderer() {
  state_->delete_buffers();
  glDeleteVertexArrays(1, &state_->vao);
  glDeleteProgram(state_->program);
}

void SlabRenderer::upload_all(const SlabModel& model) {
  render_detail::check_renderable(model);
  State& st = *state_;
  TextureAtlas atlas = build_texture_atlas(model, AtlasContent::PaintAndRoughness);
  GLint max_texture = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_texture);
  if (atlas.width > max_texture || atlas.height > max_texture)
    throw RenderError("render: the colour atlas (" + std::to_string(atlas.width) + "x" + std::to_string(atlas.height) +
                      " pixels) exceeds GL_MAX_TEXTURE_SIZE " + std::to_string(max_texture) + "; lower texel_density");
  const int S = model.slab_count(), n = model.grid_n, P = model.samples.per_slab;
  const long long indices = 3LL * S * grid::triangle_count(n);
  if (static_cast<long long>(S) * P > std::numeric_limits<uint32_t>::max() ||
      indices > std::numeric_limits<GLsizei>::max())
    throw InvalidInput("render: the model is too large to draw (" + std::to_string(S) + " slabs, grid " +
                       std::to_string(n) + ")");

  st.delete_buffers();
  st.slabs = S;
  st.n = n;
  st.texel_density = model.texel_density;
  st.per_slab = P;
  st.layout = std::move(atlas);
  const UnderLayer& u = model.under_layer;
  st.layer[0] = u.colour.x(), st.layer[1] = u.colour.y(), st.layer[2] = u.colour.z(), st.layer[3] = u.roughness;

  // Atlas texture: immutable sRGB storage, no mipmaps (they would mix neighbouring tiles).
  glCreateTextures(GL_TEXTURE_2D, 1, &st.atlas);
  glTextureStorage2D(st.atlas, 1, GL_SRGB8_ALPHA8, st.layout.width, st.layout.height);
  glTextureParameteri(st.atlas, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(st.atlas, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(st.atlas, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(st.atlas, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(st.atlas, 0, 0, 0, st.layout.width, st.layout.height, GL_RGBA, GL_UNSIGNED_BYTE,
                      st.layout.rgba.data());
  std::vector<uint8_t>().swap(st.layout.rgba);  // only the layout is needed from now on

  // Vertices: slab s owns [s·P, (s+1)·P).
  std::vector<Vertex> vertices(static_cast<size_t>(S) * P);
  for (int s = 0; s < S; ++s) st.fill_vertices(model, s, &vertices[static_cast<size_t>(s) * P]);
  glCreateBuffers(1, &st.vbo);
  glNamedBufferStorage(st.vbo, static_cast<GLsizeiptr>(vertices.size() * sizeof(Vertex)), vertices.data(),
                       GL_DYNAMIC_STORAGE_BIT);

  // Indices: the grid split of triangle_grid.h, in the order build_sample_layout() emits it; then,
  // for each coarser level, the same split of the grid of every step-th point (paper §6: level of
  // detail from coarse subsets of each slab's grid), appended to the same buffer.
  std::vector<uint32_t> all;
  all.reserve(static_cast<size_t>(indices) * 4 / 3 + 16);
  st.levels.clear();
  for (int step = 1; step <= n && n % step == 0; step *= 2) {
    const int m = n / step;
    auto at = [&](int i, int j) { return static_cast<uint32_t>(grid::index(n, step * i, step * j)); };
    std::vector<uint32_t> local;
    local.reserve(3 * static_cast<size_t>(grid::triangle_count(m)));
    for (int j = 0; j < m; ++j)
      for (int i = 0; i + j < m; ++i) {
        local.insert(local.end(), {at(i, j), at(i, j + 1), at(i + 1, j)});
        if (i + j <= m - 2) local.insert(local.end(), {at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)});
      }
    st.levels.push_back({all.size(), static_cast<GLsizei>(local.size() * S)});
    for (int s = 0; s < S; ++s)
      for (uint32_t k : local) all.push_back(static_cast<uint32_t>(s) * P + k);
  }
  glCreateBuffers(1, &st.ebo);
  glNamedBufferStorage(st.ebo, static_cast<GLsizeiptr>(all.size() * sizeof(uint32_t)), all.data(), 0);

  glVertexArrayVertexBuffer(st.vao, 0, st.vbo, 0, sizeof(Vertex));
  glVertexArrayElementBuffer(st.vao, st.ebo);
  render_detail::check_gl("uploading the slab model");
}

void SlabRenderer::upload_slab(const SlabModel& model, int slab) {
  State& st = *state_;
  st.check_layout(model, slab, "upload_slab");
  render_detail::check_renderable(model);
  st.vertices.resize(st.per_slab);
  st.fill_vertices(model, slab, st.vertices.data());
  st.tile.resize(static_cast<size_t>(st.layout.tile) * st.layout.tile * 4);
  fill_atlas_tile(model, st.layout, slab, st.tile.data(), st.layout.tile, AtlasContent::PaintAndRoughness);
  st.upload(slab);
}

void SlabRenderer::upload_slab(const SlabModel& model, const SlabView& view, int slab) {
  State& st = *state_;
  st.check_layout(model, slab, "upload_slab");
  if (view.points == nullptr || view.per_slab != st.per_slab ||
      view.texels_per_slab != static_cast<int>(model.texels.per_slab) || view.texels == nullptr)
    throw InvalidInput("upload_slab: the snapshot's slab view does not match the uploaded model's grids");
  st.vertices.resize(st.per_slab);
  st.fill_vertices(model, slab, st.vertices.data(), [&view](int k, int32_t, float& delta, Vec3f& nrm, float& layer) {
    const SlabSample& p = view.points[k];
    delta = p.delta, nrm = p.normal(), layer = view.layer_displacement[k];
  });
  st.tile.resize(static_cast<size_t>(st.layout.tile) * st.layout.tile * 4);
  fill_atlas_tile(st.layout, view.texels, st.tile.data(), st.layout.tile);
  st.upload(slab);
}

void SlabRenderer::draw(const RenderCamera& camera, bool show_slab_edges, int level) const {
  const State& st = *state_;
  if (st.slabs == 0) return;
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);  // slab models may be open; back faces are shaded from their side
  glUseProgram(st.program);
  glProgramUniformMatrix4fv(st.program, 0, 1, GL_FALSE, camera.view.data());  // Eigen is column-major too
  glProgramUniformMatrix4fv(st.program, 1, 1, GL_FALSE, camera.projection.data());
  glProgramUniform1i(st.program, 2, show_slab_edges ? 1 : 0);
  glProgramUniform4f(st.program, 3, st.layer[0], st.layer[1], st.layer[2], st.layer[3]);
  glProgramUniform4f(st.program, 4, st.footprint[0], st.footprint[1], st.footprint[2], st.footprint[3]);
  glBindTextureUnit(0, st.atlas);
  glBindVertexArray(st.vao);
  const State::Level& l = st.levels[static_cast<size_t>(std::clamp(level, 0, static_cast<int>(st.levels.size()) - 1))];
  glDrawElements(GL_TRIANGLES, l.count, GL_UNSIGNED_INT, reinterpret_cast<const void*>(l.first * sizeof(uint32_t)));
  glBindVertexArray(0);
  glUseProgram(0);
  render_detail::check_gl("drawing the slab model");
}

void SlabRenderer::set_footprint(const Vec3& centre, double radius) noexcept {
  float* f = state_->footprint;
  const bool on = centre.allFinite() && std::isfinite(radius) && radius > 0;
  for (int k = 0; k < 3; ++k) f[k] = on ? static_cast<float>(centre[k]) : 0.0f;
  f[3] = on ? static_cast<float>(radius) : 0.0f;
}

int SlabRenderer::slab_count() const noexcept { return state_->slabs; }

int SlabRenderer::level_count() const noexcept { return static_cast<int>(state_->levels.size()); }

long long SlabRenderer::triangle_count() const noexcept {
  return static_cast<long long>(state_->slabs) * grid::triangle_count(state_->n);
}

}  // namespace hdm
