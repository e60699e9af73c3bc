// SPDX-License-Identifier: MIT
// hdm bake INPUT -o MODEL.hdm: mesh -> slab model, with the bake report and fidelity figures.
#include "bake_guard.h"
#include "commands.h"
#include "input_mesh.h"
#include "progress_bar.h"

#include <hdm/analysis/bake_to_tolerance.h>
#include <hdm/analysis/fidelity.h>
#include <hdm/io/hdm_file.h>
#include <hdm/slab/bake.h>
#include <hdm/slab/scale_model.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

namespace hdm::app {
namespace {

struct BakeArgs {
  std::string input, output;
  int slabs = 0, grid = 16, texels = 2;
  double density = 4.0;
  InputOptions in;
  bool json = false;
  // Error bound [% of the diagonal]. Unset (NaN): the default fidelity bound (0.2% max, 0.02% RMS,
  // both ways) when the slab count follows --density, none when --slabs is given.
  double max_error = NAN, rms_error = NAN;
  bool no_error_bound = false;
  bool grid_given = false;  // --grid on the command line: the error-bounded bake keeps it
  int max_slabs = 100000;
  InputLimit limit;
};

// Peak resident set size of this process [MiB] (Linux reports ru_maxrss in KiB).
double peak_rss_mib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;
}

void run_bake(const BakeArgs& a) {
  guard_bake({a.input, a.output, a.slabs, a.grid, a.texels, a.density, a.limit.bytes()});
  const auto start = std::chrono::steady_clock::now();
  ProgressBar bar;
  bar("read", 0);
  PreparedInput prepared = prepare_input(a.input, a.in, a.limit.bytes(), true);
  TriangleMesh& mesh = prepared.mesh;
  const RepairReport& fixed = prepared.repair;
  BakeOptions o;
  o.slabs = a.slabs;
  o.grid_n = a.grid;
  o.density = a.density;
  o.texel_density = a.texels;
  o.progress = [&](const char* stage, double f) { bar(stage, f); };
  BakeReport r;
  const bool given = !std::isnan(a.max_error) || !std::isnan(a.rms_error);
  const bool bounded = !a.no_error_bound && (given || a.slabs == 0);
  const double max_error = !given ? 0.2 : std::isnan(a.max_error) ? INFINITY : a.max_error;
  const double rms_error = !given ? 0.02 : std::isnan(a.rms_error) ? INFINITY : a.rms_error;
  // One Embree BVH over the input for the bake's rays and the fidelity measurement; the bake
  // time reported includes its build, as when the bake built it.
  bar("input BVH", 0);
  const auto bvh_start = std::chrono::steady_clock::now();
  validate_mesh_data(mesh, a.input);
  const ExactMeshQuery reference(mesh);
  // A mesh that crosses itself bounds the union of its parts; faces buried inside it are not on
  // the surface the model follows, and the fidelity leaves them out.
  std::vector<uint8_t> buried;
  if (prepared.self_intersections > 0) buried = buried_faces(reference);
  const double bvh_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - bvh_start).count();
  std::vector<ToleranceRound> rounds;
  Fidelity f;
  SlabModel model;
  Tolerance t;
  if (bounded) {
    if (!buried.empty()) t.buried = &buried;
    t.max_pct = max_error;
    t.rms_pct = rms_error;
    t.max_slabs = a.max_slabs;
    t.adapt_grid = !a.grid_given;  // an explicit --grid is kept in every round
    model = bake_to_tolerance(reference, a.input, o, t, &rounds, &r);
    f = rounds.back().fidelity;
  } else {
    model = bake_slabs(reference, a.input, o, &r);
    bar("fidelity", 0);
    f = measure_fidelity(model, reference, buried.empty() ? nullptr : &buried);
    bar("fidelity", 1);
  }
  r.seconds += bvh_seconds;  // the last round's bake and the input BVH it used
  bar.finish();
  scale_model(model, -prepared.scale_exponent);  // back to the input's units, exactly
  save_model(model, a.output);
  nlohmann::json j = {
      {"input", a.input},
      {"output", a.output},
      {"slabs", r.slabs},
      {"grid", r.grid_n},
      {"samples", r.samples},
      {"input_triangles", r.input_triangles},
      {"submesh_triangles", r.submesh_triangles},
      {"bake_seconds", r.seconds},
      {"total_seconds", std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()},
      {"invalid_slabs", r.invalid_slabs},
      {"ray_misses", r.ray_misses},
      {"overlapping_pairs", r.overlapping_pairs},
      {"undercut_columns", r.undercut_columns},
      {"separated", r.separated},
      {"peak_rss_mib", peak_rss_mib()},
      {"repair",
       {{"merged_vertices", fixed.merged_vertices},
        {"removed_faces", fixed.removed_faces},
        {"split_vertices", fixed.split_vertices},
        {"flipped_faces", fixed.flipped_faces},
        {"filled_holes", fixed.filled_holes},
        {"added_faces", fixed.added_faces},
        {"open_boundaries", fixed.open_boundaries}}},
      {"folds",
       {{"flap_faces", prepared.folds.flap_faces},
        {"folded_stars", prepared.folds.folded_before},
        {"moved_vertices", prepared.folds.moved},
        {"max_move", std::ldexp(prepared.folds.max_move, -prepared.scale_exponent)},
        {"max_deviation", prepared.folds.max_deviation},
        {"rim_faces", prepared.folds.rim_faces},
        {"folded_stars_left", prepared.folds.folded_after}}},
      {"self_intersections", prepared.self_intersections},
      {"self_intersections_left", prepared.resolved.pairs_after},
      {"seam_vertices", prepared.resolved.seam_vertices},
      {"orient",
       {{"components", prepared.orient.components},
        {"closed", prepared.orient.closed},
        {"nearly_closed", prepared.orient.nearly_closed},
        {"sheets", prepared.orient.sheets},
        {"flipped", prepared.orient.flipped},
        {"flipped_faces", prepared.orient.flipped_faces}}},
      {"fidelity",
       {{"rms_pct", f.rms_pct},
        {"max_pct", f.max_pct},
        {"rms_back_pct", f.rms_back_pct},
        {"max_back_pct", f.max_back_pct}}}};
  if (bounded) {
    nlohmann::json tried = nlohmann::json::array();
    for (const ToleranceRound& t : rounds)
      tried.push_back({{"slabs", t.slabs},
                       {"grid", t.grid_n},
                       {"rms_pct", t.fidelity.rms_pct},
                       {"max_pct", t.fidelity.max_pct},
                       {"rms_back_pct", t.fidelity.rms_back_pct},
                       {"max_back_pct", t.fidelity.max_back_pct},
                       {"invalid_slabs", t.invalid_slabs},
                       {"overlapping_pairs", t.overlapping_pairs},
                       {"ray_misses", t.ray_misses},
                       {"met", t.met}});
    j["tolerance"] = {{"max_pct", std::isfinite(max_error) ? nlohmann::json(max_error) : nlohmann::json(nullptr)},
                      {"rms_pct", std::isfinite(rms_error) ? nlohmann::json(rms_error) : nlohmann::json(nullptr)},
                      {"met", rounds.back().met},
                      {"stopped_because", describe_stop(rounds.back(), t, r.input_triangles)},
                      {"rounds", tried}};
    if (!rounds.back().met)
      std::fprintf(stderr,
                   "hdm: warning: %s: the error bound is not met at %d slabs: %s; saved the finest model tried\n",
                   a.input.c_str(), r.slabs, describe_stop(rounds.back(), t, r.input_triangles).c_str());
  }
  if (a.json) {
    std::printf("%s\n", j.dump(2).c_str());
    return;
  }
  std::printf("baked %s -> %s\n", a.input.c_str(), a.output.c_str());
  std::printf("  slabs               %d (grid n = %d, %lld samples)\n", r.slabs, r.grid_n, (long long)r.samples);
  std::printf("  input triangles     %lld\n", (long long)r.input_triangles);
  std::printf("  submesh triangles   %lld\n", (long long)r.submesh_triangles);
  std::printf(
      "  bake time           %.2f s (peak memory %.0f MiB; %.2f s with reading, repair, every round and "
      "the fidelity measurement)\n",
      r.seconds, peak_rss_mib(), j["total_seconds"].get<double>());
  if (fixed.changed())
    std::printf(
        "  repaired input      %lld vertices welded, %lld faces removed, %lld vertices split, %lld faces flipped, "
        "%d holes filled (%lld faces), %d open boundaries kept\n",
        (long long)fixed.merged_vertices, (long long)fixed.removed_faces, (long long)fixed.split_vertices,
        (long long)fixed.flipped_faces, fixed.filled_holes, (long long)fixed.added_faces, fixed.open_boundaries);
  if (const FoldReport& fo = prepared.folds; fo.flap_faces + fo.moved + fo.rim_faces > 0)
    std::printf(
        "  folds removed       %lld rim flap faces and %lld faces of folded stars cut, %lld vertices moved to "
        "unfold %lld folded stars (%lld left); the surface changed by at most %.3g%% of the diagonal\n",
        (long long)fo.flap_faces, (long long)fo.rim_faces, (long long)fo.moved, (long long)fo.folded_before,
        (long long)fo.folded_after, 100 * fo.max_deviation / bounds(prepared.mesh).diagonal());
  if (prepared.self_intersections > 0)
    std::printf(
        "  self-intersections  %lld face pairs crossed, %lld after the local repair (%lld -> %lld faces, %lld "
        "seam vertices stitched); buried faces left out of the fidelity\n",
        (long long)prepared.self_intersections, (long long)prepared.resolved.pairs_after,
        (long long)prepared.resolved.faces_before, (long long)prepared.resolved.faces_after,
        (long long)prepared.resolved.seam_vertices);
  if (prepared.orient.flipped)
    std::printf("  oriented outward    %d of %d parts reversed (%lld faces)\n", prepared.orient.flipped,
                prepared.orient.components, (long long)prepared.orient.flipped_faces);
  std::printf("  invalid slabs       %d\n", r.invalid_slabs);
  std::printf("  ray misses          %lld (filled at the point of the line nearest the input)\n",
              (long long)r.ray_misses);
  std::printf("  undercut columns    %lld\n", (long long)r.undercut_columns);
  std::printf("  overlapping pairs   %lld\n", (long long)r.overlapping_pairs);
  std::printf("  slab separation     %s\n",
              r.separated ? "on (overlapping slabs thinned apart)" : "off (see hdm check for overlaps)");
  for (size_t k = 0; k < rounds.size(); ++k)
    std::printf("  error-bounded round %zu: %d slabs (n = %d), max %.4f%% / %.4f%% back, RMS %.4f%% / %.4f%% back%s\n",
                k + 1, rounds[k].slabs, rounds[k].grid_n, rounds[k].fidelity.max_pct, rounds[k].fidelity.max_back_pct,
                rounds[k].fidelity.rms_pct, rounds[k].fidelity.rms_back_pct, rounds[k].met ? " (bound met)" : "");
  std::printf("  fidelity (%% of bounding-box diagonal)\n");
  std::printf("    model -> input    RMS %.4f%%  max %.4f%%\n", f.rms_pct, f.max_pct);
  std::printf("    input -> model    RMS %.4f%%  max %.4f%%\n", f.rms_back_pct, f.max_back_pct);
}

}  // namespace

