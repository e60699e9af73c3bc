// SPDX-License-Identifier: MIT
// export_mesh: OBJ and PLY read back with read_mesh, GLB parsed with tinygltf; positions against
// the octahedron's closed form, faces against the grid triangles, colours against the texel
// pattern through each file's own texture coordinates or colour attributes.
#include "io/io_test_util.h"

#include <hdm/core/error.h>
#include <hdm/io/export_mesh.h>
#include <hdm/io/read_mesh.h>
#include <hdm/slab/triangle_grid.h>

#include <tiny_gltf.h>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace hdm {
namespace {

using test::TempDir;

// Texel id at displacement sample s's grid point (texel (i·m, j·m) of any slab holding s: texels
// on shared grid points are shared, so the slab does not matter).
int texel_of_sample(const SlabModel& m, int s) {
  for (int slab = 0; slab < m.slab_count(); ++slab)
    for (int k = 0; k < m.samples.per_slab; ++k)
      if (m.samples.id(slab, k) == s) {
        const int i = m.samples.point_i[k] * m.texel_density, j = m.samples.point_j[k] * m.texel_density;
        return m.texels.id(slab, grid::index(m.texels.n, i, j));
      }
  ADD_FAILURE() << "sample " << s << " is in no slab";
  return 0;
}

std::array<int, 3> expected_rgb(const SlabModel& m, int s) {
  const Vec3f c = test::texel_colour(texel_of_sample(m, s));  // the octahedron model's pattern
  return {test::srgb8(c.x()), test::srgb8(c.y()), test::srgb8(c.z())};
}

// Closed form for the octahedron model: sample s lies on its projection line between 0.8·b and
// 1.2·b, b on the unit octahedron (|b|₁ = 1), so |p|₁ = 0.8 + 0.4·δ.
double expected_l1(const SlabModel& m, int s) { return 0.8 + 0.4 * double(m.displacement[s]); }

// Maps each of @p points to the sample at the same position (brute force); -1 if none within tol.
std::vector<int> match_samples(const SlabModel& m, const std::vector<Vec3>& points, double tol) {
  std::vector<int> out;
  for (const Vec3& p : points) {
    int best = -1;
    double best_d = tol;
    for (int s = 0; s < m.samples.count; ++s) {
      const double d = (sample_position(m, s) - p).norm();
      if (d <= best_d) best = s, best_d = d;
    }
    out.push_back(best);
  }
  return out;
}

// The model's grid triangles, as its sample layout lists them.
std::vector<Tri> all_triangles(const SlabModel& model) {
  std::vector<Tri> tris;
  model.samples.for_each_triangle([&](const Tri& t) { tris.push_back(t); });
  return tris;
}

std::vector<Tri> canonical(std::vector<Tri> tris) {
  for (Tri& t : tris) std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
  std::sort(tris.begin(), tris.end());
  return tris;
}

// Geometry checks shared by OBJ and PLY: one vertex per sample at its position (float precision,
// checked against the closed form too), and the faces are the grid triangles with their winding.
void check_surface(const SlabModel& model, const TriangleMesh& mesh) {
  ASSERT_EQ(mesh.vertices.size(), size_t(model.samples.count));
  ASSERT_EQ(mesh.faces.size(), size_t(model.samples.triangle_count()));
  const std::vector<int> sample = match_samples(model, mesh.vertices, 1e-6);
  std::vector<int> seen(model.samples.count, 0);
  for (size_t v = 0; v < sample.size(); ++v) {
    ASSERT_GE(sample[v], 0) << "vertex " << v << " matches no sample";
    ++seen[sample[v]];
    EXPECT_NEAR(mesh.vertices[v].lpNorm<1>(), expected_l1(model, sample[v]), 1e-6);
  }
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), model.samples.count) << "not one vertex per sample";
  std::vector<Tri> faces;
  for (const Tri& f : mesh.faces) faces.push_back({sample[f[0]], sample[f[1]], sample[f[2]]});
  EXPECT_EQ(canonical(faces), canonical(all_triangles(model)));
}

struct Image {
  int w = 0, h = 0;
  std::vector<uint8_t> rgba;
  std::array<int, 3> at_uv(float u, float v) const {  // nearest pixel, v = 0 at row 0
    const int x = std::clamp(int(u * w), 0, w - 1), y = std::clamp(int(v * h), 0, h - 1);
    const uint8_t* p = &rgba[(size_t(y) * w + x) * 4];
    return {p[0], p[1], p[2]};
  }
};

Image decode_png(const unsigned char* bytes, int size) {
  Image img;
  int channels = 0;
  unsigned char* p = stbi_load_from_memory(bytes, size, &img.w, &img.h, &channels, 4);
  EXPECT_NE(p, nullptr) << "PNG does not decode";
  if (p) img.rgba.assign(p, p + size_t(img.w) * img.h * 4);
  stbi_image_free(p);
  return img;
}

