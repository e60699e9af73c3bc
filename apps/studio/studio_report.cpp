// SPDX-License-Identifier: MIT
#include "studio_report.h"

#include <hdm/core/percentile.h>
#include <hdm/core/write_file_atomic.h>

#include <algorithm>

namespace hdm::studio {
namespace {

// Median, 99th percentile and maximum of a copy of @p v.
nlohmann::json percentiles(std::vector<double> v) {
  if (v.empty()) return {{"median", nullptr}, {"p99", nullptr}, {"max", nullptr}, {"count", 0}};
  const double most = *std::max_element(v.begin(), v.end());
  return {{"median", percentile(v, 0.5)}, {"p99", percentile(v, 0.99)}, {"max", most}, {"count", v.size()}};
}

// Frames drawn at each level of detail.
std::vector<long> frames_per_level(const std::vector<int>& levels, int level_count) {
  std::vector<long> n(static_cast<size_t>(std::max(level_count, 1)), 0);
  for (int l : levels) ++n[static_cast<size_t>(l)];
  return n;
}

}  // namespace

void write_studio_report(const StudioReportContext& c, const ServoStats& st, const SessionStats& ss) {
  const StudioOptions& o = c.options;
  const StudioFigures& f = c.figures;
  std::vector<double> skip_first(f.frame_ms.begin() + std::min<size_t>(f.frame_ms.size(), 3), f.frame_ms.end());
  int64_t total = 0, frames_with = 0, most = 0;
  for (int u : f.uploads) total += u, frames_with += u > 0, most = std::max<int64_t>(most, u);
  nlohmann::json j = {
      {"model", o.model_name},
      {"size", {o.width, o.height}},
      {"frames", f.frames},
      {"frame_ms", percentiles(skip_first)},
      {"slabs", c.slabs},
      {"lod",
       {{"mode", o.lod < 0 ? nlohmann::json("auto") : nlohmann::json(o.lod)},
        {"frame_budget_ms", o.frame_budget_ms},
        {"frames_per_level", frames_per_level(f.levels, c.level_count)}}},
      {"uploads",
       {{"total", total}, {"frames_with_uploads", frames_with}, {"max_per_frame", most}, {"per_frame", f.uploads}}},
      {"servo",
       {{"target_rate_hz", o.rate_hz},
        {"rate_hz", st.rate_hz},
        {"ticks", st.ticks},
        {"seconds", st.seconds},
        {"late_ticks", st.overruns},
        {"long_ticks", st.long_ticks},
        {"watchdog_trips", st.watchdog_trips},
        {"realtime", c.realtime},
        {"tick_ns", {{"median", st.compute_ns.median}, {"p99", st.compute_ns.p99}, {"max", st.compute_ns.max}}},
        {"period_ns", {{"median", st.period_ns.median}, {"p99", st.period_ns.p99}, {"max", st.period_ns.max}}}}},
      {"session",
       {{"sweeps", ss.sweeps},
        {"changed", ss.changed},
        {"publications", ss.publications},
        {"slabs_published", ss.slabs_published},
        {"edits_refused", ss.edits_refused},
        {"publish_deferred", ss.publish_deferred}}},
      {"screenshots", f.screenshot_files},
      {"workspace",
       {{"origin", {c.workspace.origin.x(), c.workspace.origin.y(), c.workspace.origin.z()}},
        {"scale", c.workspace.scale}}},
      {"probes", f.probes}};
  if (c.mouse)  // the mouse's smoothing: the handle's largest move per tick against per frame
    j["mouse"] = {{"max_tick_step_m", c.mouse->max_tick_step_m()}, {"max_frame_step_m", f.max_frame_step_m}};
  if (c.bake)
    j["bake"] = {{"input", c.bake->input},
                 {"seconds", c.bake->seconds},
                 {"frames", c.bake->frames},
                 {"stages", c.bake->stages},
                 {"slabs", c.bake->slabs},
                 {"grid", c.bake->grid},
                 {"met", c.bake->met},
                 {"max_pct", c.bake->max_pct},
                 {"max_back_pct", c.bake->max_back_pct},
                 {"rms_pct", c.bake->rms_pct},
                 {"rms_back_pct", c.bake->rms_back_pct}};
  if (o.verify_uploads) j["uploads"]["dirty_total"] = f.dirty_total, j["uploads"]["mismatched"] = f.mismatched_total;
  const std::string text = j.dump(1);
  write_file_atomic(o.report, text.data(), text.size());
}

}  // namespace hdm::studio
