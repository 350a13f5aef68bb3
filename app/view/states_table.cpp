#include "app/view/states_table.h"

#include <imgui.h>

#include <algorithm>
#include <tuple>

namespace gs::app {

namespace {

uint64_t sort_key(const StateRow& row, StateColumn column) {
  switch (column) {
    case StateColumn::state:
      return row.state;
    case StateColumn::axis:
      return uint64_t(row.axis);
    case StateColumn::granularity:
      return row.absolute_granularity;
    case StateColumn::voxels:
      return row.voxels;
    case StateColumn::rays:
      return row.rays;
  }
  return row.state;
}

}  // namespace

void sort_state_rows(std::vector<StateRow>& rows, StateColumn column, bool descending) {
  std::sort(rows.begin(), rows.end(), [&](const StateRow& a, const StateRow& b) {
    const uint64_t ka = sort_key(a, column), kb = sort_key(b, column);
    if (ka != kb) return descending ? ka > kb : ka < kb;
    return a.state < b.state;
  });
}

void StatesTable::draw(const std::vector<StateRow>& rows) {
  const ImGuiTableFlags flags = ImGuiTableFlags_RowBg | ImGuiTableFlags_ScrollY |
                                ImGuiTableFlags_Sortable | ImGuiTableFlags_Resizable |
                                ImGuiTableFlags_BordersInnerV;
  if (!ImGui::BeginTable("states", 5, flags)) return;
  ImGui::TableSetupColumn("state", ImGuiTableColumnFlags_DefaultSort);
  ImGui::TableSetupColumn("axis");
  ImGui::TableSetupColumn("G");
  ImGui::TableSetupColumn("voxels");
  ImGui::TableSetupColumn("rays that used it");
  ImGui::TableSetupScrollFreeze(0, 1);
  ImGui::TableHeadersRow();
  sort_if_needed(rows);
  ImGuiListClipper clipper;  // rows of one line each: only the visible ones are drawn
  clipper.Begin(int(shown_.size()));
  while (clipper.Step())
    for (int i = clipper.DisplayStart; i < clipper.DisplayEnd; ++i) {
      const StateRow& row = shown_[size_t(i)];
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

// Sorts again when a header was clicked or the overlay cache read new rows (the rays
// column grows while the image refines).
void StatesTable::sort_if_needed(const std::vector<StateRow>& rows) {
  ImGuiTableSortSpecs* specs = ImGui::TableGetSortSpecs();
  const auto same = [](const StateRow& a, const StateRow& b) {
    return std::tie(a.state, a.axis, a.absolute_granularity, a.voxels, a.rays) ==
           std::tie(b.state, b.axis, b.absolute_granularity, b.voxels, b.rays);
  };
  const bool new_rows =
      !std::equal(rows.begin(), rows.end(), unsorted_.begin(), unsorted_.end(), same);
  if (!new_rows && !(specs && specs->SpecsDirty)) return;
  unsorted_ = rows;
  shown_ = rows;
  if (specs && specs->SpecsCount > 0) {
    const ImGuiTableColumnSortSpecs& spec = specs->Specs[0];
    sort_state_rows(shown_, StateColumn(spec.ColumnIndex),
                    spec.SortDirection == ImGuiSortDirection_Descending);
  }
  if (specs) specs->SpecsDirty = false;
}

}  // namespace gs::app
