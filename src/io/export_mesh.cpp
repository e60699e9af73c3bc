// SPDX-License-Identifier: MIT
#include <hdm/core/encode_png.h>
#include <hdm/core/error.h>
#include <hdm/io/export_mesh.h>
#include <hdm/io/hdm_file.h>
#include <hdm/atlas/texture_atlas.h>
#include <hdm/slab/triangle_grid.h>

#include <tiny_gltf.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstring>
#include <filesystem>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace hdm {
namespace {

enum class Format { obj, ply, glb };

Format format_of(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".obj") return Format::obj;
  if (ext == ".ply") return Format::ply;
  if (ext == ".glb") return Format::glb;
  throw InvalidInput(path + ": unsupported export format \"" + ext + "\" (supported: .obj, .ply, .glb)");
}

std::string with_extension(const std::string& path, const char* ext) {
  return std::filesystem::path(path).replace_extension(ext).string();
}

void check_derived(const SlabModel& m) {
  const size_t S = m.slabs.size();
  if (S == 0 || m.samples.n != m.grid_n || m.samples.slot_count() != S * m.samples.per_slab ||
      m.slab_samples.size() != m.samples.slot_count() || m.displacement.size() != size_t(m.samples.count))
    throw InvalidInput("export_mesh: the model has no slabs or no derived data (call rebuild_derived first)");
}

/// Calls f(a, b, c) with the packed grid indices of every grid triangle of one slab, in the
/// order and winding of SampleLayout::triangles (triangle_grid.h: "up" then "down" per cell).
template <class F>
void for_each_grid_triangle(int n, F&& f) {
  for (int j = 0; j < n; ++j)
    for (int i = 0; i + j < n; ++i) {
      f(grid::index(n, i, j), grid::index(n, i, j + 1), grid::index(n, i + 1, j));
      if (i + j <= n - 2) f(grid::index(n, i + 1, j), grid::index(n, i, j + 1), grid::index(n, i + 1, j + 1));
    }
}

// Shortest text that reads back as the same value.
template <class T>
void append_number(std::string& out, T v) {
  char buf[40];
  const auto r = std::to_chars(buf, buf + sizeof(buf), v);
  out.append(buf, r.ptr);
}

template <class T>
void append_pod(std::string& out, T v) {
  static_assert(std::endian::native == std::endian::little, "PLY and glTF writers assume a little-endian host");
  char buf[sizeof(T)];
  std::memcpy(buf, &v, sizeof(T));
  out.append(buf, sizeof(T));
}

std::vector<uint8_t> encode_atlas_png(const TextureAtlas& atlas, const std::string& path) {
  return encode_png(atlas.width, atlas.height, 4, atlas.rgba, path + ": the texture atlas");
}

/// Colour the surface shows at displacement sample @p s's grid point (texel (i·m, j·m) of its home
/// slab; the under-layer's where carving exposed it).
Vec3f sample_colour(const SlabModel& m, int s) {
  const int slab = m.samples.home(s).slab, local = m.samples.home(s).index;
  const int i = m.samples.point_i[local] * m.texel_density, j = m.samples.point_j[local] * m.texel_density;
  const int texel = m.texels.id(slab, grid::index(m.texels.n, i, j));
  return surface_colour(m, texel);
}

// ---- OBJ + MTL + PNG ----

