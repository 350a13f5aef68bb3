#include "app/view/structure_editor.h"

#include <imgui.h>

#include <algorithm>
#include <string_view>
#include <type_traits>
#include <variant>

#include "app/flags.h"
#include "app/view/state.h"
#include "core/accel/registry.h"
#include "core/base/error.h"

namespace gs::app {

namespace {

// The structures the viewer can build: this build's, except those that replay another run's
// hit file (the viewer's rays have no such file).
bool viewable(const Structure& structure) {
  return structure.available() && !structure.needs_oracle;
}

// The words of a choice row's value_name, "alternate|cost", as radio buttons over the enum.
void choice_control(const ParamSpec& spec, AxisRule& value) {
  int chosen = int(value);
  const std::string_view words = spec.value_name;
  for (size_t start = 0, index = 0;; ++index) {
    const size_t end = words.find('|', start);
    if (index) ImGui::SameLine();
    ImGui::RadioButton(std::string(words.substr(start, end - start)).c_str(), &chosen, int(index));
    if (end == std::string_view::npos) break;
    start = end + 1;
  }
  value = AxisRule(chosen);
}

// Where the paper treats what a parameter tunes, for its slider's tooltip; the structures'
// own limits (depth, leaf size, budget, threads) are not the paper's.
const char* paper_section(Param param) {
  switch (param) {
    case Param::intcost:
    case Param::repcost:
    case Param::travcost:
    case Param::vertcost:
    case Param::subcost:
      return "The paper §6.2: a code timing the cost function (§6) weighs.";
    case Param::max_granularity:
      return "The paper §6.5: the cost function tries each g up to this.";
    case Param::max_root_granularity:
      return "The paper §6.5 caps g to encourage recursion at the top; the root is capped lower.";
    case Param::axis:
      return "The paper cuts the axes in turn; choosing by cost is its future work.";
    case Param::sample_every:
      return "The paper §6.5: sample rays estimate the rays crossing each voxel.";
    default:
      return "Not a parameter of the paper's 1D grid.";
  }
}

// The widest label of the section: the widgets leave room for it at their right, so that no
// label is cut at the panel's edge however narrow the panel is dragged (within its minimum).
float widest_label(const Structure* structure) {
  float widest = ImGui::CalcTextSize("structure").x;
  if (structure)
    for (const ParamUse& use : structure->params)
      widest = std::max(
          widest, ImGui::CalcTextSize(std::string(param_spec(use.param).flag.substr(2)).c_str()).x);
  return widest;
}

}  // namespace

StructureEditor::StructureEditor(const std::string& accel, const AccelParams& params)
    : accel_(accel), params_(params) {
  budget_text_.set(byte_text(params.memory_budget));
}

void StructureEditor::controls(ViewState& state) {
  const Structure* edited = find_structure(accel_);
  ImGui::PushItemWidth(-(widest_label(edited) + ImGui::GetStyle().ItemInnerSpacing.x));
  section(state, edited);
  ImGui::PopItemWidth();
}

void StructureEditor::section(ViewState& state, const Structure* edited) {
  if (ImGui::BeginCombo("structure", accel_.c_str())) {
    for (const Structure& structure : structures()) {
      if (!viewable(structure)) continue;
      if (ImGui::Selectable(structure.name.c_str(), accel_ == structure.name))
        accel_ = structure.name;
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", structure.description.c_str());
    }
    ImGui::EndCombo();
  }
  if (edited)
    for (const ParamUse& use : edited->params) {
      const ParamSpec& spec = param_spec(use.param);
      if (spec.structure_flag) param_control(spec, use.default_text);
    }
  if (ImGui::Button("Apply (rebuild)")) apply(state);
  bool packets = state.session.setup().packets;
  if (ImGui::Checkbox("packets", &packets)) state.session.set_packets(packets);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip(
        "Primary rays of 8x8 pixel blocks, then their shadow rays, walked together "
        "by structures that can (grid1d, embree); the same image either way");
}

void StructureEditor::param_control(const ParamSpec& spec, const std::string& default_text) {
  const std::string label(spec.flag.substr(2));  // "max-granularity"
  std::visit(
      [&](auto field) {
        auto& value = params_.*field;
        using Value = std::remove_reference_t<decltype(value)>;
        if constexpr (std::is_same_v<Value, double>) {
          // Relative timings (§6.2) and densities span decades: logarithmic sliders.
          const double lo = 0.0, hi = 1000.0;
          ImGui::SliderScalar(label.c_str(), ImGuiDataType_Double, &value, &lo, &hi, "%.3g",
                              ImGuiSliderFlags_Logarithmic);
        } else if constexpr (std::is_same_v<Value, int>) {
          // Capped for the slider's sake; the full range stays reachable by Ctrl+click.
          const std::string shown =
              value == 0 && spec.zero_is_default ? "default (" + default_text + ")" : "%d";
          ImGui::SliderInt(label.c_str(), &value, int(spec.lo), std::min(int(spec.hi), 4096),
                           shown.c_str(), ImGuiSliderFlags_Logarithmic);
        } else if constexpr (std::is_same_v<Value, uint64_t>) {
          budget_text_.input(label.c_str());
        } else if constexpr (std::is_same_v<Value, AxisRule>) {
          choice_control(spec, value);
        }
      },
      spec.field);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("%s%s%s\n%s", std::string(spec.help).c_str(),
                      default_text.empty() ? "" : "; default ", default_text.c_str(),
                      paper_section(spec.param));
}

void StructureEditor::set(ViewState& state, const std::string& name, const std::string& value) {
  if (name == "packets") return state.session.set_packets(value == "on");
  if (name == "accel") {
    accel_ = value;
  } else {
    apply_structure_flag(params_, "--" + name, value);
    budget_text_.set(byte_text(params_.memory_budget));
  }
  apply(state);
}

void StructureEditor::apply(ViewState& state) {
  try {
    apply_structure_flag(params_, "--memory-budget", budget_text_.c_str());
    check_params(accel_, params_);
  } catch (const UsageError& e) {
    state.status.set(e.what());
    return;
  }
  state.session.set_structure(accel_, params_);
  state.structure_replaced();
}

}  // namespace gs::app
