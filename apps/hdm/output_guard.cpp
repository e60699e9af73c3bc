// SPDX-License-Identifier: MIT
#include "output_guard.h"

#include <hdm/core/error.h>

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace hdm::app {
namespace {

struct Id {
  bool exists = false;
  dev_t dev = 0;
  ino_t ino = 0;
};

Id id_of(const std::string& path) {
  struct stat st{};
  if (path.empty() || ::stat(path.c_str(), &st) != 0) return {};
  return {true, st.st_dev, st.st_ino};
}

bool same(const Id& a, const Id& b) { return a.exists && b.exists && a.dev == b.dev && a.ino == b.ino; }

}  // namespace

void check_outputs(const std::vector<std::string>& outputs, const std::vector<std::string>& inputs,
                   const char* option) {
  for (size_t k = 0; k < outputs.size(); ++k) {
    const Id out = id_of(outputs[k]);
    if (!out.exists) continue;
    for (const std::string& in : inputs)
      if (same(out, id_of(in)))
        throw InvalidInput(std::string(option) + " " + outputs[k] + ": this is the input file " + in +
                           " (writing it would destroy the input); choose another output");
    for (size_t j = 0; j < k; ++j)
      if (same(out, id_of(outputs[j])))
        throw InvalidInput(std::string(option) + " " + outputs[k] + ": the same file as the output " + outputs[j]);
  }
}

void check_model_output(const std::string& path, const char* option) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  static const char* const meshes[] = {".obj", ".ply", ".off", ".stl", ".glb", ".gltf", ".fbx", ".dae",
                                       ".3ds", ".x3d", ".wrl", ".mtl", ".png", ".csv", ".json"};
  for (const char* m : meshes)
    if (ext == m)
      throw InvalidInput(std::string(option) + " " + path + ": a slab model is written there, but '" + ext +
                         "' is the extension of another format; name the model .hdm (hdm export writes meshes)");
}

}  // namespace hdm::app
