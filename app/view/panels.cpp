#include "app/view/panels.h"

#include <imgui.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "app/view/camera_input.h"
#include "app/view/inspector.h"
#include "app/view/overlay_cache.h"
#include "app/view/overlay_panel.h"
#include "app/view/scene_opener.h"
#include "app/view/state.h"
#include "app/view/structure_editor.h"

namespace gs::app {

namespace {

const ImVec4 kWarning(1.0f, 0.4f, 0.4f, 1.0f);  // errors and figures that need attention
constexpr ImGuiWindowFlags kPanelFlags = ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize |
                                         ImGuiWindowFlags_NoCollapse |
                                         ImGuiWindowFlags_NoSavedSettings;

void place(float x, float y, float w, float h) {
  ImGui::SetNextWindowPos(ImVec2(x, y));
  ImGui::SetNextWindowSize(ImVec2(w, h));
}

std::string optional_figure(const std::optional<uint64_t>& value) {
  return value ? std::to_string(*value) : std::string("n/a");
}

void statistics_tab(const ViewState& state, const OverlayCache& overlays) {
  const ViewSetup& setup = state.session.setup();
  const ProgressiveFrame& frame = state.session.frame();
  const StructureStats& s = frame.structure;
  ImGui::Text("%s, %zu triangles, pass %d, %d spp, %.3g rays/s, %llu rays", setup.accel.c_str(),
              setup.scene->triangle_count(), frame.pass, frame.spp, frame.rays_per_second,
              (unsigned long long)frame.rays);
  const TraceCounters& c = frame.counters;
  if (c.packet_rays + c.packet_fallback_rays > 0)
    ImGui::Text(
        "packets: %llu rays in %llu packets, %.0f%% active per step, %llu fell back "
        "to single rays; pass %d done %.2f s after the restart",
        (unsigned long long)c.packet_rays, (unsigned long long)c.packets,
        100.0 * c.packet_active_fraction(), (unsigned long long)c.packet_fallback_rays, frame.pass,
        frame.seconds);
  else
    ImGui::Text("packets: %s; pass %d done %.2f s after the restart",
                setup.packets ? "none walked (this structure traces rays one at a time)" : "off",
                frame.pass, frame.seconds);
  ImGui::Text("nodes %s  subdivided %s  leaves %s  states %s  memory %.1f MB (budget %s)",
              optional_figure(s.nodes).c_str(), optional_figure(s.voxels_subdivided).c_str(),
              optional_figure(s.leaves).c_str(), optional_figure(s.traversal_states).c_str(),
              double(s.memory_bytes) / 1e6, byte_text(setup.params.memory_budget).c_str());
  if (s.voxels_over_budget > 0)
    ImGui::TextColored(kWarning, "%llu voxels over budget: left as leaves (raise the budget)",
                       (unsigned long long)s.voxels_over_budget);
  else
    ImGui::TextDisabled("voxels over budget: 0");
  ImGui::Text("overlays show %zu nodes built (refreshed every %.1f s while it grows)",
              overlays.nodes_built(), kOverlayInterval);
  if (!frame.error.empty()) ImGui::TextColored(kWarning, "%s", frame.error.c_str());
  for (const LineSet& set : overlays.structure_lines())
    for (size_t i = 0; i < std::min<size_t>(set.legend.size(), 8); ++i) {
      const glm::vec4 c = set.legend[i].color;
      ImGui::TextColored(ImVec4(c.r, c.g, c.b, 1.0f), "%s", set.legend[i].label.c_str());
    }
}

void states_tab(const OverlayCache& overlays) {
  if (!ImGui::BeginTable("states", 5, ImGuiTableFlags_RowBg | ImGuiTableFlags_ScrollY)) return;
  ImGui::TableSetupColumn("state");
  ImGui::TableSetupColumn("axis");
  ImGui::TableSetupColumn("G");
  ImGui::TableSetupColumn("voxels");
  ImGui::TableSetupColumn("rays that used it");
  ImGui::TableHeadersRow();
  for (const StateRow& row : overlays.states()) {
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    ImGui::Text("%u", row.state);
    ImGui::TableNextColumn();
    ImGui::Text("%c", "xyz"[row.axis % 3]);
    ImGui::TableNextColumn();
    ImGui::Text("%llu", (unsigned long long)row.absolute_granularity);
    ImGui::TableNextColumn();
    ImGui::Text("%llu", (unsigned long long)row.voxels);
    ImGui::TableNextColumn();
    ImGui::Text("%llu", (unsigned long long)row.rays);
  }
  ImGui::EndTable();
}

}  // namespace

Panels::Panels(StructureEditor& structure, OverlayCache& overlays, CameraInput& camera,
               SceneOpener& scene)
    : structure_(structure), overlays_(overlays), camera_(camera), scene_(scene) {}

void Panels::draw(ViewState& state) {
  controls_panel(state);
  bottom_panel(state);
}

void Panels::controls_panel(ViewState& state) {
  const ImVec2 display = ImGui::GetIO().DisplaySize;
  const float left = state.viewport.w;
  place(left, 0, std::max(display.x - left, 1.0f), display.y);
  ImGui::Begin("controls", nullptr, kPanelFlags);
  const ImGuiTreeNodeFlags open = ImGuiTreeNodeFlags_DefaultOpen;
  if (ImGui::CollapsingHeader("structure", open)) structure_.controls(state);
  if (ImGui::CollapsingHeader("overlays", open)) overlay_controls(state, overlays_);
  if (ImGui::CollapsingHeader("camera", open)) camera_.controls(state);
  if (ImGui::CollapsingHeader("scene", open)) scene_.controls();
  const std::string& status = state.status.text();
  if (!status.empty()) ImGui::TextWrapped("%s", status.c_str());
  ImGui::End();
}

void Panels::bottom_panel(ViewState& state) {
  const Viewport& view = state.viewport;
  place(0, view.h, view.w, std::max(ImGui::GetIO().DisplaySize.y - view.h, 1.0f));
  ImGui::Begin("statistics and inspector", nullptr, kPanelFlags);
  if (ImGui::BeginTabBar("tabs")) {
    if (ImGui::BeginTabItem("walk")) {
      walk_tab(state);
      ImGui::EndTabItem();
    }
    if (ImGui::BeginTabItem("statistics")) {
      statistics_tab(state, overlays_);
      ImGui::EndTabItem();
    }
    if (ImGui::BeginTabItem("states")) {
      states_tab(overlays_);
      ImGui::EndTabItem();
    }
    ImGui::EndTabBar();
  }
  ImGui::End();
}

}  // namespace gs::app
