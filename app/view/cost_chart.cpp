#include "app/view/cost_chart.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace gs::app {

namespace {

using Alternative = VoxelCostReport::Alternative;

// The four terms of a cut's cost, bottom to top, with their colours.
struct Term {
  const char* name;
  double CutCost::*value;
  ImU32 colour;
};
const std::array<Term, 4> kTerms = {{
    {"int", &CutCost::int_cost, IM_COL32(80, 140, 230, 255)},
    {"trav", &CutCost::trav_cost, IM_COL32(240, 160, 60, 255)},
    {"rep", &CutCost::rep_cost, IM_COL32(150, 150, 150, 255)},
    {"ver", &CutCost::ver_cost, IM_COL32(90, 190, 110, 255)},
}};
const ImU32 kUncutColour = IM_COL32(235, 70, 70, 255);
const ImU32 kChosenColour = IM_COL32(255, 230, 80, 255);
const ImU32 kAxisColour = IM_COL32(200, 200, 200, 255);
const ImU32 kGridColour = IM_COL32(255, 255, 255, 40);

std::string figure(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", value);
  return text;
}

// Where the chart's parts go inside its box: the legend on top, the value labels on the
// left, the g labels and the axis title below.
struct Plot {
  float left, right, top, bottom;
  ChartScale scale;
  float y(double value) const {
    return bottom - float(std::min(value / scale.top, 1.0)) * (bottom - top);
  }
};

void legend(ImDrawList* draw, ImVec2 at) {
  const float box = ImGui::GetTextLineHeight() * 0.7f;
  const auto entry = [&](const char* name, ImU32 colour) {
    draw->AddRectFilled(ImVec2(at.x, at.y + box * 0.2f), ImVec2(at.x + box, at.y + box * 1.2f),
                        colour);
    draw->AddText(ImVec2(at.x + box + 3, at.y), kAxisColour, name);
    at.x += box + ImGui::CalcTextSize(name).x + 12;
  };
  for (const Term& term : kTerms) entry(term.name, term.colour);
  entry("uncut", kUncutColour);
  entry("chosen g", kChosenColour);
}

void value_axis(ImDrawList* draw, const Plot& plot, float label_left) {
  for (double v = 0; v <= plot.scale.top * (1 + 1e-9); v += plot.scale.step) {
    const float y = plot.y(v);
    draw->AddLine(ImVec2(plot.left, y), ImVec2(plot.right, y), kGridColour);
    const std::string label = figure(v);
    draw->AddText(ImVec2(label_left, y - ImGui::GetTextLineHeight() * 0.5f), kAxisColour,
                  label.c_str());
  }
  draw->AddLine(ImVec2(plot.left, plot.top), ImVec2(plot.left, plot.bottom), kAxisColour);
  draw->AddLine(ImVec2(plot.left, plot.bottom), ImVec2(plot.right, plot.bottom), kAxisColour);
}

void bars(ImDrawList* draw, const Plot& plot, const std::vector<Alternative>& cuts, int chosen) {
  const float slot = (plot.right - plot.left) / float(cuts.size());
  // g labels no closer than one label's width apart.
  const float label_width = ImGui::CalcTextSize("0000").x;
  const int label_every = std::max(1, int(std::ceil(label_width / slot)));
  const auto chosen_at = std::find_if(
      cuts.begin(), cuts.end(), [&](const Alternative& cut) { return cut.granularity == chosen; });
  const int chosen_index = int(chosen_at - cuts.begin());
  for (size_t i = 0; i < cuts.size(); ++i) {
    const float x0 = plot.left + slot * (float(i) + 0.15f), x1 = x0 + slot * 0.7f;
    double base = 0;
    for (const Term& term : kTerms) {
      const double value = cuts[i].cost.*term.value;
      draw->AddRectFilled(ImVec2(x0, plot.y(base + value)), ImVec2(x1, plot.y(base)), term.colour);
      base += value;
    }
    const bool is_chosen = cuts[i].granularity == chosen;
    if (is_chosen)
      draw->AddRect(ImVec2(x0 - 2, plot.y(base) - 2), ImVec2(x1 + 2, plot.bottom), kChosenColour,
                    0.0f, 0, 2.0f);
    // Every label_every-th g, and the chosen one with room beside it.
    const bool labelled =
        int(i) % label_every == 0 && std::abs(int(i) - chosen_index) >= label_every;
    if (is_chosen || labelled) {
      const std::string g = std::to_string(cuts[i].granularity);
      draw->AddText(ImVec2((x0 + x1 - ImGui::CalcTextSize(g.c_str()).x) * 0.5f, plot.bottom + 2),
                    is_chosen ? kChosenColour : kAxisColour, g.c_str());
    }
  }
}

// The uncut voxel's cost: a line across the bars, or along the top when it is off the scale.
void uncut_line(ImDrawList* draw, const Plot& plot, double uncut) {
  const bool off_scale = uncut > plot.scale.top;
  const float y = plot.y(uncut);
  draw->AddLine(ImVec2(plot.left, y), ImVec2(plot.right, y), kUncutColour, 2.0f);
  const std::string label = "uncut " + figure(uncut) + (off_scale ? " (above the scale)" : "");
  const ImVec2 size = ImGui::CalcTextSize(label.c_str());
  draw->AddText(ImVec2(plot.right - size.x, y - size.y - 1), kUncutColour, label.c_str());
}

void bar_tooltip(const Alternative& cut, int chosen, double uncut) {
  ImGui::BeginTooltip();
  ImGui::Text("g = %d%s, per ray:", cut.granularity, cut.granularity == chosen ? " (chosen)" : "");
  for (const Term& term : kTerms)
    ImGui::Text("  %-5s %s", term.name, figure(cut.cost.*term.value).c_str());
  ImGui::Text("  total %s (uncut %s)", figure(cut.cost.total).c_str(), figure(uncut).c_str());
  ImGui::EndTooltip();
}

}  // namespace

