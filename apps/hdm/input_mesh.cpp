// SPDX-License-Identifier: MIT
#include "input_mesh.h"

#include <hdm/io/read_mesh.h>

#include <cstdio>

namespace hdm::app {

PrepareOptions InputOptions::prepare() const {
  PrepareOptions p;
  p.repair = !no_repair;
  p.max_hole_edges = max_hole_edges;
  p.max_hole_size = max_hole_size;
  return p;
}

void add_input_options(CLI::App& cmd, InputOptions& o) {
  cmd.add_flag("--no-repair", o.no_repair,
               "refuse a dirty mesh (non-manifold or inconsistent edges) instead of repairing it");
  cmd.add_option("--max-hole", o.max_hole_edges, "fill boundary cycles of at most this many edges (default 64)")
      ->check(CLI::Range(0, 1 << 20));
  cmd.add_option("--max-hole-size", o.max_hole_size,
                 "... and whose extent is at most this fraction of the diagonal (default 0.05)")
      ->check(CLI::Range(0.0, 10.0));
}

TriangleMesh read_input(const std::string& path, uint64_t max_file_bytes) {
  MeshReadReport read;
  TriangleMesh mesh = read_mesh(path, {max_file_bytes}, &read);
  for (const std::string& w : read.warnings) std::fprintf(stderr, "hdm: warning: %s\n", w.c_str());
  return mesh;
}

}  // namespace hdm::app
