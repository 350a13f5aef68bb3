#include "app/view/inspector.h"

#include <imgui.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "app/view/state.h"

namespace gs::app {

namespace {

std::string descents_text(const WalkCell& cell) {
  static const char* const kCase[] = {"reused", "index_only", "reinitialised"};
  std::string text;
  for (const WalkDescent& d : cell.descents) {
    char part[160];
    std::snprintf(part, sizeof part, "%s%c g%u G%llu s%u c%lld %s", text.empty() ? "" : "; ",
                  "xyz"[d.axis % 3], d.granularity, (unsigned long long)d.absolute_granularity,
                  d.state, (long long)d.cell, kCase[int(d.state_case)]);
    text += part;
  }
  return text.empty() ? "-" : text;
}

// first / prev / next / last and a slider over the cells.
void cell_navigation(ViewState& state) {
  PickedWalk& picked = state.picked;
  const int last = std::max(int(picked.walk->cells.size()) - 1, 0);
  const int before = picked.cell;
  if (ImGui::Button("first")) picked.cell = 0;
  ImGui::SameLine();
  if (ImGui::Button("prev")) picked.cell = std::max(picked.cell - 1, 0);
  ImGui::SameLine();
  if (ImGui::Button("next")) picked.cell = std::min(picked.cell + 1, last);
  ImGui::SameLine();
  if (ImGui::Button("last")) picked.cell = last;
  ImGui::SameLine();
  ImGui::SetNextItemWidth(-1);
  ImGui::SliderInt("##cell", &picked.cell, 0, last);
  if (picked.cell != before) state.walk_changed();
}

void walk_row(ViewState& state, int i) {
  const WalkCell& c = state.picked.walk->cells[size_t(i)];
  ImGui::TableNextRow();
  ImGui::TableNextColumn();
  if (ImGui::Selectable(std::to_string(i).c_str(), i == state.picked.cell,
                        ImGuiSelectableFlags_SpanAllColumns)) {
    state.picked.cell = i;
    state.walk_changed();
  }
  ImGui::TableNextColumn();
  ImGui::Text("%u", c.depth);
  ImGui::TableNextColumn();
  ImGui::TextUnformatted(c.entered_axis < 0 ? "start"
                                            : std::string(1, "xyz"[c.entered_axis % 3]).c_str());
  ImGui::TableNextColumn();
  ImGui::Text("%u", c.climbed);
  ImGui::TableNextColumn();
  ImGui::TextUnformatted(descents_text(c).c_str());
  ImGui::TableNextColumn();
  ImGui::Text("%u", c.tests);
  ImGui::TableNextColumn();
  ImGui::Text("%u", c.rejections);
  ImGui::TableNextColumn();
  ImGui::Text("%d", c.hit);
  ImGui::TableNextColumn();
  ImGui::Text("%u", c.voxel);
}

void walk_table(ViewState& state) {
  const ImGuiTableFlags flags = ImGuiTableFlags_RowBg | ImGuiTableFlags_ScrollY |
                                ImGuiTableFlags_ScrollX | ImGuiTableFlags_Resizable |
                                ImGuiTableFlags_SizingFixedFit;
  if (!ImGui::BeginTable("walk", 9, flags)) return;
  for (const char* name :
       {"#", "depth", "entered", "climbed", "descents", "tests", "rejected", "hit", "voxel"})
    ImGui::TableSetupColumn(name);
  ImGui::TableSetupScrollFreeze(1, 1);
  ImGui::TableHeadersRow();
  ImGuiListClipper clipper;
  clipper.Begin(int(state.picked.walk->cells.size()));
  while (clipper.Step())
    for (int i = clipper.DisplayStart; i < clipper.DisplayEnd; ++i) walk_row(state, i);
  ImGui::EndTable();
}

// The cost of each granularity tried on the chosen axis, the chosen one starred.
void cut_alternatives(const VoxelCostReport& r) {
  ImGui::TextUnformatted("g     int    trav   rep    ver    total  (per ray, chosen axis)");
  for (const VoxelCostReport::Alternative& alt : r.alternatives) {
    if (alt.axis != r.axis) continue;
    const CutCost& c = alt.cost;
    ImGui::Text("%-3d%s %-6.3g %-6.3g %-6.3g %-6.3g %-6.3g", alt.granularity,
                alt.granularity == r.granularity ? "*" : " ", c.int_cost, c.trav_cost, c.rep_cost,
                c.ver_cost, c.total);
  }
}

// The §6 cost model for the inspected cell's parent voxel, as the build evaluated it
// (Grid1D::cost_report), beside what this ray did there.
void cost_breakdown(const PickedWalk& picked) {
  if (!picked.cost) {
    ImGui::TextWrapped("Cell %d: no parent voxel (the root is a leaf) or no 1D grid.", picked.cell);
    return;
  }
  const VoxelCostReport& r = picked.cost->report;
  const VoxelFigures& f = r.figures;
  ImGui::Text("parent voxel %u, depth %u: cut on %c into g = %d", r.voxel, r.depth,
              "xyz"[std::max(r.axis, 0) % 3], r.granularity);
  ImGui::Text("N = %.0f, extent %.3g x %.3g x %.3g, mean size %.3g %.3g %.3g", f.triangles,
              f.extent[0], f.extent[1], f.extent[2], f.mean_size[0], f.mean_size[1],
              f.mean_size[2]);
  ImGui::Text("estimated rays %.4g, subdivision cost Subcost*N = %.4g", f.rays, r.subdivision_cost);
  for (const AxisPlan& plan : r.plans)
    ImGui::Text("axis %c: best g %d, %.4g per ray vs %.4g uncut: %s", "xyz"[plan.axis],
                plan.granularity > 1 ? plan.granularity : plan.cost.spanned_cells, plan.cost.total,
                plan.no_split, plan.granularity > 1 ? "cut pays" : "keep");
  cut_alternatives(r);
  const RayInVoxel& here = picked.cost->ray_here;
  ImGui::Text("this ray here: %d cells, %llu tests, %llu mailbox rejections", here.cells,
              (unsigned long long)here.tests, (unsigned long long)here.rejections);
}

}  // namespace

void walk_tab(ViewState& state) {
  const PickedWalk& picked = state.picked;
  if (!picked.walk) {
    ImGui::TextUnformatted("Click the image to inspect that pixel's ray walk.");
    return;
  }
  ImGui::Text("pixel %d,%d  hit %d  t %.6g  %zu cells", picked.pixel[0], picked.pixel[1],
              picked.walk->hit.id, double(picked.walk->hit.t), picked.walk->cells.size());
  cell_navigation(state);
  const float half = ImGui::GetContentRegionAvail().x * 0.6f;
  ImGui::BeginChild("cells", ImVec2(half, 0));
  walk_table(state);
  ImGui::EndChild();
  ImGui::SameLine();
  ImGui::BeginChild("cost", ImVec2(0, 0));
  cost_breakdown(picked);
  ImGui::EndChild();
}

}  // namespace gs::app
