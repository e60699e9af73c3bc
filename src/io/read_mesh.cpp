// SPDX-License-Identifier: MIT
#include <hdm/core/error.h>
#include <hdm/io/read_mesh.h>

#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <bit>
#include <cmath>
#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <string_view>
#include <exception>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

namespace hdm {
namespace {

// Exact-position key for welding across assimp meshes; +0.0 folds -0 into +0 like operator==.
struct PositionKey {
  uint64_t x, y, z;
  bool operator==(const PositionKey&) const = default;
};
struct PositionKeyHash {
  size_t operator()(const PositionKey& k) const noexcept {
    uint64_t h = k.x * 0x9E3779B97F4A7C15ull;
    h ^= k.y + 0x7F4A7C159E3779B9ull + (h << 6) + (h >> 2);
    h ^= k.z + 0x94D049BB133111EBull + (h << 6) + (h >> 2);
    return static_cast<size_t>(h);
  }
};
PositionKey key_of(const Vec3& p) {
  return {std::bit_cast<uint64_t>(p.x() + 0.0), std::bit_cast<uint64_t>(p.y() + 0.0),
          std::bit_cast<uint64_t>(p.z() + 0.0)};
}

// ---- PLY pre-check: assimp 5.2 loops forever on a PLY header without end_header and reads past
// the end of a truncated binary body, so the sizes are checked here first ----

struct PlyProperty {
  int size = 0;       // bytes of a scalar property or of a list's items
  int count_size = 0; // bytes of a list's count, 0 for a scalar
  bool count_signed = false;
};
struct PlyElement {
  std::string name;
  uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

int ply_type_size(const std::string& t, bool* is_signed = nullptr) {
  if (is_signed) *is_signed = t == "char" || t == "int8" || t == "short" || t == "int16" || t == "int" || t == "int32";
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "int32" || t == "uint32" || t == "float" || t == "float32") return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}

uint64_t read_ply_count(const unsigned char* p, const PlyProperty& prop, bool big_endian) {
  uint64_t bits = 0;
  for (int k = 0; k < prop.count_size; ++k)
    bits |= static_cast<uint64_t>(p[big_endian ? prop.count_size - 1 - k : k]) << (8 * k);
  if (prop.count_signed && (bits >> (8 * prop.count_size - 1)) != 0) return UINT64_MAX;  // negative
  return bits;
}

void check_ply(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string data(4, '\0');
  if (!in.read(data.data(), 4) || data.compare(0, 3, "ply") != 0 || (data[3] != '\n' && data[3] != '\r')) return;
  data.append(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());  // only PLY files are read twice
  const size_t end = data.find("end_header");
  const size_t body = end == std::string::npos ? end : data.find('\n', end);
  if (body == std::string::npos) throw IoError(path + ": truncated (the PLY header has no end_header line)");

  std::istringstream header(data.substr(0, end));
  std::string line, format;
  std::vector<PlyElement> elements;
  auto malformed = [&] { return IoError(path + ": malformed PLY header line \"" + line + "\""); };
  while (std::getline(header, line)) {
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "format") {
      words >> format;
    } else if (key == "element") {
      PlyElement e;
      if (!(words >> e.name >> e.count)) throw malformed();
      elements.push_back(e);
    } else if (key == "property") {
      std::string type, count_type, item_type;
      if (!(words >> type) || elements.empty()) throw malformed();
      PlyProperty prop;
      if (type == "list") {
        if (!(words >> count_type >> item_type)) throw malformed();
        prop.count_size = ply_type_size(count_type, &prop.count_signed);
        prop.size = ply_type_size(item_type);
        if (prop.count_size == 0) throw malformed();
      } else {
        prop.size = ply_type_size(type);
      }
      if (prop.size == 0) throw malformed();
      elements.back().properties.push_back(prop);
    }
  }

