// SPDX-License-Identifier: MIT
// hdm check MODEL.hdm --against INPUT: independent measurement of a slab model against its input
// (docs/design.md#how-we-measure): exact queries on the input with Embree, never the slab code.
#include "commands.h"
#include "input_mesh.h"
#include "memory_budget.h"

#include <hdm/analysis/fidelity.h>
#include <hdm/slab/shell_check.h>
#include <hdm/io/hdm_file.h>
#include <hdm/slab/scale_model.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <utility>

namespace hdm::app {
namespace {

struct CheckArgs {
  std::string model, input;
  int64_t points = 100000;
  InputOptions in;
  bool json = false;
  InputLimit limit;
  MemoryBudget budget;
};

void run_check(const CheckArgs& a) {
  require_memory(check_peak_bytes(file_bytes(a.model), file_bytes(a.input), a.points), a.budget, "hdm check " + a.model,
                 std::to_string(a.points) + " contact points (--points)");
  SlabModel model = load_model(a.model, {a.limit.bytes()});
  // The input as `hdm bake` prepared it (the same scale, repair and orientation, from the input
  // alone), and the model at that scale: every figure is relative to the diagonal.
  PrepareOptions prepare = a.in.prepare();
  prepare.resolve = false;  // measured against the input's own faces, not the bake's resolution of them
  PreparedInput prepared = prepare_input(read_input(a.input, a.limit.bytes()), a.input, prepare);
  scale_model(model, prepared.report.scale_exponent);
  const ExactMeshQuery exact(std::move(prepared.mesh));
  std::vector<uint8_t> interior;
  if (prepared.report.self_intersections > 0) interior = interior_faces(exact);
  const std::vector<Vec3> points = surface_points(exact, interior.empty() ? nullptr : &interior);
  const Fidelity f = measure_fidelity(model, exact, &points);
  const ContactAccuracy c = measure_contact(model, exact, a.points, 1, 1.0, interior.empty() ? nullptr : &interior);
  const int invalid = count_invalid_slabs(model);
  const int64_t overlapping = count_overlapping_pairs(model);
  const int64_t undercut = count_undercut_columns(model, exact);
  const nlohmann::json j = {{"model", a.model},
                            {"against", a.input},
                            {"slabs", model.slab_count()},
                            {"grid", model.grid_n},
                            {"fidelity",
                             {{"rms_pct", f.rms_pct},
                              {"max_pct", f.max_pct},
                              {"rms_back_pct", f.rms_back_pct},
                              {"max_back_pct", f.max_back_pct}}},
                            {"contact",
                             {{"points", c.points},
                              {"agreement", c.agreement},
                              {"depth_rms_pct", c.depth_rms_pct},
                              {"depth_max_pct", c.depth_max_pct},
                              {"missed_below_shell", c.missed_below_shell},
                              {"missed_in_shell", c.missed_in_shell},
                              {"false_inside", c.false_inside}}},
                            {"invalid_slabs", invalid},
                            {"overlapping_pairs", overlapping},
                            {"undercut_columns", undercut},
                            {"self_intersections", prepared.report.self_intersections},
                            {"interior_faces", std::count(interior.begin(), interior.end(), uint8_t(1))},
                            {"samples", model.samples.count}};
  if (a.json) {
    std::printf("%s\n", j.dump(2).c_str());
    return;
  }
  std::printf("check %s against %s (%d slabs, n = %d)\n", a.model.c_str(), a.input.c_str(), model.slab_count(),
              model.grid_n);
  std::printf("  fidelity model -> input   RMS %.4f%%  max %.4f%% of the diagonal\n", f.rms_pct, f.max_pct);
  std::printf("  fidelity input -> model   RMS %.4f%%  max %.4f%%\n", f.rms_back_pct, f.max_back_pct);
  std::printf("  contact (%lld points within 1%% of the surface)\n", (long long)c.points);
  std::printf("    inside/outside agreement %.4f%%\n", 100 * c.agreement);
  std::printf("    depth error              RMS %.4f%%  max %.4f%%\n", c.depth_rms_pct, c.depth_max_pct);
  std::printf(
      "    disagreements            %lld inside but below the shell, %lld inside but above the surface, %lld outside "
      "but below\n",
      (long long)c.missed_below_shell, (long long)c.missed_in_shell, (long long)c.false_inside);
  std::printf("  invalid slabs             %d\n", invalid);
  std::printf("  overlapping slab pairs    %lld\n", (long long)overlapping);
  std::printf("  undercut columns          %lld of %d\n", (long long)undercut, model.samples.count);
}

}  // namespace

void add_check_command(CLI::App& app) {
  auto a = std::make_shared<CheckArgs>();
  CLI::App* cmd = app.add_subcommand("check", "Measure a slab model against its input mesh with exact queries");
  cmd->add_option("model", a->model, "slab model (.hdm)")->required();
  cmd->add_option("--against", a->input, "the input mesh it was baked from")->required();
  cmd->add_option("--points", a->points, "contact test points")->check(CLI::Range(int64_t(100), int64_t(100000000)));
  add_input_options(*cmd, a->in);
  cmd->add_flag("--json", a->json, "print one JSON object");
  add_input_limit(cmd, a->limit);
  add_memory_budget(cmd, a->budget);
  cmd->callback([a] { run_check(*a); });
}

}  // namespace hdm::app
