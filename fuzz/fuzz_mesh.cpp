// SPDX-License-Identifier: MIT
// libFuzzer target for one mesh reader: the format is the extension of HDM_FUZZ_FILE (fuzz.obj,
// fuzz.ply, fuzz.off, fuzz.stl). A documented error (IoError, InvalidInput) is a pass; anything
// else (a crash, another exception, a sanitizer report, a leak, a hang, an allocation beyond
// libFuzzer's limit) or a mesh that breaks read_mesh()'s promises is a finding.
#include <hdm/core/error.h>
#include <hdm/io/read_mesh.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  hdm::TriangleMesh mesh;
  hdm::MeshReadReport report;
  try {
    mesh = hdm::read_mesh_from_memory({reinterpret_cast<const char*>(data), size}, HDM_FUZZ_FILE, {}, &report);
  } catch (const hdm::IoError&) {
    return 0;
  } catch (const hdm::InvalidInput&) {
    return 0;
  }
  // What read_mesh() promises: triangles, ids in range, every vertex used, finite coordinates; a
  // few warnings (one per kind of thing skipped, at most six for PLY header lines), each naming
  // the file.
  if (mesh.faces.empty() || report.warnings.size() > 16) __builtin_trap();
  for (const std::string& w : report.warnings)
    if (w.rfind(HDM_FUZZ_FILE, 0) != 0) __builtin_trap();
  std::vector<char> used(mesh.vertices.size(), 0);
  for (const hdm::Tri& f : mesh.faces)
    for (int32_t v : f) {
      if (v < 0 || static_cast<size_t>(v) >= mesh.vertices.size()) __builtin_trap();
      used[v] = 1;
    }
  for (size_t v = 0; v < mesh.vertices.size(); ++v)
    if (!used[v] || !mesh.vertices[v].allFinite()) __builtin_trap();
  return 0;
}