void export_obj(const SlabModel& m, const std::string& path) {
  const std::string mtl_path = with_extension(path, ".mtl"), png_path = with_extension(path, ".png");
  const std::string mtl_name = std::filesystem::path(mtl_path).filename().string();
  const std::string png_name = std::filesystem::path(png_path).filename().string();
  const TextureAtlas atlas = build_texture_atlas(m);
  const std::vector<uint8_t> png = encode_atlas_png(atlas, png_path);
  const std::string mtl =
      "# hdm colour atlas\nnewmtl hdm_colour\nKa 0 0 0\nKd 1 1 1\nKs 0 0 0\nd 1\nillum 1\nmap_Kd " + png_name + "\n";

  const int n = m.grid_n, S = m.slab_count(), per_slab = m.samples.per_slab;
  std::string out;
  out.reserve(static_cast<size_t>(m.samples.count) * 80 + static_cast<size_t>(S) * per_slab * 30 +
              size_t(m.samples.triangle_count()) * 60);
  out += "# hdm displaced surface of " + m.source + "\nmtllib " + mtl_name + "\n";
  for (int s = 0; s < m.samples.count; ++s) {
    const Vec3 p = sample_position(m, s);
    out += "v ";
    append_number(out, p.x());
    out += ' ';
    append_number(out, p.y());
    out += ' ';
    append_number(out, p.z());
    out += '\n';
  }
  for (int s = 0; s < m.samples.count; ++s) {
    const Vec3f q = sample_normal(m, s).normalized();  // unit to float rounding, as the formats expect
    out += "vn ";
    append_number(out, q.x());
    out += ' ';
    append_number(out, q.y());
    out += ' ';
    append_number(out, q.z());
    out += '\n';
  }
  for (int s = 0; s < S; ++s)
    for (int k = 0; k < per_slab; ++k) {
      const Eigen::Vector2f t = atlas.uv(s, double(m.samples.point_i[k]) / n, double(m.samples.point_j[k]) / n);
      out += "vt ";
      append_number(out, t.x());
      out += ' ';
      append_number(out, 1.0f - t.y());  // OBJ: v = 0 is the bottom row of the image
      out += '\n';
    }
  out += "usemtl hdm_colour\n";
  for (int s = 0; s < S; ++s) {
    const SlabIds ids = m.samples.slab_ids(s);
    const int64_t vt_base = static_cast<int64_t>(s) * per_slab + 1;
    for_each_grid_triangle(n, [&](int a, int b, int c) {
      out += 'f';
      for (int k : {a, b, c}) {
        out += ' ';
        append_number(out, ids[k] + 1);
        out += '/';
        append_number(out, vt_base + k);
        out += '/';
        append_number(out, ids[k] + 1);
      }
      out += '\n';
    });
  }
  // One set: a failed export leaves neither a new OBJ nor a new MTL or PNG beside the old ones.
  const FileBytes set[] = {
      {path, out.data(), out.size()}, {mtl_path, mtl.data(), mtl.size()}, {png_path, png.data(), png.size()}};
  write_files_atomic(set);
}

// ---- PLY ----

void export_ply(const SlabModel& m, const std::string& path) {
  std::string out = "ply\nformat binary_little_endian 1.0\ncomment hdm displaced surface\nelement vertex " +
                    std::to_string(m.samples.count) +
                    "\nproperty float x\nproperty float y\nproperty float z\n"
                    "property float nx\nproperty float ny\nproperty float nz\n"
                    "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                    "element face " +
                    std::to_string(m.samples.triangle_count()) +
                    "\nproperty list uchar int vertex_indices\nend_header\n";
  out.reserve(out.size() + static_cast<size_t>(m.samples.count) * 27 + size_t(m.samples.triangle_count()) * 13);
  for (int s = 0; s < m.samples.count; ++s) {
    const Vec3f p = sample_position(m, s).cast<float>();
    const Vec3f q = sample_normal(m, s).normalized();  // unit to float rounding, as the formats expect
    const Vec3f c = sample_colour(m, s);
    for (int k = 0; k < 3; ++k) append_pod(out, p[k]);
    for (int k = 0; k < 3; ++k) append_pod(out, q[k]);
    for (int k = 0; k < 3; ++k) append_pod(out, linear_to_srgb8(c[k]));
  }
  m.samples.for_each_triangle([&](const Tri& t) {
    append_pod(out, uint8_t{3});
    for (int32_t v : t) append_pod(out, v);
  });
  write_file_atomic(path, out.data(), out.size());
}

// ---- binary glTF ----

/// Appends @p bytes to the glTF buffer as a new 4-byte aligned bufferView; returns its index.
int add_view(tinygltf::Model& g, const void* bytes, size_t size, int target) {
  std::vector<unsigned char>& data = g.buffers[0].data;
  data.resize((data.size() + 3) & ~size_t{3}, 0);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = data.size();
  view.byteLength = size;
  view.target = target;
  data.insert(data.end(), static_cast<const unsigned char*>(bytes), static_cast<const unsigned char*>(bytes) + size);
  g.bufferViews.push_back(view);
  return static_cast<int>(g.bufferViews.size()) - 1;
}

int add_accessor(tinygltf::Model& g, int view, int component, int type, size_t count) {
  tinygltf::Accessor a;
  a.bufferView = view;
  a.byteOffset = 0;
  a.componentType = component;
  a.type = type;
  a.count = count;
  g.accessors.push_back(a);
  return static_cast<int>(g.accessors.size()) - 1;
}

