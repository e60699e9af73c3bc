// SPDX-License-Identifier: MIT
// read_mesh: the size limit, the choice of reader (mesh_format.h), and the assimp fallback for the
// formats hdm does not read itself.
#include <hdm/core/error.h>
#include <hdm/io/read_mesh.h>

#include "mesh_format.h"
#include "polygon_soup.h"
#include "text_cursor.h"

#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <string>
#include <unordered_map>
#include <vector>

namespace hdm {
namespace {

using io::detail::with_commas;

std::string lower_extension(const std::string& name) {
  std::string ext = std::filesystem::path(name).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// ---- the assimp fallback (formats other than OBJ, PLY, OFF, STL) ----

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

// Reads with assimp from @p path, or from @p bytes when it is not null (hint: the extension).
const aiScene& import_scene(Assimp::Importer& importer, const std::string& path, const std::string_view* bytes) {
  // Drop every per-vertex attribute but the position, so JoinIdenticalVertices welds by position.
  importer.SetPropertyInteger(AI_CONFIG_PP_RVC_FLAGS, aiComponent_NORMALS | aiComponent_TANGENTS_AND_BITANGENTS |
                                                          aiComponent_COLORS | aiComponent_TEXCOORDS |
                                                          aiComponent_BONEWEIGHTS);
  const aiScene* scene = nullptr;
  try {
    if (bytes) {
      const std::string ext = lower_extension(path);
      scene = importer.ReadFileFromMemory(bytes->data(), bytes->size(), 0, ext.empty() ? "" : ext.c_str() + 1);
    } else {
      scene = importer.ReadFile(path, 0);
    }
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
  return *scene;
}

TriangleMesh from_scene(const aiScene& scene, const std::string& path, std::vector<std::string>& warnings) {
  TriangleMesh mesh;
  std::unordered_map<PositionKey, int32_t, PositionKeyHash> welded;
  uint64_t other_faces = 0, total_faces = 0, total_vertices = 0;
  std::vector<int32_t> remap;
  for (unsigned m = 0; m < scene.mNumMeshes; ++m) {
    const aiMesh& am = *scene.mMeshes[m];
    total_faces += am.mNumFaces;
    total_vertices += am.mNumVertices;
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
  if (mesh.faces.empty())
    throw InvalidInput(path + ": holds no triangles: " +
                       (other_faces > 0 ? with_commas(other_faces) + " points and line segments" : "no faces") + " (" +
                       with_commas(total_vertices) + " vertices)");
  if (other_faces > 0)
    warnings.push_back(path + ": skipped " + with_commas(other_faces) + " of " + with_commas(total_faces) +
                       " faces: they are points or line segments, which bound no area");
  return mesh;
}

TriangleMesh read_with_assimp(const std::string& path, const std::string_view* bytes,
                              std::vector<std::string>& warnings) {
  Assimp::Importer importer;
  return from_scene(import_scene(importer, path, bytes), path, warnings);
}

}  // namespace

TriangleMesh read_mesh_from_memory(std::string_view bytes, const std::string& name, const MeshReadOptions& options,
                                   MeshReadReport* report) {
  check_input_size(bytes.size(), options.max_file_bytes, name);
  if (bytes.empty()) throw IoError(name + ": empty file");
  std::vector<std::string> warnings;
  auto done = [&](TriangleMesh mesh) {
    if (report) report->warnings.insert(report->warnings.end(), warnings.begin(), warnings.end());
    return mesh;
  };
  io::detail::MeshFormat format = io::detail::format_by_extension(name);
  if (format == io::detail::MeshFormat::Other && io::detail::has_no_extension(name))
    format = io::detail::format_by_content(bytes);
  switch (format) {
    case io::detail::MeshFormat::Obj:
      return done(io::detail::to_triangle_mesh(io::detail::parse_obj(bytes, name), name, warnings));
    case io::detail::MeshFormat::Ply:
      return done(io::detail::to_triangle_mesh(io::detail::parse_ply(bytes, name), name, warnings));
    case io::detail::MeshFormat::Off:
      return done(io::detail::to_triangle_mesh(io::detail::parse_off(bytes, name), name, warnings));
    case io::detail::MeshFormat::Stl:
      return done(io::detail::to_triangle_mesh(io::detail::parse_stl(bytes, name), name, warnings));
    case io::detail::MeshFormat::Other:
      break;
  }
  return done(read_with_assimp(name, &bytes, warnings));
}

TriangleMesh read_mesh(const std::string& path, const MeshReadOptions& options, MeshReadReport* report) {
  if (io::detail::format_by_extension(path) == io::detail::MeshFormat::Other) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw IoError(path + ": no such file");
    if (!std::filesystem::is_regular_file(path, ec)) throw IoError(path + ": not a regular file");
    check_input_size(std::filesystem::file_size(path, ec), options.max_file_bytes, path);
    // Without an extension the content decides; a format of hdm's own is read from memory.
    if (io::detail::has_no_extension(path)) {
      const std::string bytes = read_file(path, options.max_file_bytes);
      if (io::detail::format_by_content(bytes) != io::detail::MeshFormat::Other)
        return read_mesh_from_memory(bytes, path, options, report);
    }
    // assimp reads the file itself, so formats that refer to other files (glTF buffers) work.
    std::vector<std::string> warnings;
    TriangleMesh mesh = read_with_assimp(path, nullptr, warnings);
    if (report) report->warnings.insert(report->warnings.end(), warnings.begin(), warnings.end());
    return mesh;
  }
  const std::string bytes = read_file(path, options.max_file_bytes);
  return read_mesh_from_memory(bytes, path, options, report);
}

}  // namespace hdm
