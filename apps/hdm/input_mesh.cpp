// SPDX-License-Identifier: MIT
#include "input_mesh.h"

#include <hdm/io/read_mesh.h>
#include <hdm/mesh/remove_folds.h>
#include <hdm/mesh/stitch_seams.h>

#include <cstdio>

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
  MeshReadReport read;
  in.mesh = read_mesh(path, {max_file_bytes}, &read);
  for (const std::string& w : read.warnings) std::fprintf(stderr, "hdm: warning: %s\n", w.c_str());
  in.read_warnings = std::move(read.warnings);
  in.scale_exponent = scale_exponent(bounds(in.mesh).diagonal(), path);
  scale_mesh(in.mesh, in.scale_exponent);
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
  bool open = in.orient.nearly_closed + in.orient.sheets > 0;  // some part has a boundary edge
  // Open patches that cross where they should meet (CAD patch soups, game assets in parts) are
  // first joined at their seams and oriented as one surface, for the bake and the check alike.
  bool closed_by_seams = false;
  if (in.self_intersections > 0 && open) {
    TriangleMesh joined = stitch_seams(in.mesh, &in.seams);
    if (in.seams.inserted + in.seams.snapped > 0) {
      orient_outward(joined);  // in.orient keeps the report of the input's own parts
      in.mesh = std::move(joined);
      closed_by_seams = in.seams.boundary_edges_after == 0;
      open = !closed_by_seams;
      in.resolved.seam_vertices = in.seams.inserted + in.seams.snapped;
    }
  }
  // A nearly closed input that crosses itself (a bust with an open base) is the solid it nearly
  // bounds: its holes are filled for the bake and the check alike, so the check measures the caps
  // the model has, and the buried faces are those inside that solid.
  int64_t filled_faces = 0;
  if (in.self_intersections > 0 && open) {
    TriangleMesh filled = fill_nearly_closed(in.mesh);
    if (!filled.faces.empty()) {  // only returned closed
      filled_faces = static_cast<int64_t>(filled.faces.size() - in.mesh.faces.size());
      in.mesh = std::move(filled);
      open = false;
    }
  }
  // An open sheet's folds (a reconstructed scan's flaps and crumples: no valid slab, no single-valued
  // displacement there) are removed, for the bake and the check alike; after the seams are joined,
  // so that a seam between patches is not taken for a fold.
  if (open) in.folds = remove_folds(in.mesh);
  if (resolve && in.self_intersections > 0) {
    if (closed_by_seams) {
      // Closed now; what still crosses (folds inside a patch) stays as the input has it: CGAL
      // 5.5's refinement of a closed union crashes on some such surfaces.
      in.resolved.pairs_before = in.self_intersections;
      in.resolved.pairs_after = count_self_intersections(in.mesh);
    } else {
      in.mesh = resolve_self_intersections(in.mesh, &in.resolved);
      if (in.seams.inserted + in.seams.snapped > 0) in.resolved.seam_vertices = in.seams.inserted + in.seams.snapped;
      in.resolved.filled_faces = filled_faces;
    }
  }
  return in;
}

}  // namespace hdm::app
