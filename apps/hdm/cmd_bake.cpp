// SPDX-License-Identifier: MIT
// hdm bake INPUT -o MODEL.hdm: mesh -> slab model, with the bake report and fidelity figures.
#include "bake_guard.h"
#include "commands.h"
#include "input_mesh.h"
#include "progress_bar.h"

#include <hdm/io/hdm_file.h>
#include <hdm/pipeline/bake_input.h>

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

// The bake's options as the command line gives them: the error bound of hdm (0.2 % max, 0.02 %
// RMS, both ways) unless --slabs is given without a bound, or --no-error-bound.
BakeInputOptions bake_options(const BakeArgs& a) {
  BakeInputOptions o;
  o.bake.slabs = a.slabs;
  o.bake.grid_n = a.grid;
  o.bake.density = a.density;
  o.bake.texel_density = a.texels;
  o.prepare = a.in.prepare();
  const bool given = !std::isnan(a.max_error) || !std::isnan(a.rms_error);
  o.bounded = !a.no_error_bound && (given || a.slabs == 0);
  o.tolerance.max_pct = !given ? 0.2 : std::isnan(a.max_error) ? INFINITY : a.max_error;
  o.tolerance.rms_pct = !given ? 0.02 : std::isnan(a.rms_error) ? INFINITY : a.rms_error;
  o.tolerance.max_slabs = a.max_slabs;
  o.tolerance.adapt_grid = !a.grid_given;  // an explicit --grid is kept in every round
  return o;
}

nlohmann::json fidelity_json(const Fidelity& f) {
  return {{"rms_pct", f.rms_pct},
          {"max_pct", f.max_pct},
          {"rms_back_pct", f.rms_back_pct},
          {"max_back_pct", f.max_back_pct}};
}

// What prepare_input() did, as the JSON report's "repair", "folds", "orient" and crossing keys.
void add_input_json(nlohmann::json& j, const PrepareReport& in) {
  const RepairReport& fixed = in.repair;
  j["repair"] = {{"merged_vertices", fixed.merged_vertices}, {"removed_faces", fixed.removed_faces},
                 {"split_vertices", fixed.split_vertices},   {"flipped_faces", fixed.flipped_faces},
                 {"filled_holes", fixed.filled_holes},       {"added_faces", fixed.added_faces},
                 {"open_boundaries", fixed.open_boundaries}};
  j["folds"] = {{"flap_faces", in.folds.flap_faces},
                {"empty_cone_vertices", in.folds.empty_cones_before},
                {"moved_vertices", in.folds.moved},
                {"max_move", std::ldexp(in.folds.max_move, -in.scale_exponent)},
                {"max_deviation", in.folds.max_deviation},
                {"rim_faces", in.folds.rim_faces},
                {"empty_cone_vertices_left", in.folds.empty_cones_after}};
  j["self_intersections"] = in.self_intersections;
  j["self_intersections_left"] = in.resolved.pairs_after;
  j["seam_vertices"] = in.resolved.seam_vertices;
  j["orient"] = {
      {"components", in.orient.components}, {"closed", in.orient.closed},   {"nearly_closed", in.orient.nearly_closed},
      {"sheets", in.orient.sheets},         {"flipped", in.orient.flipped}, {"flipped_faces", in.orient.flipped_faces}};
}

nlohmann::json tolerance_json(const BakeInputOptions& o, const BakeInputReport& rep) {
  nlohmann::json tried = nlohmann::json::array();
  for (const ToleranceRound& t : rep.rounds)
    tried.push_back({{"slabs", t.slabs},
                     {"grid", t.grid_n},
                     {"rms_pct", t.fidelity.rms_pct},
                     {"max_pct", t.fidelity.max_pct},
                     {"rms_back_pct", t.fidelity.rms_back_pct},
                     {"max_back_pct", t.fidelity.max_back_pct},
                     {"invalid_slabs", t.invalid_slabs},
                     {"overlapping_pairs", t.overlapping_pairs},
                     {"ray_misses", t.ray_misses},
                     {"local", t.local},
                     {"fewer", t.fewer},
                     {"met", t.met}});
  const auto bound = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
  return {{"max_pct", bound(o.tolerance.max_pct)},
          {"rms_pct", bound(o.tolerance.rms_pct)},
          {"met", rep.rounds.back().met},
          {"stopped_because", describe_stop(rep.rounds.back(), o.tolerance, rep.bake.input_triangles)},
          {"rounds", tried}};
}

nlohmann::json bake_json(const BakeArgs& a, const BakeInputOptions& o, const BakeInputReport& rep,
                         const SlabModel& model) {
  const BakeReport& r = rep.bake;
  nlohmann::json j = {
      {"input", a.input},
      {"output", a.output},
      {"slabs", r.slabs},
      {"grid", r.grid_n},
      {"samples", r.samples},
      {"input_triangles", r.input_triangles},
      {"submesh_triangles", r.submesh_triangles},
      {"bake_seconds", r.seconds},
      {"total_seconds", rep.seconds},
      {"invalid_slabs", r.invalid_slabs},
      {"ray_misses", r.ray_misses},
      {"overlapping_pairs", r.overlapping_pairs},
      {"undercut_columns", r.undercut_columns},
      {"separated", r.separated},
      {"peak_rss_mib", peak_rss_mib()},
      {"fidelity", fidelity_json(rep.fidelity)},
      {"remeshed_faces", rep.remeshed_faces},
      {"displacement_quantisation_pct", 100 * displacement_quantisation(model) / model.source_diagonal}};
  add_input_json(j, rep.input);
  if (o.bounded) j["tolerance"] = tolerance_json(o, rep);
  return j;
}

