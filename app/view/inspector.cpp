#include "app/view/inspector.h"

#include <imgui.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "app/view/cost_chart.h"
#include "app/view/state.h"

namespace gs::app {

namespace {

const ImU32 kTestsColour = IM_COL32(80, 140, 230, 255);
const ImU32 kRejectionsColour = IM_COL32(235, 70, 70, 255);
const ImU32 kCurrentColour = IM_COL32(255, 230, 80, 90);
constexpr float kMinStepWidth = 6.0f;  // the timeline scrolls rather than thin its steps more

// One descent a line, so that the column stays narrow and each descent reads whole.
std::string descents_text(const WalkCell& cell) {
  static const char* const kCase[] = {"reused", "index_only", "reinitialised"};
  std::string text;
  for (const WalkDescent& d : cell.descents) {
    char part[160];
    std::snprintf(part, sizeof part, "%s%c g%u G%llu s%u c%lld %s", text.empty() ? "" : "\n",
                  "xyz"[d.axis % 3], d.granularity, (unsigned long long)d.absolute_granularity,
                  d.state, (long long)d.cell, kCase[int(d.state_case)]);
    text += part;
  }
  return text.empty() ? "-" : text;
}

// A table cell's text; when the column is narrower than it, hovering shows it whole.
void cell_text(const std::string& text) {
  const float room = ImGui::GetContentRegionAvail().x;
  ImGui::TextUnformatted(text.c_str());
  if (ImGui::IsItemHovered() && ImGui::CalcTextSize(text.c_str()).x > room)
    ImGui::SetTooltip("%s", text.c_str());
}

void select_cell(ViewState& state, int cell) {
  if (cell == state.picked.cell) return;
  state.picked.cell = cell;
  state.walk_changed();
}

// first / prev / next / last and a slider over the cells.
void cell_navigation(ViewState& state) {
  const int last = std::max(int(state.picked.walk->cells.size()) - 1, 0);
  int cell = state.picked.cell;
  if (ImGui::Button("first")) cell = 0;
  ImGui::SameLine();
  if (ImGui::Button("prev")) cell = std::max(cell - 1, 0);
  ImGui::SameLine();
  if (ImGui::Button("next")) cell = std::min(cell + 1, last);
  ImGui::SameLine();
  if (ImGui::Button("last")) cell = last;
  ImGui::SameLine();
  ImGui::SetNextItemWidth(-1);
  ImGui::SliderInt("##cell", &cell, 0, last);
  select_cell(state, cell);
}

// True in the first frame that shows another inspected cell (kept in ImGui's storage of the
// panel), when the timeline and the table scroll to it: the buttons and the slider may pick
// a cell out of their view.
bool inspected_cell_moved(int cell) {
  int& shown = *ImGui::GetStateStorage()->GetIntRef(ImGui::GetID("inspected cell"), -1);
  const bool moved = shown != cell;
  shown = cell;
  return moved;
}

void step_tooltip(const WalkCell& c, int i) {
  ImGui::SetTooltip("step %d: depth %u, %u tests, %u rejected, nearest hit so far %d\n%s", i,
                    c.depth, c.tests, c.rejections, c.hit, descents_text(c).c_str());
}

// The walk as a row of steps, one column each: the bars are the triangle tests (blue) and
// mailbox rejections (red) made in that cell, on one scale; the inspected step is
// highlighted, and clicking a column inspects that step.
void walk_timeline(ViewState& state, float height, bool follow) {
  const std::vector<WalkCell>& cells = state.picked.walk->cells;
  const int count = int(cells.size());
  const float room = ImGui::GetContentRegionAvail().x;
  const float step = std::max(room / float(std::max(count, 1)), kMinStepWidth);
  const bool scrolls = step * float(count) > room;
  ImGui::BeginChild("timeline", ImVec2(0, height), false, ImGuiWindowFlags_HorizontalScrollbar);
  const float bar_room = height - (scrolls ? ImGui::GetStyle().ScrollbarSize : 0.0f);
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  ImGui::InvisibleButton("steps", ImVec2(std::max(step * float(count), 1.0f), bar_room));
  uint32_t most = 1;
  for (const WalkCell& c : cells) most = std::max({most, c.tests, c.rejections});
  ImDrawList* draw = ImGui::GetWindowDrawList();
  const float bottom = origin.y + bar_room;
  for (int i = 0; i < count; ++i) {
    const float x = origin.x + step * float(i);
    if (i == state.picked.cell)
      draw->AddRectFilled(ImVec2(x, origin.y), ImVec2(x + step, bottom), kCurrentColour);
    if (i == state.picked.cell && follow)
      ImGui::SetScrollFromPosX(ImGui::GetCursorStartPos().x + step * (float(i) + 0.5f));
    const WalkCell& c = cells[size_t(i)];
    const float half = step * 0.4f, per_unit = (bar_room - 2) / float(most);
    draw->AddRectFilled(ImVec2(x + step * 0.1f, bottom - per_unit * float(c.tests)),
                        ImVec2(x + step * 0.1f + half, bottom), kTestsColour);
    draw->AddRectFilled(ImVec2(x + step * 0.5f, bottom - per_unit * float(c.rejections)),
                        ImVec2(x + step * 0.5f + half, bottom), kRejectionsColour);
  }
  const int hovered = ImGui::IsItemHovered()
                          ? slot_at(ImGui::GetIO().MousePos.x, origin.x, step * float(count), count)
                          : -1;
  if (hovered >= 0) {
    step_tooltip(cells[size_t(hovered)], hovered);
    if (ImGui::IsItemClicked()) select_cell(state, hovered);
  }
  ImGui::EndChild();
}

void walk_row(ViewState& state, int i, bool follow) {
  const WalkCell& c = state.picked.walk->cells[size_t(i)];
  const std::string descents = descents_text(c);
  ImGui::TableNextRow();
  ImGui::TableNextColumn();
  // As tall as the row's descents, so that the whole row is the click target.
  const float lines = float(std::max<size_t>(c.descents.size(), 1));
  if (ImGui::Selectable(std::to_string(i).c_str(), i == state.picked.cell,
                        ImGuiSelectableFlags_SpanAllColumns,
                        ImVec2(0, lines * ImGui::GetTextLineHeight())))
    select_cell(state, i);
  if (follow && i == state.picked.cell && !ImGui::IsItemVisible()) ImGui::SetScrollHereY();
  ImGui::TableNextColumn();
  ImGui::Text("%u", c.depth);
  ImGui::TableNextColumn();
  // A subdivided voxel's spanning triangles, searched on the way down, are not entered.
  cell_text(c.spanning           ? "spanning"
            : c.entered_axis < 0 ? "start"
                                 : std::string(1, "xyz"[c.entered_axis % 3]));
  ImGui::TableNextColumn();
  ImGui::Text("%u", c.climbed);
  ImGui::TableNextColumn();
  cell_text(descents);
  ImGui::TableNextColumn();
  ImGui::Text("%u", c.tests);
  ImGui::TableNextColumn();
  ImGui::Text("%u", c.rejections);
  ImGui::TableNextColumn();
  ImGui::Text("%d", c.hit);
  ImGui::TableNextColumn();
  ImGui::Text("%u", c.voxel);
}

// Rows are as tall as their descents, so every row is drawn (ImGuiListClipper needs rows of
// one height); walks are hundreds of cells, not millions.
void walk_table(ViewState& state, bool follow) {
  const ImGuiTableFlags flags = ImGuiTableFlags_RowBg | ImGuiTableFlags_ScrollY |
                                ImGuiTableFlags_ScrollX | ImGuiTableFlags_Resizable |
                                ImGuiTableFlags_SizingFixedFit | ImGuiTableFlags_BordersInnerV;
  if (!ImGui::BeginTable("walk", 9, flags)) return;
  for (const char* name :
       {"#", "depth", "entered", "climbed", "descents", "tests", "rejected", "hit", "voxel"})
    ImGui::TableSetupColumn(name);
  ImGui::TableSetupScrollFreeze(1, 1);
  ImGui::TableHeadersRow();
  for (int i = 0; i < int(state.picked.walk->cells.size()); ++i) walk_row(state, i, follow);
  ImGui::EndTable();
}

// The chart's numbers as a table: each granularity tried on the chosen axis, per ray.
void alternatives_table(const VoxelCostReport& r) {
  const ImGuiTableFlags flags =
      ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingFixedFit | ImGuiTableFlags_BordersInnerV;
  if (!ImGui::BeginTable("alternatives", 6, flags)) return;
  for (const char* name : {"g", "int", "trav", "rep", "ver", "total"})
    ImGui::TableSetupColumn(name);
  ImGui::TableHeadersRow();
  for (const VoxelCostReport::Alternative& alt : r.alternatives) {
    if (alt.axis != r.axis) continue;
    const CutCost& c = alt.cost;
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    ImGui::Text("%d%s", alt.granularity, alt.granularity == r.granularity ? " (chosen)" : "");
    for (const double value : {c.int_cost, c.trav_cost, c.rep_cost, c.ver_cost, c.total}) {
      ImGui::TableNextColumn();
      ImGui::Text("%.4g", value);
    }
  }
  ImGui::EndTable();
}

// The report's figures as text, wrapped to the panel.
void cost_figures(const PickedWalk& picked) {
  const VoxelCostReport& r = picked.cost->report;
  const VoxelFigures& f = r.figures;
  ImGui::TextWrapped("N = %.0f, extent %.3g x %.3g x %.3g, mean size %.3g %.3g %.3g", f.triangles,
                     f.extent[0], f.extent[1], f.extent[2], f.mean_size[0], f.mean_size[1],
                     f.mean_size[2]);
  ImGui::TextWrapped("estimated rays %.4g (§6.5), subdivision cost Subcost*N = %.4g", f.rays,
                     r.subdivision_cost);
  for (const AxisPlan& plan : r.plans)
    ImGui::TextWrapped("axis %c: best g %d, %.4g per ray vs %.4g uncut: %s", "xyz"[plan.axis],
                       plan.granularity > 1 ? plan.granularity : plan.cost.spanned_cells,
                       plan.cost.total, plan.no_split, plan.granularity > 1 ? "cut pays" : "keep");
  const RayInVoxel& here = picked.cost->ray_here;
  ImGui::TextWrapped("this ray here: %d cells, %llu tests, %llu mailbox rejections", here.cells,
                     (unsigned long long)here.tests, (unsigned long long)here.rejections);
  alternatives_table(r);
}

// The §6 cost model for the inspected cell's parent voxel, as the build evaluated it
// (Grid1D::cost_report): the chart first, the numbers folded below it.
void cost_breakdown(const PickedWalk& picked) {
  if (!picked.cost) {
    ImGui::TextWrapped("Cell %d: no parent voxel (the root is a leaf) or no 1D grid.", picked.cell);
    return;
  }
  const VoxelCostReport& r = picked.cost->report;
  ImGui::TextWrapped("parent voxel %u, depth %u: cut on %c into g = %d", r.voxel, r.depth,
                     "xyz"[std::max(r.axis, 0) % 3], r.granularity);
  constexpr float kMinChartHeight = 150.0f;
  const ImVec2 room = ImGui::GetContentRegionAvail();
  cost_chart(r, ImVec2(room.x, std::max(room.y, kMinChartHeight)));
  if (ImGui::CollapsingHeader("numbers")) cost_figures(picked);
}

}  // namespace

void walk_tab(ViewState& state) {
  const PickedWalk& picked = state.picked;
  if (!picked.walk) {
    ImGui::TextWrapped("Click the image to inspect that pixel's ray walk.");
    return;
  }
  ImGui::TextWrapped("pixel %d,%d  hit %d  t %.6g  %zu cells", picked.pixel[0], picked.pixel[1],
                     picked.walk->hit.id, double(picked.walk->hit.t), picked.walk->cells.size());
  cell_navigation(state);
  const ImVec2 room = ImGui::GetContentRegionAvail();
  ImGui::BeginChild("walk steps", ImVec2(room.x * 0.5f, 0));
  const bool follow = inspected_cell_moved(picked.cell);
  walk_timeline(state, std::clamp(room.y * 0.3f, 28.0f, 80.0f), follow);
  walk_table(state, follow);
  ImGui::EndChild();
  ImGui::SameLine();
  ImGui::BeginChild("cost", ImVec2(0, 0));
  cost_breakdown(picked);
  ImGui::EndChild();
}

}  // namespace gs::app