class Export : public ::testing::Test {
 protected:
  SlabModel model = test::octahedron_model();
  TempDir dir;
};

TEST_F(Export, ObjReadsBackAndItsUvsPointAtTheTexelColours) {
  const std::string path = dir.file("surface.obj");
  export_mesh(model, path);
  const std::vector<std::string> files = export_files(path);
  ASSERT_EQ(files.size(), 3u);
  for (const std::string& f : files) {
    EXPECT_TRUE(std::filesystem::exists(f)) << f;
    EXPECT_FALSE(std::filesystem::exists(f + ".tmp")) << f;
  }
  check_surface(model, read_mesh(path));

  // The MTL names the PNG; the PNG decodes.
  std::ifstream mtl(dir.file("surface.mtl"));
  const std::string mtl_text((std::istreambuf_iterator<char>(mtl)), std::istreambuf_iterator<char>());
  EXPECT_NE(mtl_text.find("map_Kd surface.png"), std::string::npos);
  const std::vector<uint8_t> png = test::read_bytes(dir.file("surface.png"));
  const Image img = decode_png(png.data(), int(png.size()));

  // Parse v, vt and f ourselves: the colour under each corner's vt is its sample's texel colour.
  std::ifstream in(path);
  std::string line;
  std::vector<Vec3> v;
  std::vector<std::array<float, 2>> vt;
  size_t corners = 0;
  bool mtllib = false;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string key;
    s >> key;
    if (key == "mtllib") mtllib = line == "mtllib surface.mtl";
    if (key == "v") {
      Vec3 p;
      s >> p.x() >> p.y() >> p.z();
      v.push_back(p);
    } else if (key == "vt") {
      std::array<float, 2> t;
      s >> t[0] >> t[1];
      vt.push_back(t);
    } else if (key == "f") {
      std::string corner;
      while (s >> corner) {
        int iv = 0, it = 0, in_ = 0;
        ASSERT_EQ(std::sscanf(corner.c_str(), "%d/%d/%d", &iv, &it, &in_), 3) << corner;
        ASSERT_EQ(iv, in_) << "normals are per sample";
        const int sample = match_samples(model, {v.at(iv - 1)}, 1e-9)[0];
        ASSERT_GE(sample, 0);
        const auto& t = vt.at(it - 1);
        EXPECT_EQ(img.at_uv(t[0], 1.0f - t[1]), expected_rgb(model, sample)) << "corner " << corner;
        ++corners;
      }
    }
  }
  EXPECT_TRUE(mtllib);
  EXPECT_EQ(v.size(), size_t(model.samples.count));
  EXPECT_EQ(vt.size(), size_t(model.slab_count() * model.samples.per_slab));
  EXPECT_EQ(corners, 3 * size_t(model.samples.triangle_count()));
}

TEST_F(Export, PlyReadsBackWithNormalsAndColours) {
  const std::string path = dir.file("surface.ply");
  export_mesh(model, path);
  check_surface(model, read_mesh(path));

  // Decode the binary body with the header the docs promise.
  const std::vector<uint8_t> b = test::read_bytes(path);
  const std::string text(b.begin(), b.end());
  const std::string header = "ply\nformat binary_little_endian 1.0\n";
  ASSERT_EQ(text.compare(0, header.size(), header), 0);
  const size_t body = text.find("end_header\n") + 11;
  const std::string head = text.substr(0, body);
  for (const char* p : {"property float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\n"
                        "property float nz\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n",
                        "property list uchar int vertex_indices\n"})
    EXPECT_NE(head.find(p), std::string::npos) << p;
  EXPECT_NE(head.find("element vertex " + std::to_string(model.samples.count) + "\n"), std::string::npos);
  ASSERT_EQ(b.size(), body + size_t(model.samples.count) * 27 + size_t(model.samples.triangle_count()) * 13);
  for (int v = 0; v < model.samples.count; ++v) {
    const uint8_t* rec = &b[body + size_t(v) * 27];
    float f[6];
    std::memcpy(f, rec, sizeof(f));
    const int s = match_samples(model, {Vec3(f[0], f[1], f[2])}, 1e-6)[0];
    ASSERT_GE(s, 0);
    EXPECT_NEAR(Vec3(f[3], f[4], f[5]).norm(), 1.0, 1e-5);
    EXPECT_EQ(Vec3f(f[3], f[4], f[5]), sample_normal(model, s).normalized());
    EXPECT_EQ((std::array<int, 3>{rec[24], rec[25], rec[26]}), expected_rgb(model, s)) << "sample " << s;
  }
}