  const std::string what = path + ": truncated (PLY data ends inside element ";
  if (format == "ascii") {
    size_t pos = body + 1;
    auto next_token = [&](const PlyElement& e, uint64_t k) {
      while (pos < data.size() && std::isspace(static_cast<unsigned char>(data[pos]))) ++pos;
      if (pos >= data.size()) throw IoError(what + e.name + " " + std::to_string(k) + ")");
      const size_t start = pos;
      while (pos < data.size() && !std::isspace(static_cast<unsigned char>(data[pos]))) ++pos;
      return std::string_view(data).substr(start, pos - start);
    };
    for (const PlyElement& e : elements) {
      if (e.properties.empty()) continue;
      for (uint64_t k = 0; k < e.count; ++k)  // every instance consumes a token: bounded by the file
        for (const PlyProperty& prop : e.properties) {
          const std::string_view t = next_token(e, k);
          if (prop.count_size == 0) continue;
          const long long n = std::strtoll(std::string(t).c_str(), nullptr, 10);
          for (long long j = 0; j < n; ++j) next_token(e, k);
        }
    }
  } else if (format == "binary_little_endian" || format == "binary_big_endian") {
    const bool big = format == "binary_big_endian";
    const auto* bytes = reinterpret_cast<const unsigned char*>(data.data());
    uint64_t pos = body + 1;
    const uint64_t size = data.size();
    for (const PlyElement& e : elements) {
      bool has_list = false;
      uint64_t stride = 0;
      for (const PlyProperty& prop : e.properties) {
        has_list = has_list || prop.count_size > 0;
        stride += prop.size;
      }
      if (!has_list) {
        if (stride > 0 && e.count > (size - pos) / stride)
          throw IoError(what + e.name + ": " + std::to_string(e.count) + " declared)");
        pos += e.count * stride;
        continue;
      }
      for (uint64_t k = 0; k < e.count; ++k)  // every instance consumes bytes: bounded by the file
        for (const PlyProperty& prop : e.properties) {
          uint64_t need = prop.count_size ? prop.count_size : prop.size;
          if (need > size - pos) throw IoError(what + e.name + " " + std::to_string(k) + ")");
          if (prop.count_size) {
            const uint64_t n = read_ply_count(bytes + pos, prop, big);
            if (n > (size - pos - need) / prop.size) throw IoError(what + e.name + " " + std::to_string(k) + ")");
            need += n * prop.size;
          }
          pos += need;
        }
    }
  } else {
    throw IoError(path + ": unknown PLY format \"" + format + "\"");
  }
}

// Checks the raw scene before post-processing: assimp's steps assert (abort) on faces without
// indices, which a truncated file can leave behind, and its vertex welding is not meant for NaN.
void check_raw_scene(const aiScene& scene, const std::string& path) {
  if (scene.mNumMeshes > 0 && !scene.mMeshes) throw IoError(path + ": corrupt (no mesh data)");
  for (unsigned m = 0; m < scene.mNumMeshes; ++m) {
    if (!scene.mMeshes[m]) throw IoError(path + ": corrupt (no mesh data)");
    const aiMesh& mesh = *scene.mMeshes[m];
    if ((mesh.mNumVertices > 0 && !mesh.mVertices) || (mesh.mNumFaces > 0 && !mesh.mFaces))
      throw IoError(path + ": corrupt (missing vertex or face data)");
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices == 0 || !face.mIndices)
        throw IoError(path + ": truncated or corrupt (face " + std::to_string(f) + " has no vertices)");
      for (unsigned k = 0; k < face.mNumIndices; ++k)
        if (face.mIndices[k] >= mesh.mNumVertices)
          throw IoError(path + ": truncated or corrupt (face " + std::to_string(f) + " refers to vertex " +
                        std::to_string(face.mIndices[k]) + " of " + std::to_string(mesh.mNumVertices) + ")");
    }
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const aiVector3D& p = mesh.mVertices[v];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        throw InvalidInput(path + ": vertex " + std::to_string(v) + " has a non-finite coordinate");
    }
  }
}

const aiScene* import_scene(Assimp::Importer& importer, const std::string& path) {
  // Drop every per-vertex attribute but the position, so JoinIdenticalVertices welds by position.
  importer.SetPropertyInteger(AI_CONFIG_PP_RVC_FLAGS,
                              aiComponent_NORMALS | aiComponent_TANGENTS_AND_BITANGENTS | aiComponent_COLORS |
                                  aiComponent_TEXCOORDS | aiComponent_BONEWEIGHTS);
  const aiScene* scene = nullptr;
  try {
    scene = importer.ReadFile(path, 0);
    if (!scene) throw IoError(path + ": " + importer.GetErrorString());
    check_raw_scene(*scene, path);
    scene = importer.ApplyPostProcessing(aiProcess_RemoveComponent | aiProcess_Triangulate |
                                         aiProcess_JoinIdenticalVertices);
    if (!scene) throw IoError(path + ": " + importer.GetErrorString());
  } catch (const IoError&) {
    throw;
  } catch (const InvalidInput&) {
    throw;
  } catch (const std::exception& e) {  // assimp builds without its global catch let errors escape
    throw IoError(path + ": " + e.what());
  }
  return scene;
}

}  // namespace

TriangleMesh read_mesh(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw IoError(path + ": no such file");
  if (!std::filesystem::is_regular_file(path, ec)) throw IoError(path + ": not a regular file");

  check_ply(path);
  Assimp::Importer importer;
  const aiScene& scene = *import_scene(importer, path);

  TriangleMesh mesh;
  std::unordered_map<PositionKey, int32_t, PositionKeyHash> welded;
  size_t other_faces = 0, total_faces = 0;
  std::vector<int32_t> remap;
  for (unsigned m = 0; m < scene.mNumMeshes; ++m) {
    const aiMesh& am = *scene.mMeshes[m];
    total_faces += am.mNumFaces;
    // Mark the vertices that triangles use; -2 = unused, -1 = used but not yet numbered.
    remap.assign(am.mNumVertices, -2);
    for (unsigned f = 0; f < am.mNumFaces; ++f) {
      const aiFace& face = am.mFaces[f];
      if (face.mNumIndices != 3) {
        ++other_faces;
        continue;
      }
      for (unsigned k = 0; k < 3; ++k) {
        if (face.mIndices[k] >= am.mNumVertices) throw IoError(path + ": corrupt (face refers to a missing vertex)");
        remap[face.mIndices[k]] = -1;
      }
    }
    for (unsigned v = 0; v < am.mNumVertices; ++v) {
      if (remap[v] == -2) continue;
      const aiVector3D& a = am.mVertices[v];
      const Vec3 p(static_cast<double>(a.x), static_cast<double>(a.y), static_cast<double>(a.z));
      const auto [it, fresh] = welded.try_emplace(key_of(p), static_cast<int32_t>(mesh.vertices.size()));
      if (fresh) mesh.vertices.push_back(p);
      remap[v] = it->second;
    }
    for (unsigned f = 0; f < am.mNumFaces; ++f) {
      const aiFace& face = am.mFaces[f];
      if (face.mNumIndices == 3)
        mesh.faces.push_back({remap[face.mIndices[0]], remap[face.mIndices[1]], remap[face.mIndices[2]]});
    }
  }
  if (other_faces > 0)
    throw InvalidInput(path + ": " + std::to_string(other_faces) + " of " + std::to_string(total_faces) +
                       " faces are points or line segments, not triangles");
  if (mesh.faces.empty()) throw InvalidInput(path + ": holds no triangles");
  return mesh;
}

}  // namespace hdm
