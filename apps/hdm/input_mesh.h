// SPDX-License-Identifier: MIT
#pragma once
// The one place the `hdm` program (and the studio) reads an input mesh, printing read_mesh()'s
// warnings as "hdm: warning: ...", and the command-line options of its preparation
// (prepare_input(), bake_input()).
#include <hdm/mesh/triangle_mesh.h>
#include <hdm/pipeline/prepare_input.h>

#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>

namespace hdm::app {

struct InputOptions {
  bool no_repair = false;       // refuse a dirty mesh instead of repairing it
  int max_hole_edges = 64;      // RepairOptions::max_hole_edges
  double max_hole_size = 0.05;  // RepairOptions::max_hole_size
  // The same choices as prepare_input() takes them (resolve on: what a bake follows).
  PrepareOptions prepare() const;
};

// Adds --no-repair, --max-hole and --max-hole-size to @p cmd.
void add_input_options(CLI::App& cmd, InputOptions& o);

// Reads @p path with read_mesh() (size limit @p max_file_bytes) and prints each of its warnings
// to stderr. Throws what read_mesh() throws.
TriangleMesh read_input(const std::string& path, uint64_t max_file_bytes);

}  // namespace hdm::app