TEST_F(Export, GlbParsesBackWithTinyGltf) {
  const std::string path = dir.file("surface.glb");
  export_mesh(model, path);
  tinygltf::Model g;
  tinygltf::TinyGLTF loader;
  std::string err, warn;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&g, &err, &warn, path)) << err;
  EXPECT_TRUE(err.empty()) << err;
  ASSERT_EQ(g.meshes.size(), 1u);
  ASSERT_EQ(g.meshes[0].primitives.size(), 1u);
  const tinygltf::Primitive& prim = g.meshes[0].primitives[0];
  EXPECT_EQ(prim.mode, TINYGLTF_MODE_TRIANGLES);
  for (const char* a : {"POSITION", "NORMAL", "TEXCOORD_0"}) ASSERT_TRUE(prim.attributes.count(a)) << a;

  // Reads accessor `index` as `components` floats (or uint32 indices) per element.
  auto data_of = [&](int index, int component_type, size_t components) {
    const tinygltf::Accessor& acc = g.accessors.at(index);
    EXPECT_EQ(acc.componentType, component_type);
    const tinygltf::BufferView& view = g.bufferViews.at(acc.bufferView);
    const unsigned char* p = g.buffers.at(view.buffer).data.data() + view.byteOffset + acc.byteOffset;
    EXPECT_LE(view.byteOffset + acc.byteOffset + acc.count * components * 4, g.buffers[view.buffer].data.size());
    return std::make_pair(p, acc.count);
  };
  const auto [pos, V] = data_of(prim.attributes.at("POSITION"), TINYGLTF_COMPONENT_TYPE_FLOAT, 3);
  const auto [nrm, Vn] = data_of(prim.attributes.at("NORMAL"), TINYGLTF_COMPONENT_TYPE_FLOAT, 3);
  const auto [uvs, Vt] = data_of(prim.attributes.at("TEXCOORD_0"), TINYGLTF_COMPONENT_TYPE_FLOAT, 2);
  const auto [idx, I] = data_of(prim.indices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, 1);
  EXPECT_EQ(V, size_t(model.slab_count() * model.samples.per_slab)) << "vertices are duplicated per slab";
  EXPECT_EQ(Vn, V);
  EXPECT_EQ(Vt, V);
  ASSERT_EQ(I, 3 * size_t(model.samples.triangle_count()));

  // Material -> texture -> embedded PNG image, decoded by tinygltf.
  ASSERT_EQ(prim.material, 0);
  const int tex = g.materials.at(0).pbrMetallicRoughness.baseColorTexture.index;
  ASSERT_GE(tex, 0);
  const tinygltf::Image& gi = g.images.at(g.textures.at(tex).source);
  EXPECT_EQ(gi.mimeType, "image/png");
  EXPECT_GE(gi.bufferView, 0) << "the image must be embedded";
  ASSERT_EQ(gi.component, 4);
  Image img{gi.width, gi.height, gi.image};

  std::vector<Vec3> points(V);
  std::vector<int> sample(V);
  for (size_t v = 0; v < V; ++v) {
    float p[3], n[3], t[2];
    std::memcpy(p, pos + 12 * v, 12);
    std::memcpy(n, nrm + 12 * v, 12);
    std::memcpy(t, uvs + 8 * v, 8);
    sample[v] = match_samples(model, {Vec3(p[0], p[1], p[2])}, 1e-6)[0];
    ASSERT_GE(sample[v], 0) << "vertex " << v;
    EXPECT_NEAR(Vec3(p[0], p[1], p[2]).lpNorm<1>(), expected_l1(model, sample[v]), 1e-6);
    EXPECT_EQ(Vec3f(n[0], n[1], n[2]), sample_normal(model, sample[v]).normalized());
    EXPECT_EQ(img.at_uv(t[0], t[1]), expected_rgb(model, sample[v])) << "vertex " << v;
  }
  std::vector<Tri> faces;
  for (size_t k = 0; k < I; k += 3) {
    uint32_t t[3];
    std::memcpy(t, idx + 4 * k, 12);
    for (uint32_t i : t) ASSERT_LT(i, V);
    faces.push_back({sample[t[0]], sample[t[1]], sample[t[2]]});
  }
  EXPECT_EQ(canonical(faces), canonical(all_triangles(model)));
}

TEST_F(Export, UnsupportedExtensionThrowsInvalidInputNamingThePath) {
  const std::string path = dir.file("surface.fbx");
  try {
    export_mesh(model, path);
    ADD_FAILURE() << "no exception";
  } catch (const InvalidInput& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    for (const char* ext : {".obj", ".ply", ".glb"}) EXPECT_NE(msg.find(ext), std::string::npos) << msg;
  }
  EXPECT_FALSE(std::filesystem::exists(path));
}

TEST_F(Export, UnwritableDestinationThrowsIoError) {
  EXPECT_THROW(export_mesh(model, dir.file("no/such/dir/surface.ply")), IoError);
}

}  // namespace
}  // namespace hdm
