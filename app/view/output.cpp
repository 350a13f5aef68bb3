#include "app/view/output.h"

// glad first: it claims the GL header guard before GLFW or ImGui could pull in GL headers.
#include <glad/gl.h>
#include <imgui.h>
#include <imgui_internal.h>  // ImGuiWindow: each window's rectangle, content and scrollbars

#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

#include "app/gl/frame.h"
#include "app/gl/window.h"
#include "app/view/state.h"
#include "core/base/error.h"
#include "core/base/files.h"
#include "core/render/render.h"

namespace gs::app {

namespace {

nlohmann::json optional_json(const std::optional<uint64_t>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

nlohmann::json rect_json(float x, float y, float w, float h) {
  return {{"x", x}, {"y", y}, {"w", w}, {"h", h}};
}

// Content that needs more than the visible area on an axis without a scrollbar is cut off
// (a pixel's slack for rounding).
bool clipped(float content, float visible, bool scrollbar) {
  return !scrollbar && content > visible + 1.0f;
}

// A window drawn in the last frame: where it is, how much content it has and how much of it
// shows. The visible size is the inner rectangle (no title bar or scrollbars) less padding.
nlohmann::json window_json(const ImGuiWindow& window) {
  const ImVec2 inner(std::max(window.InnerRect.GetWidth() - 2 * window.WindowPadding.x, 0.0f),
                     std::max(window.InnerRect.GetHeight() - 2 * window.WindowPadding.y, 0.0f));
  const ImVec2 content = window.ContentSize;
  return {{"name", window.Name},
          {"parent", window.ParentWindow ? window.ParentWindow->Name : ""},
          {"rect", rect_json(window.Pos.x, window.Pos.y, window.Size.x, window.Size.y)},
          {"content", {{"w", content.x}, {"h", content.y}}},
          {"inner", {{"w", inner.x}, {"h", inner.y}}},
          {"scrollbar", {{"x", window.ScrollbarX}, {"y", window.ScrollbarY}}},
          {"clipped", clipped(content.x, inner.x, window.ScrollbarX) ||
                          clipped(content.y, inner.y, window.ScrollbarY)}};
}

// The viewport and every ImGui window of the last frame (panels, splitter bars, child
// windows, the help overlay), so that tests can check that nothing is cut off.
nlohmann::json layout_json(const Viewport& view) {
  nlohmann::json windows = nlohmann::json::array();
  for (const ImGuiWindow* window : ImGui::GetCurrentContext()->Windows)
    if (window->Active && !window->Hidden && !window->IsFallbackWindow)
      windows.push_back(window_json(*window));
  const ImVec2 display = ImGui::GetIO().DisplaySize;
  return {{"display", {{"w", display.x}, {"h", display.y}}},
          {"viewport", rect_json(view.x, view.y, view.w, view.h)},
          {"windows", windows}};
}

nlohmann::json figures_json(const std::optional<BuildFigures>& figures) {
  if (!figures) return nullptr;
  const std::optional<double> fraction = figures->sampling_fraction();
  return {{"voxels_built", figures->voxels_built},
          {"voxels_subdivided", figures->voxels_subdivided},
          {"triangles_sorted", figures->triangles_sorted},
          {"triangles_from_scout", figures->triangles_from_scout},
          {"sample_rays", figures->sample_rays},
          {"sample_rays_traced", figures->sample_rays_traced},
          {"scout_voxels_built", figures->scout_voxels_built},
          {"sampling_fraction", fraction ? nlohmann::json(*fraction) : nlohmann::json(nullptr)}};
}

nlohmann::json status_json(const BuildStatus& status) {
  return {{"structure", status.structure},
          {"building", status.building},
          {"seconds", status.seconds},
          {"figures", figures_json(status.figures)}};
}

// Whether the build progress bar was shown and what it last showed, the newest build as it
// stands (its figures when it ended), and the build's figures taken with the shown frame's
// structure statistics (figures are null where the structure reports none).
nlohmann::json build_progress_json(const ViewState& state) {
  const BuildBarRecord& bar = state.build_bar;
  return {{"bar_shown", bar.shown},
          {"bar_last", bar.shown ? status_json(bar.last) : nlohmann::json(nullptr)},
          {"build", status_json(state.session.build_status())},
          {"frame", figures_json(state.session.frame().build)}};
}

}  // namespace

void write_walk(const PickedWalk& picked, const std::string& path) {
  if (!picked.walk)
    throw InputError("view: pixel " + std::to_string(picked.pixel[0]) + "," +
                     std::to_string(picked.pixel[1]) + ": no walk recorded");
  nlohmann::json json = to_json(*picked.walk);
  const std::string camera = to_string(picked.camera);
  json["view"] = {{"width", picked.size[0]},
                  {"height", picked.size[1]},
                  {"camera", camera},
                  {"pixel", {picked.pixel[0], picked.pixel[1]}}};
  write_json(path, json);
  std::printf("viewport %dx%d camera %s pixel %d,%d\n", picked.size[0], picked.size[1],
              camera.c_str(), picked.pixel[0], picked.pixel[1]);
}

void write_screenshot(const gl::Window& window, const std::string& path) {
  if (window.minimised()) throw InputError(path + ": the window is minimised");
  const glm::ivec2 size = window.framebuffer_size();
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glReadBuffer(GL_BACK);
  std::vector<uint8_t> rgba = gl::read_pixels(size.x, size.y);  // rows flipped to the top
  for (size_t i = 3; i < rgba.size(); i += 4) rgba[i] = 255;    // the window is opaque
  write_png(path, size.x, size.y, rgba);
}

void write_stats(const ViewState& state, const nlohmann::json& compare, const std::string& path) {
  const Session& session = state.session;
  const ViewSetup& setup = session.setup();
  const ProgressiveFrame& frame = session.frame();
  const StructureStats& s = frame.structure;
  nlohmann::json stats = {
      {"scene", setup.scene->name},
      {"accel", setup.accel},
      {"parameters", setup.params.to_json()},
      {"triangles", setup.scene->triangle_count()},
      {"view",
       {{"width", frame.width},
        {"height", frame.height},
        {"camera", to_string(session.frame_camera())},
        {"pass", frame.pass},
        {"spp", frame.spp},
        {"current", session.frame_current()}}},
      {"packets", setup.packets},
      {"rays", frame.rays},
      {"rays_per_second", frame.rays_per_second},
      {"seconds", frame.seconds},
      {"full_pass_seconds", session.full_pass_seconds()},
      {"packet_rays", frame.counters.packet_rays},
      {"packet_fallback_rays", frame.counters.packet_fallback_rays},
      {"packet_active_fraction", frame.counters.packet_active_fraction()},
      {"build_seconds", s.build_seconds},
      {"nodes", optional_json(s.nodes)},
      {"voxels_subdivided", optional_json(s.voxels_subdivided)},
      {"leaves", optional_json(s.leaves)},
      {"traversal_states", optional_json(s.traversal_states)},
      {"memory_bytes", s.memory_bytes},
      {"voxels_over_budget", s.voxels_over_budget},
      {"error", frame.error},
      {"status", state.status.text()},
      {"layout", layout_json(state.viewport)},
      {"window_frames", {{"built", state.frames_built}, {"drawn", state.frames_drawn}}},
      {"build_progress", build_progress_json(state)}};
  stats["compare"] = compare;
  write_json(path, stats);
}

}  // namespace gs::app