void add_bake_command(CLI::App& app) {
  auto a = std::make_shared<BakeArgs>();
  CLI::App* cmd = app.add_subcommand("bake", "Bake a triangle mesh (OBJ, PLY, OFF, STL) into a slab model (.hdm)");
  cmd->add_option("input", a->input, "input mesh")->required();
  cmd->add_option("-o,--output", a->output, "output slab model (.hdm)")->required();
  cmd->add_option("--slabs", a->slabs, "target slab count (default: input triangles * density / n^2)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--density", a->density, "with no --slabs: submesh triangles per input triangle (default 4)")
      ->check(CLI::Range(1e-3, 1024.0));
  CLI::Option* grid = cmd->add_option("--grid", a->grid,
                                      "displacement intervals per slab edge n (paper: 15; default 16, lowered "
                                      "in error-bounded rounds that add slabs, so the samples stay at --density)")
                          ->check(CLI::Range(1, 256));
  cmd->add_option("--texels", a->texels, "colour texels per displacement interval")->check(CLI::Range(1, 16));
  add_input_options(*cmd, a->in);
  cmd->add_option("--max-error", a->max_error,
                  "error-bounded bake: raise the slab count until the maximum distance both ways is at most this "
                  "% of the diagonal (default without --slabs: 0.2, with --rms-error 0.02)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--rms-error", a->rms_error,
                  "error-bounded bake: ... and the RMS distance both ways at most this % of the diagonal")
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--no-error-bound", a->no_error_bound,
                "bake once at the --slabs or --density count, whatever the error");
  cmd->add_option("--max-slabs", a->max_slabs, "error-bounded bake: never more slabs than this (default 100000)")
      ->check(CLI::Range(1, 10000000));
  cmd->add_flag("--json", a->json, "print the report as one JSON object");
  add_input_limit(cmd, a->limit);
  cmd->callback([a, grid] {
    a->grid_given = grid->count() > 0;
    run_bake(*a);
  });
}

}  // namespace hdm::app