// The lines on what prepare_input() changed in the input (nothing printed for a clean mesh).
void print_input_changes(const PrepareReport& in, double diagonal) {
  if (const RepairReport& fixed = in.repair; fixed.changed())
    std::printf(
        "  repaired input      %lld vertices welded, %lld faces removed, %lld vertices split, %lld faces flipped, "
        "%d holes filled (%lld faces), %d open boundaries kept\n",
        (long long)fixed.merged_vertices, (long long)fixed.removed_faces, (long long)fixed.split_vertices,
        (long long)fixed.flipped_faces, fixed.filled_holes, (long long)fixed.added_faces, fixed.open_boundaries);
  if (const FoldReport& fo = in.folds; fo.flap_faces + fo.moved + fo.rim_faces > 0)
    std::printf(
        "  folds removed       %lld rim flap faces and %lld faces of empty-cone vertices cut, %lld vertices moved to "
        "open the dual cones of %lld empty-cone vertices (%lld left); the surface changed by at most %.3g%% of the "
        "diagonal\n",
        (long long)fo.flap_faces, (long long)fo.rim_faces, (long long)fo.moved, (long long)fo.empty_cones_before,
        (long long)fo.empty_cones_after, 100 * fo.max_deviation / diagonal);
  if (in.self_intersections > 0)
    std::printf(
        "  self-intersections  %lld face pairs crossed, %lld after the local repair (%lld -> %lld faces, %lld "
        "seam vertices stitched); interior faces left out of the fidelity\n",
        (long long)in.self_intersections, (long long)in.resolved.pairs_after, (long long)in.resolved.faces_before,
        (long long)in.resolved.faces_after, (long long)in.resolved.seam_vertices);
  if (in.orient.flipped)
    std::printf("  oriented outward    %d of %d parts reversed (%lld faces)\n", in.orient.flipped, in.orient.components,
                (long long)in.orient.flipped_faces);
}

void print_bake(const BakeArgs& a, const BakeInputReport& rep, const SlabModel& model) {
  const BakeReport& r = rep.bake;
  std::printf("baked %s -> %s\n", a.input.c_str(), a.output.c_str());
  std::printf("  slabs               %d (grid n = %d, %lld samples)\n", r.slabs, r.grid_n, (long long)r.samples);
  std::printf("  input triangles     %lld\n", (long long)r.input_triangles);
  std::printf("  submesh triangles   %lld\n", (long long)r.submesh_triangles);
  std::printf(
      "  bake time           %.2f s (peak memory %.0f MiB; %.2f s with reading, repair, every round and "
      "the fidelity measurement)\n",
      r.seconds, peak_rss_mib(), rep.seconds);
  print_input_changes(rep.input, rep.diagonal);
  if (rep.remeshed_faces > 0)
    std::printf(
        "  remeshed source     %lld triangles of the same surface decimated into slabs (the input's own "
        "triangles left slabs invalid); the rays cast on the input\n",
        (long long)rep.remeshed_faces);
  std::printf("  invalid slabs       %d\n", r.invalid_slabs);
  std::printf("  ray misses          %lld (filled at the point of the line nearest the input)\n",
              (long long)r.ray_misses);
  std::printf("  undercut columns    %lld\n", (long long)r.undercut_columns);
  std::printf("  overlapping pairs   %lld\n", (long long)r.overlapping_pairs);
  std::printf("  slab separation     %s\n",
              r.separated ? "on (overlapping slabs thinned apart)" : "off (see hdm check for overlaps)");
  for (size_t k = 0; k < rep.rounds.size(); ++k) {
    const ToleranceRound& t = rep.rounds[k];
    std::printf("  error-bounded round %zu: %d slabs (n = %d), max %.4f%% / %.4f%% back, RMS %.4f%% / %.4f%% back%s\n",
                k + 1, t.slabs, t.grid_n, t.fidelity.max_pct, t.fidelity.max_back_pct, t.fidelity.rms_pct,
                t.fidelity.rms_back_pct,
                t.met && k + 1 == rep.rounds.size() ? " (bound met)"
                : t.fewer                           ? " (fewer slabs tried, not kept)"
                : t.met                             ? " (bound met; fewer slabs tried next)"
                                                    : "");
  }
  const Fidelity& f = rep.fidelity;
  std::printf("  fidelity (%% of bounding-box diagonal)\n");
  std::printf("    model -> input    RMS %.4f%%  max %.4f%%\n", f.rms_pct, f.max_pct);
  std::printf("    input -> model    RMS %.4f%%  max %.4f%%\n", f.rms_back_pct, f.max_back_pct);
  std::printf("    of which stored   at most %.2g%% (displacements as unorm16)\n",
              100 * displacement_quantisation(model) / model.source_diagonal);
}

void run_bake(const BakeArgs& a) {
  guard_bake({a.input, a.output, a.slabs, a.grid, a.texels, a.density, a.limit.bytes()});
  const auto start = std::chrono::steady_clock::now();
  ProgressBar bar;
  bar("read", 0);
  TriangleMesh mesh = read_input(a.input, a.limit.bytes());
  BakeInputOptions o = bake_options(a);
  o.bake.progress = [&](const char* stage, double f) { bar(stage, f); };
  BakeInputReport rep;
  SlabModel model = bake_input(std::move(mesh), a.input, o, &rep);
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();  // with reading
  bar.finish();
  save_model(model, a.output);
  if (o.bounded && !rep.rounds.back().met)
    std::fprintf(stderr, "hdm: warning: %s: the error bound is not met at %d slabs: %s; saved the finest model tried\n",
                 a.input.c_str(), rep.bake.slabs,
                 describe_stop(rep.rounds.back(), o.tolerance, rep.bake.input_triangles).c_str());
  if (a.json)
    std::printf("%s\n", bake_json(a, o, rep, model).dump(2).c_str());
  else
    print_bake(a, rep, model);
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
