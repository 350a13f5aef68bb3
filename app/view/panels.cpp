#include "app/view/panels.h"

#include <imgui.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "app/view/camera_input.h"
#include "app/view/compare_view.h"
#include "app/view/inspector.h"
#include "app/view/overlay_cache.h"
#include "app/view/overlay_panel.h"
#include "app/view/scene_opener.h"
#include "app/view/state.h"
#include "app/view/structure_editor.h"

namespace gs::app {

namespace {

const ImVec4 kWarning(1.0f, 0.4f, 0.4f, 1.0f);  // errors and figures that need attention
// No title bars: the layout places and sizes the panels, and a small window needs the rows.
// A click in a panel leaves it behind the help overlay.
constexpr ImGuiWindowFlags kPanelFlags = ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoMove |
                                         ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                                         ImGuiWindowFlags_NoSavedSettings |
                                         ImGuiWindowFlags_NoBringToFrontOnFocus;

void place(const Rect& rect) {
  ImGui::SetNextWindowPos(ImVec2(rect.x, rect.y));
  ImGui::SetNextWindowSize(ImVec2(rect.w, rect.h));
}

// A warning wrapped to the panel's width (TextColored does not wrap).
void warning_text(const std::string& text) {
  ImGui::PushStyleColor(ImGuiCol_Text, kWarning);
  ImGui::TextWrapped("%s", text.c_str());
  ImGui::PopStyleColor();
}

std::string optional_figure(const std::optional<uint64_t>& value) {
  return value ? std::to_string(*value) : std::string("n/a");
}

void statistics_tab(const ViewState& state, const OverlayCache& overlays) {
  const ViewSetup& setup = state.session.setup();
  const ProgressiveFrame& frame = state.session.frame();
  const StructureStats& s = frame.structure;
  ImGui::TextWrapped("%s, %zu triangles, pass %d, %d spp, %.3g rays/s, %llu rays",
                     setup.accel.c_str(), setup.scene->triangle_count(), frame.pass, frame.spp,
                     frame.rays_per_second, (unsigned long long)frame.rays);
  const TraceCounters& c = frame.counters;
  if (c.packet_rays + c.packet_fallback_rays > 0)
    ImGui::TextWrapped(
        "packets: %llu rays in %llu packets, %.0f%% active per step, %llu fell back "
        "to single rays; pass %d done %.2f s after the restart",
        (unsigned long long)c.packet_rays, (unsigned long long)c.packets,
        100.0 * c.packet_active_fraction(), (unsigned long long)c.packet_fallback_rays, frame.pass,
        frame.seconds);
  else
    ImGui::TextWrapped(
        "packets: %s; pass %d done %.2f s after the restart",
        setup.packets ? "none walked (this structure traces rays one at a time)" : "off",
        frame.pass, frame.seconds);
  ImGui::TextWrapped("nodes %s  subdivided %s  leaves %s  states %s  memory %.1f MB (budget %s)",
                     optional_figure(s.nodes).c_str(), optional_figure(s.voxels_subdivided).c_str(),
                     optional_figure(s.leaves).c_str(), optional_figure(s.traversal_states).c_str(),
                     double(s.memory_bytes) / 1e6, byte_text(setup.params.memory_budget).c_str());
  if (s.voxels_over_budget > 0)
    warning_text(std::to_string(s.voxels_over_budget) +
                 " voxels over budget: left as leaves (raise the budget)");
  else
    ImGui::TextDisabled("voxels over budget: 0");
  ImGui::TextWrapped("overlays show %zu nodes built (refreshed every %.1f s while it grows)",
                     overlays.nodes_built(), kOverlayInterval);
  if (!frame.error.empty()) warning_text(frame.error);
  for (const LineSet& set : overlays.structure_lines())
    for (size_t i = 0; i < std::min<size_t>(set.legend.size(), 8); ++i) {
      const glm::vec4 c = set.legend[i].color;
      ImGui::TextColored(ImVec4(c.r, c.g, c.b, 1.0f), "%s", set.legend[i].label.c_str());
    }
}

}  // namespace

Panels::Panels(StructureEditor& structure, OverlayCache& overlays, CameraInput& camera,
               SceneOpener& scene, CompareView& compare)
    : structure_(structure),
      overlays_(overlays),
      camera_(camera),
      scene_(scene),
      compare_(compare) {}

void Panels::draw(ViewState& state, const WindowLayout& layout) {
  controls_panel(state, layout.controls);
  bottom_panel(state, layout.bottom);
}

void Panels::controls_panel(ViewState& state, const Rect& rect) {
  place(rect);
  ImGui::Begin("controls", nullptr, kPanelFlags);
  const ImGuiTreeNodeFlags open = ImGuiTreeNodeFlags_DefaultOpen;
  if (ImGui::CollapsingHeader("structure", open)) structure_.controls(state);
  if (ImGui::CollapsingHeader("overlays", open)) overlay_controls(state, overlays_);
  if (ImGui::CollapsingHeader("A/B compare", open)) compare_.controls(state, overlays_.heat());
  if (ImGui::CollapsingHeader("camera", open)) camera_.controls(state);
  if (ImGui::CollapsingHeader("scene", open)) scene_.controls();
  const std::string& status = state.status.text();
  if (!status.empty()) ImGui::TextWrapped("%s", status.c_str());
  ImGui::End();
}

void Panels::select_tab(const std::string& name) { tab_asked_ = name; }

// BeginTabItem for a tab of the bottom panel, selecting it if a script asked for it.
bool Panels::tab(const char* name) {
  return ImGui::BeginTabItem(name, nullptr, tab_asked_ == name ? ImGuiTabItemFlags_SetSelected : 0);
}

void Panels::bottom_panel(ViewState& state, const Rect& rect) {
  place(rect);
  ImGui::Begin("statistics and inspector", nullptr, kPanelFlags);
  if (ImGui::BeginTabBar("tabs")) {
    if (tab("walk")) {
      walk_tab(state);
      ImGui::EndTabItem();
    }
    if (tab("statistics")) {
      statistics_tab(state, overlays_);
      ImGui::EndTabItem();
    }
    if (tab("states")) {
      states_.draw(overlays_.states());
      ImGui::EndTabItem();
    }
    ImGui::EndTabBar();
  }
  tab_asked_.clear();
  ImGui::End();
}

}  // namespace gs::app
