#include "app/view/structure_editor.h"

#include <imgui.h>

#include <algorithm>
#include <utility>
#include <vector>

#include "app/flags.h"
#include "app/view/state.h"
#include "core/base/error.h"

namespace gs::app {

namespace {

// The structure's index in accelerator_names() (their count when unknown).
int accelerator_index(const std::string& name) {
  const std::vector<std::string> names = accelerator_names();
  return int(std::find(names.begin(), names.end(), name) - names.begin());
}

void cost_slider(const char* label, double& value) {
  const double lo = 0.0, hi = 20.0;
  ImGui::SliderScalar(label, ImGuiDataType_Double, &value, &lo, &hi, "%.2f");
}

}  // namespace

std::string byte_text(uint64_t bytes) {
  constexpr std::pair<int, const char*> kSuffixes[] = {{30, "G"}, {20, "M"}, {10, "K"}};
  for (const auto& [shift, suffix] : kSuffixes)
    if (bytes > 0 && bytes % (uint64_t{1} << shift) == 0)
      return std::to_string(bytes >> shift) + suffix;
  return std::to_string(bytes);
}

StructureEditor::StructureEditor(const std::string& accel, const AccelParams& params)
    : accel_(accelerator_index(accel)), params_(params) {
  budget_text_.set(byte_text(params.memory_budget));
}

void StructureEditor::controls(ViewState& state) {
  const std::vector<std::string> names = accelerator_names();
  for (int i = 0; i < int(names.size()); ++i) {
    if (i) ImGui::SameLine();
    ImGui::RadioButton(names[size_t(i)].c_str(), &accel_, i);
  }
  cost_slider("Intcost", params_.intcost);
  cost_slider("Repcost", params_.repcost);
  cost_slider("Travcost", params_.travcost);
  cost_slider("Vertcost", params_.vertcost);
  cost_slider("Subcost", params_.subcost);
  ImGui::SliderInt("max granularity", &params_.max_granularity, 2, 64);
  int axis = int(params_.axis);
  ImGui::RadioButton("alternate axes", &axis, int(AxisRule::alternate));
  ImGui::SameLine();
  ImGui::RadioButton("axis by cost", &axis, int(AxisRule::cost));
  params_.axis = AxisRule(axis);
  budget_text_.input("memory budget");
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip(
        "bytes of structure, suffix K, M or G; a voxel that would exceed it "
        "stays a leaf");
  if (ImGui::Button("Apply (rebuild)")) apply(state);
}

void StructureEditor::set(ViewState& state, const std::string& name, const std::string& value) {
  if (name == "accel") {
    accel_ = accelerator_index(value);
  } else {
    apply_structure_flag(params_, "--" + name, value);
    budget_text_.set(byte_text(params_.memory_budget));
  }
  apply(state);
}

void StructureEditor::apply(ViewState& state) {
  try {
    apply_structure_flag(params_, "--memory-budget", budget_text_.c_str());
  } catch (const UsageError& e) {
    state.status.set(e.what());
    return;
  }
  const std::vector<std::string> names = accelerator_names();
  const std::string accel = accel_ >= 0 && accel_ < int(names.size()) ? names[size_t(accel_)]
                                                                      : state.session.setup().accel;
  state.session.set_structure(accel, params_);
  state.structure_replaced();
}

}  // namespace gs::app
