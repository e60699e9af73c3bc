// SPDX-License-Identifier: MIT
// hdm info MODEL.hdm [--json]: sizes, source, displacement and hardness statistics of a saved model.
#include "commands.h"

#include <hdm/io/hdm_file.h>
#include <hdm/slab/model_memory.h>
#include <hdm/slab/slab_snapshots.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace hdm::app {
namespace {

struct InfoOptions {
  std::string model;
  bool json = false;
  InputLimit limit;
};

// Minimum, mean and maximum of a per-sample field (zeros when it is empty).
struct FieldRange {
  double lo = 0, mean = 0, hi = 0;
};
template <class Field>
FieldRange range_of(const Field& v) {
  FieldRange r;
  if (v.empty()) return r;
  double lo = INFINITY, hi = -INFINITY, sum = 0;
  for (size_t k = 0; k < v.size(); ++k) {
    const double x = float(v[k]);
    lo = std::min(lo, x), hi = std::max(hi, x), sum += x;
  }
  return {lo, sum / static_cast<double>(v.size()), hi};
}

void run_info(const InfoOptions& o) {
  const SlabModel m = load_model(o.model, {o.limit.bytes()});
  const FieldRange disp = range_of(m.displacement), hard = range_of(m.hardness);
  int64_t exposed = 0;  // samples where the surface lies below the under-layer's top
  for (size_t s = 0; s < m.displacement.size() && s < m.layer_displacement.size(); ++s)
    exposed += m.displacement[s] < m.layer_displacement[s];
  const auto file_bytes = static_cast<uintmax_t>(std::filesystem::file_size(o.model));
  const ModelMemory mem = model_memory(m);
  const double step = displacement_quantisation(m);  // [model units]
  const double step_pct = m.source_diagonal > 0 ? 100 * step / m.source_diagonal : NAN;
  // What a sculpting session's snapshots add at their default settings (copy on write: the spare
  // versions and the per-slab state).
  const SlabSnapshots snapshots(m);
  const size_t snapshot_bytes = snapshots.memory_bytes();

  if (o.json) {
    const nlohmann::json j = {
        {"slabs", m.slab_count()},
        {"coarse_vertices", m.coarse_vertex_count()},
        {"grid", m.grid_n},
        {"texel_density", m.texel_density},
        {"samples", m.samples.count},
        {"texels", m.texels.count},
        {"source", m.source},
        {"source_triangles", m.source_triangles},
        {"displacement",
         {{"min", disp.lo},
          {"mean", disp.mean},
          {"max", disp.hi},
          {"quantisation", step},
          {"quantisation_pct", std::isfinite(step_pct) ? nlohmann::json(step_pct) : nlohmann::json(nullptr)}}},
        {"hardness_hv",
         {{"min", hard.lo}, {"mean", hard.mean}, {"max", hard.hi}, {"under_layer", m.under_layer.hardness_hv}}},
        {"under_layer_exposed_samples", exposed},
        {"bytes", mem.sample_fields + mem.texel_fields + mem.coarse},
        {"memory",
         {{"total_bytes", mem.total()},
          {"sample_fields", mem.sample_fields},
          {"texel_fields", mem.texel_fields},
          {"coarse", mem.coarse},
          {"sample_layout", mem.sample_layout},
          {"texel_layout", mem.texel_layout},
          {"caches", mem.caches},
          {"slab_constants", mem.slab_constants},
          {"uniform_fields_as_arrays", mem.uniform_fields},
          {"bytes_per_sample", mem.per_sample()},
          {"bytes_per_texel", mem.per_texel()},
          {"snapshot_bytes", snapshot_bytes},
          {"snapshot_versions", snapshots.version_count()}}},
        {"file_bytes", file_bytes}};
    std::printf("%s\n", j.dump().c_str());
    return;
  }
  std::printf("model             %s\n", o.model.c_str());
  std::printf("slabs             %d\n", m.slab_count());
  std::printf("coarse vertices   %d\n", m.coarse_vertex_count());
  std::printf("grid n            %d (%d samples per slab)\n", m.grid_n, m.samples.per_slab);
  std::printf("texel density     %d (texel grid %d)\n", m.texel_density, m.texels.n);
  std::printf("samples           %d\n", m.samples.count);
  std::printf("texels            %d\n", m.texels.count);
  std::printf("source            %s\n", m.source.empty() ? "(unknown)" : m.source.c_str());
  std::printf("source triangles  %lld\n", static_cast<long long>(m.source_triangles));
  std::printf("displacement      min %.6g  mean %.6g  max %.6g\n", disp.lo, disp.mean, disp.hi);
  std::printf(
      "  stored as        unorm16: surface points within %.3g model units of the values written (%.2g %% of "
      "the source's diagonal)\n",
      step, step_pct);
  std::printf("hardness [HV]     min %.6g  mean %.6g  max %.6g\n", hard.lo, hard.mean, hard.hi);
  std::printf("under-layer       exposed at %lld samples, hardness %.6g HV\n", static_cast<long long>(exposed),
              double(m.under_layer.hardness_hv));
  std::printf("file size         %ju bytes\n", file_bytes);
  const auto mib = [](int64_t b) { return double(b) / (1 << 20); };
  std::printf("in memory         %.1f MiB: %.1f bytes per displacement sample, %.1f per colour texel\n",
              mib(mem.total()), mem.per_sample(), mem.per_texel());
  std::printf("  stored          %.1f MiB per-sample fields, %.1f MiB per-texel fields, %.1f MiB coarse mesh\n",
              mib(mem.sample_fields), mib(mem.texel_fields), mib(mem.coarse));
  std::printf(
      "  derived         %.1f MiB sample layout, %.1f MiB texel layout, %.1f MiB query caches, "
      "%.1f MiB slab constants\n",
      mib(mem.sample_layout), mib(mem.texel_layout), mib(mem.caches), mib(mem.slab_constants));
  std::printf("  when edited     +%.1f MiB: an editor gives the fields of one value their arrays\n",
              mib(mem.uniform_fields));
  std::printf(
      "  snapshots       %.2f MiB while sculpting (%.1f %% of the model edited: %d spare versions, copy on write)\n",
      mib(int64_t(snapshot_bytes)), 100.0 * double(snapshot_bytes) / double(mem.total() + mem.uniform_fields),
      snapshots.version_count());
}

}  // namespace

void add_info_command(CLI::App& app) {
  auto opts = std::make_shared<InfoOptions>();
  CLI::App* sub = app.add_subcommand("info", "Print the sizes, memory, source and displacement range of a .hdm model");
  sub->add_option("model", opts->model, "model file (.hdm)")->required()->check(CLI::ExistingFile);
  sub->add_flag("--json", opts->json, "print one JSON object instead of text");
  add_input_limit(sub, opts->limit);
  sub->callback([opts] { run_info(*opts); });
}

}  // namespace hdm::app