ChartScale nice_scale(double largest) {
  if (!(largest > 0)) return {};
  const double raw = largest / 5.0;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  const double ratio = raw / power;
  const double step = (ratio <= 1 ? 1 : ratio <= 2 ? 2 : ratio <= 5 ? 5 : 10) * power;
  return {std::ceil(largest / step - 1e-9) * step, step};
}

int slot_at(float x, float left, float width, int count) {
  if (count <= 0 || x < left || x >= left + width) return -1;
  return std::min(int((x - left) / width * float(count)), count - 1);
}

void cost_chart(const VoxelCostReport& report, const ImVec2& size) {
  std::vector<Alternative> cuts;
  for (const Alternative& alt : report.alternatives)
    if (alt.axis == report.axis) cuts.push_back(alt);
  double uncut = 0, largest = 0;
  for (const AxisPlan& plan : report.plans)
    if (plan.axis == report.axis) uncut = plan.no_split;
  for (const Alternative& cut : cuts) largest = std::max(largest, cut.cost.total);
  // The scale takes in the uncut cost unless that would squash the bars below half height
  // (an uncut voxel can cost twenty times the best cut).
  if (uncut <= 2 * largest) largest = std::max(largest, uncut);
  if (cuts.empty()) {
    ImGui::TextWrapped("No granularities were tried on this voxel.");
    return;
  }

  const ImVec2 origin = ImGui::GetCursorScreenPos();
  ImGui::InvisibleButton("cost chart", size);
  ImDrawList* draw = ImGui::GetWindowDrawList();
  const float line = ImGui::GetTextLineHeight();
  Plot plot;
  plot.scale = nice_scale(largest);
  const float label_width = ImGui::CalcTextSize(figure(plot.scale.top).c_str()).x;
  plot.left = origin.x + label_width + 6;
  plot.right = origin.x + size.x - 4;
  plot.top = origin.y + line * 2.0f;
  plot.bottom = origin.y + size.y - line * 2.2f;
  legend(draw, origin);
  value_axis(draw, plot, origin.x);
  bars(draw, plot, cuts, report.granularity);
  uncut_line(draw, plot, uncut);
  const std::string title =
      std::string("g, cells along ") + "xyz"[std::max(report.axis, 0) % 3] + "  (cost per ray)";
  draw->AddText(ImVec2((plot.left + plot.right - ImGui::CalcTextSize(title.c_str()).x) * 0.5f,
                       plot.bottom + line + 2),
                kAxisColour, title.c_str());
  const int hovered = ImGui::IsItemHovered() ? slot_at(ImGui::GetIO().MousePos.x, plot.left,
                                                       plot.right - plot.left, int(cuts.size()))
                                             : -1;
  if (hovered >= 0) bar_tooltip(cuts[size_t(hovered)], report.granularity, uncut);
}

}  // namespace gs::app
