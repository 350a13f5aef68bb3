#include "app/view/build_progress.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "app/view/state.h"

namespace gs::app {

namespace {

// A build shorter than this shows no bar: it would only flicker.
constexpr double kShowAfterSeconds = 0.5;
constexpr float kBarWidth = 320.0f;
// The sweeping bar of a build without figures: a block a quarter of the bar wide crossing
// it once per period, so that a build that tells nothing still shows it is alive.
constexpr double kSweepSeconds = 1.5;
constexpr float kSweepShare = 0.25f;

constexpr ImGuiWindowFlags kFlags =
    ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
    ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing |
    ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoInputs;

void sweeping_bar(double seconds) {
  const ImVec2 size(kBarWidth, ImGui::GetFrameHeight());
  const ImVec2 lo = ImGui::GetCursorScreenPos();
  const ImVec2 hi(lo.x + size.x, lo.y + size.y);
  ImGui::Dummy(size);
  ImDrawList& draw = *ImGui::GetWindowDrawList();
  draw.AddRectFilled(lo, hi, ImGui::GetColorU32(ImGuiCol_FrameBg));
  // The block enters at the left edge and leaves at the right, clipped to the bar.
  const auto phase = float(std::fmod(seconds / kSweepSeconds, 1.0));
  const float block = kSweepShare * size.x;
  const float start = lo.x - block + phase * (size.x + block);
  draw.AddRectFilled(ImVec2(std::max(start, lo.x), lo.y),
                     ImVec2(std::min(start + block, hi.x), hi.y),
                     ImGui::GetColorU32(ImGuiCol_PlotHistogram));
}

// A count for %llu (uint64_t is unsigned long here, which %llu does not take).
unsigned long long n(uint64_t count) { return count; }

void figures_text(const BuildFigures& f, bool sampling) {
  if (f.sample_rays > 0 && !sampling)
    ImGui::TextUnformatted("first image: voxels built as its rays reach them");
  if (f.sample_rays > 0) {
    ImGui::Text("sampling pass: %llu of %llu rays", n(f.sample_rays_traced), n(f.sample_rays));
    ImGui::Text("its scout: %llu voxels built", n(f.scout_voxels_built));
  }
  ImGui::Text("voxels built: %llu, cut: %llu", n(f.voxels_built), n(f.voxels_subdivided));
  ImGui::Text("triangles sorted: %llu (%llu in cuts taken from the scout)", n(f.triangles_sorted),
              n(f.triangles_from_scout));
}

void draw_bar(const ViewState& state, const BuildStatus& status) {
  const Viewport& view = state.viewport;
  ImGui::SetNextWindowPos(ImVec2(view.x + 0.5f * view.w, view.y + 0.5f * view.h), ImGuiCond_Always,
                          ImVec2(0.5f, 0.5f));
  ImGui::SetNextWindowBgAlpha(0.8f);
  // Within the viewport: the panels beside it would hide the rest.
  ImGui::SetNextWindowSizeConstraints(ImVec2(0.0f, 0.0f), ImVec2(view.w, view.h));
  ImGui::Begin("build progress", nullptr, kFlags);
  ImGui::Text("building %s: %.1f s", status.structure.c_str(), status.seconds);
  // The sampling pass is the one part whose total is known; after it, the first passes'
  // rays build the structure as they reach its voxels, to an end nobody can tell.
  const BuildFigures* figures = status.figures ? &*status.figures : nullptr;
  const bool sampling = figures && figures->sample_rays_traced < figures->sample_rays;
  if (sampling)
    ImGui::ProgressBar(float(figures->sampling_fraction().value_or(0.0)), ImVec2(kBarWidth, 0.0f));
  else
    sweeping_bar(status.seconds);
  if (figures)
    figures_text(*figures, sampling);
  else
    ImGui::TextUnformatted("this structure does not report its progress");
  ImGui::End();
}

}  // namespace

void draw_build_progress(ViewState& state) {
  const BuildStatus status = state.session.build_status();
  if (!status.building || status.seconds < kShowAfterSeconds) return;
  draw_bar(state, status);
  state.build_bar.shown = true;
  state.build_bar.last = status;
}

}  // namespace gs::app
