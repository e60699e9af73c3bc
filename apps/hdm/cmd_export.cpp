// SPDX-License-Identifier: MIT
// hdm export MODEL.hdm -o OUT.obj|OUT.ply|OUT.glb: writes the displaced surface of a model.
#include "commands.h"
#include "output_guard.h"

#include <hdm/io/export_mesh.h>
#include <hdm/io/hdm_file.h>

#include <CLI/CLI.hpp>

#include <cstdio>
#include <memory>
#include <string>

namespace hdm::app {
namespace {

struct ExportOptions {
  std::string model;
  std::string output;
  InputLimit limit;
};

void run_export(const ExportOptions& o) {
  const std::vector<std::string> files = export_files(o.output);  // rejects a bad extension before loading
  check_outputs(files, {o.model});
  const SlabModel m = load_model(o.model, {o.limit.bytes()});
  export_mesh(m, o.output);
  for (const std::string& f : files) std::printf("wrote %s\n", f.c_str());
}

}  // namespace

void add_export_command(CLI::App& app) {
  auto opts = std::make_shared<ExportOptions>();
  CLI::App* sub = app.add_subcommand(
      "export", "Write the displaced surface of a .hdm model as OBJ (+MTL+PNG), binary PLY or binary glTF");
  sub->add_option("model", opts->model, "model file (.hdm)")->required()->check(CLI::ExistingFile);
  sub->add_option("-o,--output", opts->output, "output file: .obj, .ply or .glb")->required();
  add_input_limit(sub, opts->limit);
  sub->callback([opts] { run_export(*opts); });
}

}  // namespace hdm::app
