// SPDX-License-Identifier: MIT
#include "input_mesh.h"

#include <hdm/io/read_mesh.h>

namespace hdm::app {

void add_input_options(CLI::App& cmd, InputOptions& o) {
  cmd.add_flag("--no-repair", o.no_repair,
               "refuse a dirty mesh (non-manifold or inconsistent edges) instead of repairing it");
  cmd.add_option("--max-hole", o.max_hole_edges, "fill boundary cycles of at most this many edges (default 64)")
      ->check(CLI::Range(0, 1 << 20));
  cmd.add_option("--max-hole-size", o.max_hole_size,
                 "... and whose extent is at most this fraction of the diagonal (default 0.05)")
      ->check(CLI::Range(0.0, 10.0));
}

PreparedInput prepare_input(const std::string& path, const InputOptions& o, uint64_t max_file_bytes, bool resolve) {
  PreparedInput in;
  in.mesh = read_mesh(path, {max_file_bytes});
  if (o.no_repair) {
    validate_for_bake(in.mesh, path);
  } else if (needs_repair(in.mesh)) {
    RepairOptions ro;
    ro.max_hole_edges = o.max_hole_edges;
    ro.max_hole_size = o.max_hole_size;
    in.mesh = repair_mesh(in.mesh, path, ro, &in.repair);
  }
  in.orient = orient_outward(in.mesh);
  in.self_intersections = count_self_intersections(in.mesh);
  if (resolve && in.self_intersections > 0) in.mesh = resolve_self_intersections(in.mesh, &in.resolved);
  return in;
}

}  // namespace hdm::app
