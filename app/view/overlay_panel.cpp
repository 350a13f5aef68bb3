#include "app/view/overlay_panel.h"

#include <imgui.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>

#include "app/view/overlay_cache.h"
#include "app/view/state.h"

namespace gs::app {

namespace {

const char* const kHeatNames[] = {"none", "steps", "tests", "built"};
const ImVec4 kCappedNote(1.0f, 0.75f, 0.3f, 1.0f);  // amber: some lines were left out

// The turbo bar from the range's low to its high end.
void heat_legend(const HeatMap& heat) {
  constexpr int kSteps = 32;
  constexpr float kHeight = 10.0f;
  ImDrawList* draw = ImGui::GetWindowDrawList();
  const ImVec2 at = ImGui::GetCursorScreenPos();
  const float width = ImGui::GetContentRegionAvail().x;
  for (int i = 0; i < kSteps; ++i) {
    const std::array<uint8_t, 3> c0 = turbo(float(i) / kSteps), c1 = turbo(float(i + 1) / kSteps);
    const ImU32 left = IM_COL32(c0[0], c0[1], c0[2], 255);
    const ImU32 right = IM_COL32(c1[0], c1[1], c1[2], 255);
    draw->AddRectFilledMultiColor(ImVec2(at.x + width * i / kSteps, at.y),
                                  ImVec2(at.x + width * (i + 1) / kSteps, at.y + kHeight), left,
                                  right, right, left);
  }
  ImGui::Dummy(ImVec2(width, kHeight));
  ImGui::Text("%.3g", heat.lo);
  ImGui::SameLine(std::max(width - 60.0f, 40.0f));
  ImGui::Text("%.3g", heat.hi);
}

// The heatmap's figure at the pixel under the mouse.
void heat_under_cursor(const ViewState& state, const HeatMap& heat) {
  const ImGuiIO& io = ImGui::GetIO();
  const Viewport& view = state.viewport;
  const ProgressiveFrame& frame = state.session.frame();
  if (!view.contains(io.MousePos) || frame.width <= 0 || heat.values().empty()) return;
  const int x = int((io.MousePos.x - view.x) / view.w * frame.width);
  const int y = int((io.MousePos.y - view.y) / view.h * frame.height);
  const size_t i = size_t(std::clamp(y, 0, frame.height - 1)) * size_t(frame.width) +
                   size_t(std::clamp(x, 0, frame.width - 1));
  if (i < heat.values().size())
    ImGui::Text("under the cursor (%d, %d): %.2f", x, y, heat.values()[i]);
}

void heat_controls(ViewState& state, HeatMap& heat) {
  int kind = int(state.overlays.heat);
  if (ImGui::Combo("heatmap", &kind, kHeatNames, IM_ARRAYSIZE(kHeatNames))) {
    state.overlays.heat = HeatKind(kind);
    heat.invalidate();
  }
  if (state.overlays.heat == HeatKind::none) return;
  if (state.session.setup().packets)
    ImGui::TextWrapped(
        "packets on: each 8x8 block's pixels share its rays' cost (untick "
        "packets for each pixel's own)");
  if (ImGui::Checkbox("auto range", &heat.auto_range)) heat.invalidate();
  if (ImGui::DragFloatRange2("range", &heat.lo, &heat.hi, 0.1f, 0.0f, 1e6f)) {
    heat.auto_range = false;
    heat.invalidate();
  }
  ImGui::Text("max %.2f per sample", heat.max());
  heat_legend(heat);
  heat_under_cursor(state, heat);
}

// Which levels and which voxels cells and states show, and what the line cap left out.
void structure_filter_controls(ViewState& state, const OverlayCache& overlays) {
  OverlaySelection& shown = state.overlays;
  if (!shown.cells && !shown.states) return;
  bool changed = ImGui::Checkbox("near the walk", &shown.near_walk);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("only the voxels the clicked ray went through, with their walls");
  int first = int(shown.depths.first), last = int(shown.depths.last);
  // The range leaves room on its row for its label and the "all" button.
  const ImGuiStyle& style = ImGui::GetStyle();
  ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x - ImGui::CalcTextSize("levels").x -
                          ImGui::CalcTextSize("all").x - 2 * style.FramePadding.x -
                          style.ItemInnerSpacing.x - style.ItemSpacing.x);
  if (ImGui::DragIntRange2("levels", &first, &last, 0.1f, 0, kMaxDepth)) {
    shown.depths = {uint32_t(std::clamp(first, 0, kMaxDepth)),
                    uint32_t(std::clamp(std::max(first, last), 0, kMaxDepth))};
    changed = true;
  }
  ImGui::SameLine();
  if (ImGui::SmallButton("all")) shown.depths = {}, changed = true;
  if (changed) state.overlays_stale = true;
  for (const LineSet& set : overlays.structure_lines()) {
    const bool capped = set.coverage.shown() < set.coverage.total();
    ImGui::PushStyleColor(ImGuiCol_Text,
                          capped ? kCappedNote : ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
    ImGui::TextWrapped("%s", set.coverage.describe().c_str());
    ImGui::PopStyleColor();
  }
  if (shown.near_walk && !state.picked.walk) ImGui::TextDisabled("click the image to pick a walk");
}

}  // namespace

void choose_overlays(ViewState& state, HeatMap& heat, const OverlaySelection& selection) {
  state.overlays = selection;
  heat.invalidate();
  state.walk_changed();  // also marks the structure's overlays stale
}

void overlay_controls(ViewState& state, OverlayCache& overlays) {
  OverlaySelection& shown = state.overlays;
  bool changed = ImGui::Checkbox("cells", &shown.cells);
  ImGui::SameLine();
  changed |= ImGui::Checkbox("states", &shown.states);
  ImGui::SameLine();
  if (ImGui::Checkbox("walk", &shown.walk)) state.walk_changed();
  int by_axis = state.colour_by_axis ? 1 : 0;
  ImGui::TextUnformatted("cell colour");
  ImGui::SameLine();
  changed |= ImGui::RadioButton("depth", &by_axis, 0);
  ImGui::SameLine();
  changed |= ImGui::RadioButton("axis", &by_axis, 1);
  state.colour_by_axis = by_axis == 1;
  if (changed) state.overlays_stale = true;
  structure_filter_controls(state, overlays);
  heat_controls(state, overlays.heat());
  const std::string list = format_overlays(shown);
  ImGui::TextDisabled("as --overlay: %s", list.empty() ? "(none)" : list.c_str());
}

}  // namespace gs::app