void export_glb(const SlabModel& m, const std::string& path) {
  const int n = m.grid_n, S = m.slab_count(), per_slab = m.samples.per_slab;
  const size_t V = static_cast<size_t>(S) * per_slab;
  if (V > static_cast<size_t>(std::numeric_limits<uint32_t>::max()))
    throw InvalidInput(path + ": too many vertices for 32-bit glTF indices");
  const TextureAtlas atlas = build_texture_atlas(m);

  // Vertices duplicated per slab (slab-major, packed grid order), so each has its slab's uv.
  std::vector<float> positions(V * 3), normals(V * 3), uvs(V * 2);
  std::vector<uint32_t> indices;
  indices.reserve(size_t(m.samples.triangle_count()) * 3);
  std::vector<double> lo(3, std::numeric_limits<double>::infinity()), hi(3, -std::numeric_limits<double>::infinity());
  for (int s = 0; s < S; ++s)
    for (int k = 0; k < per_slab; ++k) {
      const size_t v = static_cast<size_t>(s) * per_slab + k;
      const int32_t id = m.samples.id(s, k);
      const Vec3f p = sample_position(m, id).cast<float>(), nrm = m.slab_samples[v].normal().normalized();
      const Eigen::Vector2f t = atlas.uv(s, double(m.samples.point_i[k]) / n, double(m.samples.point_j[k]) / n);
      for (int c = 0; c < 3; ++c) {
        positions[3 * v + c] = p[c];
        normals[3 * v + c] = nrm[c];
        lo[c] = std::min(lo[c], double(p[c]));
        hi[c] = std::max(hi[c], double(p[c]));
      }
      uvs[2 * v] = t.x();
      uvs[2 * v + 1] = t.y();
    }
  for (int s = 0; s < S; ++s) {
    const uint32_t base = static_cast<uint32_t>(s) * per_slab;
    for_each_grid_triangle(n, [&](int a, int b, int c) {
      indices.insert(indices.end(), {base + a, base + b, base + c});
    });
  }
  const std::vector<uint8_t> png = encode_atlas_png(atlas, path);

  tinygltf::Model g;
  g.asset.version = "2.0";
  g.asset.generator = "hdm";
  g.buffers.resize(1);
  const int pos_view = add_view(g, positions.data(), positions.size() * 4, TINYGLTF_TARGET_ARRAY_BUFFER);
  const int nrm_view = add_view(g, normals.data(), normals.size() * 4, TINYGLTF_TARGET_ARRAY_BUFFER);
  const int uv_view = add_view(g, uvs.data(), uvs.size() * 4, TINYGLTF_TARGET_ARRAY_BUFFER);
  const int idx_view = add_view(g, indices.data(), indices.size() * 4, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
  const int png_view = add_view(g, png.data(), png.size(), 0);
  g.buffers[0].data.resize((g.buffers[0].data.size() + 3) & ~size_t{3}, 0);

  const int pos = add_accessor(g, pos_view, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, V);
  g.accessors[pos].minValues = lo;  // required for POSITION by the glTF spec
  g.accessors[pos].maxValues = hi;
  const int nrm = add_accessor(g, nrm_view, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, V);
  const int uv = add_accessor(g, uv_view, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, V);
  const int idx = add_accessor(g, idx_view, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, indices.size());

  tinygltf::Image image;
  image.name = "hdm_colour_atlas";
  image.mimeType = "image/png";
  image.bufferView = png_view;
  g.images.push_back(image);
  tinygltf::Sampler sampler;
  sampler.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
  sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;  // no mipmaps: they would mix neighbouring tiles
  sampler.wrapS = sampler.wrapT = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
  g.samplers.push_back(sampler);
  tinygltf::Texture texture;
  texture.source = 0;
  texture.sampler = 0;
  g.textures.push_back(texture);
  tinygltf::Material material;
  material.name = "hdm_colour";
  material.pbrMetallicRoughness.baseColorTexture.index = 0;
  material.pbrMetallicRoughness.metallicFactor = 0.0;
  material.pbrMetallicRoughness.roughnessFactor = 1.0;
  g.materials.push_back(material);

  tinygltf::Primitive prim;
  prim.attributes["POSITION"] = pos;
  prim.attributes["NORMAL"] = nrm;
  prim.attributes["TEXCOORD_0"] = uv;
  prim.indices = idx;
  prim.material = 0;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  tinygltf::Mesh mesh;
  mesh.name = m.source.empty() ? "hdm" : m.source;
  mesh.primitives.push_back(prim);
  g.meshes.push_back(mesh);
  tinygltf::Node node;
  node.mesh = 0;
  g.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes.push_back(0);
  g.scenes.push_back(scene);
  g.defaultScene = 0;

  std::ostringstream stream;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&g, stream, false, true) || !stream)
    throw IoError(path + ": glTF serialisation failed");
  const std::string bytes = std::move(stream).str();
  write_file_atomic(path, bytes.data(), bytes.size());
}

}  // namespace

std::vector<std::string> export_files(const std::string& path) {
  if (format_of(path) == Format::obj) return {path, with_extension(path, ".mtl"), with_extension(path, ".png")};
  return {path};
}

void export_mesh(const SlabModel& model, const std::string& path) {
  const Format format = format_of(path);
  check_derived(model);
  switch (format) {
    case Format::obj:
      export_obj(model, path);
      break;
    case Format::ply:
      export_ply(model, path);
      break;
    case Format::glb:
      export_glb(model, path);
      break;
  }
}

}  // namespace hdm
