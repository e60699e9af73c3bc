// SPDX-License-Identifier: MIT
#pragma once
// The input mesh as `hdm bake` prepares it, shared by `hdm check` so that both measure the same
// surface: read, repair a dirty scan (unless refused), orient every part outward.
#include <hdm/mesh/orient_mesh.h>
#include <hdm/mesh/scale_mesh.h>
#include <hdm/mesh/remove_folds.h>
#include <hdm/mesh/self_intersections.h>
#include <hdm/mesh/repair_mesh.h>
#include <hdm/mesh/stitch_seams.h>

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace hdm::app {

struct InputOptions {
  bool no_repair = false;       // refuse a dirty mesh instead of repairing it
  int max_hole_edges = 64;      // RepairOptions::max_hole_edges
  double max_hole_size = 0.05;  // RepairOptions::max_hole_size
};

struct PreparedInput {
  TriangleMesh mesh;      // scaled by 2^scale_exponent (diagonal in [1, 2)): every step works at one size
  int scale_exponent = 0;  // scale_exponent() of the mesh as read; scale_model(m, -k) gives the input's units
  std::vector<std::string> read_warnings;  // what read_mesh() skipped (MeshReadReport)
  RepairReport repair;
  OrientReport orient;
  FoldReport folds;                 // open input: what remove_folds() did
  int64_t self_intersections = 0;   // face pairs of the mesh (as read, repaired and oriented) that cross
  SeamReport seams;                 // open input that crosses itself: what stitch_seams() joined
  SelfIntersectionReport resolved;  // with `resolve`: what resolve_self_intersections() did
};

// Adds --no-repair, --max-hole and --max-hole-size to @p cmd.
void add_input_options(CLI::App& cmd, InputOptions& o);

// Reads @p path, normalises its scale by a power of two (scale_mesh(), exact; refused outside
// [kMinDiagonal, kMaxDiagonal]), repairs it when needs_repair() (validate_for_bake() with --no-repair), then
// orient_outward(), and counts its self-intersections. An open mesh that crosses itself is then
// stitched at its seams (stitch_seams()) and oriented again as one surface, for `hdm bake` and
// `hdm check` alike (the same orientation, so the same buried faces). With @p resolve, replaces
// the mesh by resolve_self_intersections() of it (what `hdm bake` bakes; `hdm check` measures
// against the mesh before that), except when stitching closed it. @p max_file_bytes is read_mesh()'s size limit. Throws
// what read_mesh() and repair_mesh() throw. Prints read_mesh()'s warnings to stderr ("hdm: warning:
// ..."), the one place the program does.
PreparedInput prepare_input(const std::string& path, const InputOptions& o, uint64_t max_file_bytes,
                            bool resolve = false);

}  // namespace hdm::app
