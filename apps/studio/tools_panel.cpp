// SPDX-License-Identifier: MIT
#include "panels.h"

#include <hdm/edit/brush_registry.h>

#include <imgui.h>

namespace hdm::studio {

namespace {

// The tool combo's entries: the probe, then every registered brush's label.
bool tool_label(void*, int k, const char** out) {
  const auto brushes = brush_registry();
  if (k < 0 || k > static_cast<int>(brushes.size())) return false;
  *out = k == 0 ? "probe" : brushes[static_cast<size_t>(k - 1)].label;
  return true;
}

}  // namespace

PanelActions draw_tools_panel(ToolSettings& t, PanelFiles& files, const std::string& message) {
  PanelActions a;
  ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
  ImGui::Begin("Tools", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
  ImGui::PushItemWidth(170);
  int kind = t.brush ? static_cast<int>(*t.brush) + 1 : 0;
  ImGui::Combo("tool", &kind, &tool_label, nullptr, static_cast<int>(brush_registry().size()) + 1);
  t.brush = kind == 0 ? std::nullopt : std::optional<BrushTool>(static_cast<BrushTool>(kind - 1));
  const BrushInfo* info = t.brush ? find_brush(*t.brush) : nullptr;
  if (info && ImGui::IsItemHovered()) ImGui::SetTooltip("%s", info->summary);
  ImGui::SliderFloat("radius [mm]", &t.radius_mm, 0.2f, 20.0f, "%.1f");
  ImGui::SliderFloat("depth [mm]", &t.depth_mm, 0.0f, 5.0f, "%.2f");
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("how far the tool goes in below the surface under the cursor (shift+wheel)");
  ImGui::SliderFloat("strength", &t.strength, 0.0f, 1.0f, "%.2f");
  // Only the settings the brush reads (its registry entry's parameters).
  if (info && info->uses(BrushParam::Height)) ImGui::SliderFloat("height [mm]", &t.height_mm, 0.0f, 5.0f, "%.2f");
  if (info && info->uses(BrushParam::Resilience))
    ImGui::SliderFloat("resilience [mm]", &t.resilience_mm, 0.0f, 2.0f, "%.2f");
  if (info && info->uses(BrushParam::Field)) {
    static const char* const fields[] = {"colour",    "roughness",       "friction_static", "friction_dynamic",
                                         "stiffness", "layer_thickness", "hardness"};
    ImGui::Combo("field", &t.field, fields, IM_ARRAYSIZE(fields));
    if (t.field == static_cast<int>(BrushField::Colour))
      ImGui::ColorEdit3("colour", t.colour, ImGuiColorEditFlags_Float);
    else
      ImGui::InputFloat(t.field == static_cast<int>(BrushField::LayerThickness) ? "thickness [mm]" : "value", &t.value);
  }
  ImGui::Separator();
  // Applied by the servo thread from its next tick (a command, never a lock).
  ImGui::SliderFloat("stiffness [N/m]", &t.stiffness, 50.0f, 5000.0f, "%.0f", ImGuiSliderFlags_Logarithmic);
  ImGui::SliderFloat("friction", &t.friction, 0.0f, 2.0f, "%.2f");
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("factor on the surface's static and dynamic friction (painted with the friction fields)");
  ImGui::Separator();
  a.undo = ImGui::Button("undo");
  ImGui::SameLine();
  a.redo = ImGui::Button("redo");
  ImGui::SameLine();
  a.fit = ImGui::Button("fit view");
  ImGui::InputText("##save", files.save, sizeof files.save);
  ImGui::SameLine();
  a.save = ImGui::Button("save .hdm");
  ImGui::InputText("##export", files.export_path, sizeof files.export_path);
  ImGui::SameLine();
  a.export_model = ImGui::Button("export");
  ImGui::InputText("##shot", files.screenshot, sizeof files.screenshot);
  ImGui::SameLine();
  a.screenshot = ImGui::Button("screenshot");
  ImGui::PopItemWidth();
  if (!message.empty()) ImGui::TextUnformatted(message.c_str());
  ImGui::TextDisabled(
      "left: tool   right: orbit   middle / shift+right: pan\nwheel: zoom   shift+wheel: depth   F: fit\n"
      "ctrl+Z: undo   ctrl+shift+Z: redo");
  ImGui::End();
  return a;
}

void draw_status_overlay(const StatusFigures& s, float width) {
  ImGui::SetNextWindowPos(ImVec2(width - 10, 10), ImGuiCond_Always, ImVec2(1, 0));
  ImGui::SetNextWindowBgAlpha(0.6f);
  ImGui::Begin("status", nullptr,
               ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoFocusOnAppearing |
                   ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoMove);
  ImGui::Text("servo      %6.0f Hz (target %.0f)", s.servo_rate_hz, s.target_rate_hz);
  ImGui::Text("tick p99   %6.1f us, %lld late", s.tick_p99_us, static_cast<long long>(s.late_ticks));
  ImGui::Text("frame      %6.1f ms median, %.1f ms p99, level %d (grid %d)", s.frame_ms_median, s.frame_ms_p99, s.level,
              s.grid);
  ImGui::Text("uploaded   %6d slabs this frame (%lld total of %d)", s.uploaded,
              static_cast<long long>(s.uploaded_total), s.slabs);
  ImGui::Text("edits      %6.0f sweeps/s, epoch %llu", s.edits_per_s, static_cast<unsigned long long>(s.epoch));
  ImGui::Text("contact    %s, force %.2f N", s.contact ? "yes" : "no ", s.force_n);
  if (s.bridge)
    ImGui::Text("bridge     %s: %lld packets, %lld dropped, %lld watchdog trips", s.bridge,
                static_cast<long long>(s.bridge_accepted), static_cast<long long>(s.bridge_dropped),
                static_cast<long long>(s.bridge_watchdog_trips));
  ImGui::End();
}

}  // namespace hdm::studio
