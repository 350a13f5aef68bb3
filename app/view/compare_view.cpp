#include "app/view/compare_view.h"

// glad first: it claims the GL header guard before GLFW or ImGui could pull in GL headers.
#include <glad/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <utility>

#include "app/view/overlay_cache.h"
#include "core/base/error.h"
#include "core/render/compare.h"

namespace gs::app {

namespace {

constexpr const char* kModeNames[] = {"split", "a", "b", "difference"};  // script words
constexpr const char* kModeLabels[] = {"split", "A", "B", "B - A"};
const ImU32 kLabelBackground = IM_COL32(0, 0, 0, 170);
const ImU32 kDivider = IM_COL32(255, 255, 255, 230);

// What B is derived from: a new structure or parameter set of A's rebuilds B too.
std::string structure_key(const ViewSetup& setup) {
  return setup.accel + " " + setup.params.to_json().dump();
}

// A label on a dark box at `at` over the viewport.
void label(const ImVec2& at, const std::string& text) {
  ImDrawList* draw = ImGui::GetBackgroundDrawList();
  const ImVec2 size = ImGui::CalcTextSize(text.c_str());
  draw->AddRectFilled(at, ImVec2(at.x + size.x + 8, at.y + size.y + 4), kLabelBackground);
  draw->AddText(ImVec2(at.x + 4, at.y + 2), IM_COL32_WHITE, text.c_str());
}

// The totals side by side, a table that fits the panel (columns share its width).
void totals(const CompareTotals& a, const CompareTotals& b) {
  const ImGuiTableFlags flags =
      ImGuiTableFlags_RowBg | ImGuiTableFlags_BordersInnerV | ImGuiTableFlags_SizingStretchProp;
  if (!ImGui::BeginTable("totals", 4, flags)) return;
  for (const char* name : {"figure", "A", "B", "B / A"}) ImGui::TableSetupColumn(name);
  ImGui::TableHeadersRow();
  for (const TotalsRow& row : totals_rows(a, b))
    for (const std::string* cell : {&row.figure, &row.a, &row.b, &row.ratio}) {
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(cell->c_str());
    }
  ImGui::EndTable();
}

}  // namespace

const char* compare_mode_name(CompareMode mode) { return kModeNames[int(mode)]; }

std::optional<CompareMode> compare_mode_named(const std::string& name) {
  for (int i = 0; i < IM_ARRAYSIZE(kModeNames); ++i)
    if (name == kModeNames[i]) return CompareMode(i);
  return std::nullopt;
}

CompareView::CompareView(std::function<void()> frame_ready) : frame_ready_(std::move(frame_ready)) {
  spec_text_.set("accel=bvh");
}

void CompareView::set(ViewState& state, const std::string& spec_text) {
  if (spec_text == "off") {
    session_.reset();
    return;
  }
  try {
    spec_ = parse_compare(spec_text);
    spec_text_.set(spec_text);
    start(state);
  } catch (const UsageError& e) {
    state.status.set(e.what());
  }
}

// Throws UsageError when the spec does not apply to A's structure (side_b).
void CompareView::start(ViewState& state) {
  const ViewSetup& a = state.session.setup();
  const CompareSide side = side_b(spec_, a.accel, a.params);
  // Stopped first: two sessions of B would briefly share the cores.
  session_.reset();
  session_ = std::make_unique<Session>(a.scene, side.accel, side.params, frame_ready_);
  heat_b_of_.reset(), drawn_of_.reset();  // a new session counts its generations anew
  a_structure_ = structure_key(a);
  label_b_ = side_b_label(spec_, a.accel);
  follow(state);
  state.status.set("A/B: comparing with " + label_b_);
}

// B renders A's view: the same scene, camera, size and packets (unless the spec sets them).
void CompareView::follow(const ViewState& state) {
  const ViewSetup& a = state.session.setup();
  const ViewSetup& b = session_->setup();
  if (a.scene != b.scene) session_->set_scene(a.scene, a.camera);
  if (std::string key = structure_key(a); key != a_structure_) {
    a_structure_ = std::move(key);
    const CompareSide side = side_b(spec_, a.accel, a.params);
    session_->set_structure(side.accel, side.params);
  }
  if (b.max_spp != a.max_spp) session_->set_max_spp(a.max_spp);
  const bool packets = spec_.packets.value_or(a.packets);
  if (b.packets != packets) session_->set_packets(packets);
  if (to_string(a.camera) != to_string(b.camera)) session_->move_camera(a.camera);
  if (a.width != b.width || a.height != b.height) session_->resize(a.width, a.height);
}

void CompareView::update(ViewState& state, HeatMap& heat_a) {
  state.compare_pending = false;
  if (!session_) return stop(heat_a);
  if (!ImGui::GetIO().WantCaptureKeyboard && ImGui::IsKeyPressed(GLFW_KEY_B, false))
    mode_ = mode_ == CompareMode::b ? CompareMode::a : CompareMode::b;  // the A/B toggle
  try {
    follow(state);
  } catch (const UsageError& e) {  // A changed to a structure the spec does not apply to
    state.status.set("A/B stopped: " + std::string(e.what()));
    session_.reset();
    return stop(heat_a);
  }
  session_->take_frame();
  state.compare_pending = !(session_->full_pass_current() && b_matches_a(state));
  const HeatKind kind = state.overlays.heat;
  if (kind == HeatKind::none || !b_matches_a(state)) {
    heat_b_.clear();
    heat_b_of_.reset();
    return;
  }
  const ProgressiveFrame& b = session_->frame();
  const HeatInputs inputs{b.generation, b.pass, kind};
  if (heat_b_of_ != inputs) {
    heat_b_ = heat_values(b.pixels, kind, b.spp);
    heat_b_of_ = inputs;
  }
  // One scale for both heatmaps: A's range follows the larger maximum.
  const float shared = shared_heat_max(heat_a.values(), heat_b_);
  if (heat_a.auto_range || heat_a.lo != 0.0f || heat_a.hi != shared) {
    heat_a.auto_range = false;
    heat_a.lo = 0.0f, heat_a.hi = shared;
    heat_a.invalidate();
  }
  shares_range_ = true;
}

// Back to A's own automatic heat range once the comparison ends.
void CompareView::stop(HeatMap& heat_a) {
  if (!shares_range_) return;
  shares_range_ = false;
  heat_a.auto_range = true;
  heat_a.invalidate();
}

bool CompareView::b_matches_a(const ViewState& state) const {
  const ProgressiveFrame &a = state.session.frame(), &b = session_->frame();
  return b.pass > 0 && a.pass > 0 && a.width == b.width && a.height == b.height &&
         to_string(state.session.frame_camera()) == to_string(session_->frame_camera());
}

bool CompareView::refresh_b(const ViewState& state, const HeatMap& heat_a, bool& redrawn) {
  const ProgressiveFrame &a = state.session.frame(), &b = session_->frame();
  const DrawnInputs inputs{a.generation,        b.generation, a.pass,   b.pass,
                           state.overlays.heat, mode_,        heat_a.hi};
  if (drawn_of_ == inputs) return shown_;  // target_ still holds it
  drawn_of_ = inputs;
  const bool comparable = !heat_b_.empty() && heat_a.values().size() == heat_b_.size();
  difference_range_ = comparable ? difference_range(heat_a.values(), heat_b_) : 0.0f;
  const std::span<const uint8_t> rgba = b_image(state, heat_a);
  redrawn = !rgba.empty();
  if (redrawn) draw_b(state, rgba);
  return redrawn;
}

std::span<const uint8_t> CompareView::b_image(const ViewState& state, const HeatMap& heat_a) {
  if (mode_ == CompareMode::a || !b_matches_a(state)) return {};
  const bool heat = state.overlays.heat != HeatKind::none && !heat_b_.empty();
  if (mode_ == CompareMode::difference) {
    if (!heat || heat_a.values().size() != heat_b_.size()) return {};
    b_rgba_ = difference_image(heat_a.values(), heat_b_);
    return b_rgba_;
  }
  if (!heat) return session_->frame().image.rgba;
  b_rgba_ = heat_image(heat_b_, 0.0f, heat_a.hi);
  return b_rgba_;
}

void CompareView::draw_b(const ViewState& state, std::span<const uint8_t> rgba) {
  const ProgressiveFrame& b = session_->frame();
  target_.resize(b.width, b.height);
  target_.bind();
  gl::FrameInput input;
  input.image_width = b.width;
  input.image_height = b.height;
  input.rgba = rgba;
  input.camera = session_->frame_camera();
  input.scene_box = state.session.setup().scene_box;
  renderer_.draw(b.width, b.height, input);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

bool CompareView::draw(const ViewState& state, const HeatMap& heat_a) {
  bool redrawn = false;
  shown_ = session_ && refresh_b(state, heat_a, redrawn);
  if (!session_) return false;
  const Viewport& view = state.viewport;
  const float from = mode_ == CompareMode::split ? divider_ : 0.0f;
  const float x = view.x + from * view.w;
  // GL textures count rows from the bottom: flip v, as the viewport's own image does.
  if (shown_)
    ImGui::GetBackgroundDrawList()->AddImage(target_.texture(), ImVec2(x, view.y),
                                             ImVec2(view.x + view.w, view.y + view.h),
                                             ImVec2(from, 1), ImVec2(1, 0));
  if (mode_ == CompareMode::split && shown_)
    ImGui::GetBackgroundDrawList()->AddLine(ImVec2(x, view.y), ImVec2(x, view.y + view.h), kDivider,
                                            2.0f);
  if (mode_ == CompareMode::split || mode_ == CompareMode::a)
    label(ImVec2(view.x + 4, view.y + 4), "A: " + state.session.setup().accel);
  if (mode_ != CompareMode::a) label(ImVec2(x + 4, view.y + 4), b_label(state));
  return redrawn;
}

// What B's part is labelled: its structure, what it still waits for, or the difference.
std::string CompareView::b_label(const ViewState& state) const {
  if (!b_matches_a(state)) return label_b_ + ": rendering";
  if (mode_ != CompareMode::difference) return label_b_;
  return shown_ ? "B - A (" + label_b_ + ")" : "B - A needs a heatmap";
}

void CompareView::controls(ViewState& state, HeatMap& heat_a) {
  // Fields leave room for their labels: the panel may be as narrow as its minimum.
  ImGui::PushItemWidth(
      -(ImGui::CalcTextSize("B changes").x + ImGui::GetStyle().ItemInnerSpacing.x));
  const bool shown = spec_controls(state);
  ImGui::PopItemWidth();
  if (shown) totals_controls(state, heat_a);
}

// The spec, start and stop, and how the viewport shows B; false once no comparison runs.
bool CompareView::spec_controls(ViewState& state) {
  spec_text_.input("B changes");
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip(
        "NAME=VALUE words, commas or blanks between: accel=NAME, packets=on|off, or a "
        "structure flag without its dashes (max-granularity=8, vertcost=4)");
  if (ImGui::Button(active() ? "restart B" : "compare")) set(state, spec_text_.c_str());
  if (!active()) return false;
  ImGui::SameLine();
  if (ImGui::Button("stop")) {
    set(state, "off");
    return false;
  }
  int mode = int(mode_);
  for (int i = 0; i < IM_ARRAYSIZE(kModeNames); ++i) {
    if (i) ImGui::SameLine();
    ImGui::RadioButton(kModeLabels[i], &mode, i);
  }
  mode_ = CompareMode(mode);
  if (mode_ == CompareMode::split) ImGui::SliderFloat("divider", &divider_, 0.05f, 0.95f, "%.2f");
  ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
  ImGui::TextWrapped("key B: A or B alone; B - A needs a heatmap");
  ImGui::PopStyleColor();
  return true;
}

// B's progress, the totals side by side and the heatmaps' shared scale.
void CompareView::totals_controls(const ViewState& state, const HeatMap& heat_a) {
  const ProgressiveFrame& b = session_->frame();
  ImGui::TextWrapped("%s: pass %d, %d spp%s", label_b_.c_str(), b.pass, b.spp,
                     b_matches_a(state) ? "" : " (rendering this view)");
  if (!b.error.empty()) ImGui::TextWrapped("B: %s", b.error.c_str());
  totals(compare_totals("A: " + state.session.setup().accel, state.session.frame()),
         compare_totals(label_b_, b));
  if (!heat_b_.empty())
    ImGui::TextWrapped("heatmaps on one scale 0..%.3g; B - A over +-%.3g (beyond saturated)",
                       double(heat_a.hi), double(difference_range_));
}

nlohmann::json CompareView::stats(const ViewState& state) const {
  if (!session_) return nullptr;
  const ProgressiveFrame& b = session_->frame();
  const CompareTotals totals = compare_totals(label_b_, b);
  return {{"spec", spec_.text},
          {"label", label_b_},
          {"mode", compare_mode_name(mode_)},
          {"accel", session_->setup().accel},
          {"parameters", session_->setup().params.to_json()},
          {"shown", shown_},
          {"matches_a", b_matches_a(state)},
          {"view",
           {{"width", b.width},
            {"height", b.height},
            {"camera", to_string(session_->frame_camera())},
            {"pass", b.pass},
            {"spp", b.spp}}},
          {"rays_per_second", totals.rays_per_second},
          {"tests_per_ray", totals.tests_per_ray ? nlohmann::json(*totals.tests_per_ray) : nullptr},
          {"steps_per_ray", totals.steps_per_ray ? nlohmann::json(*totals.steps_per_ray) : nullptr},
          {"nodes", totals.nodes ? nlohmann::json(*totals.nodes) : nullptr},
          {"memory_bytes", totals.memory_bytes},
          {"build_seconds", totals.build_seconds},
          {"error", b.error}};
}

}  // namespace gs::app
