#include "app/shot.h"

#include <imgui.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

#include "app/gl/frame.h"
#include "app/gl/headless.h"
#include "app/gl/imgui_renderer.h"
#include "core/accel/grid1d/grid1d.h"
#include "core/base/error.h"
#include "core/render/overlay.h"
#include "core/trace/trace_job.h"

namespace gs::app {

namespace {

std::array<int, 2> walk_pixel(const ShotJob& job) {
  if (job.pixel) return *job.pixel;
  return {job.settings.width / 2, job.settings.height / 2};
}

// Usage errors before any file is read (docs/design.md §3: usage first).
void check_usage(const ShotJob& job, const Accelerator& accel) {
  check_render_settings(job.settings);
  if (job.overlays.needs_grid() && !accel.grid1d())
    throw UsageError("shot: --overlay cells, states and walk need --accel grid1d, not '" +
                     job.accel + "'");
  const auto [x, y] = walk_pixel(job);
  if (x < 0 || y < 0 || x >= job.settings.width || y >= job.settings.height)
    throw UsageError("--pixel '" + std::to_string(x) + "," + std::to_string(y) + "': outside the " +
                     std::to_string(job.settings.width) + "x" +
                     std::to_string(job.settings.height) + " image");
}

// What the frame shows besides the image, and what the panel says about it.
struct Overlays {
  std::vector<LineSet> lines;
  std::vector<uint8_t> heat;  // RGBA8 in place of the shaded image; empty for none
  float heat_max = 0.0f;
};

Overlays make_overlays(const ShotJob& job, const Accelerator& accel, const Camera& camera,
                       const RenderOutcome& outcome) {
  Overlays overlays;
  const Grid1D* grid = accel.grid1d();
  const OverlaySelection& chosen = job.overlays;
  // The walk first: re-tracing the ray may build voxels the cells overlay then shows, and
  // near-walk needs it.
  std::optional<Walk> walk;
  if (chosen.walk || chosen.near_walk) {
    const auto [x, y] = walk_pixel(job);
    const auto context = accel.make_context();
    walk = accel.record_walk(camera.primary_ray(x, y, job.settings.width, job.settings.height),
                             *context);
  }
  const VoxelFilter filter{
      .depths = chosen.depths, .near_walk = chosen.near_walk, .walk = walk ? &*walk : nullptr};
  if (chosen.cells) overlays.lines.push_back(cell_lines(*grid, CellColoring::depth, filter));
  if (chosen.states) overlays.lines.push_back(state_lines(*grid, filter));
  for (const LineSet& set : overlays.lines)
    std::fprintf(stderr, "gridscope shot: %s\n", set.coverage.describe().c_str());
  // After the notes: the walk is never capped.
  if (chosen.walk && walk) overlays.lines.push_back(walk_lines(*walk));
  if (chosen.heat != HeatKind::none) {
    const std::vector<float> values = heat_values(outcome.pixels, chosen.heat, job.settings.spp);
    overlays.heat_max = values.empty() ? 0.0f : *std::max_element(values.begin(), values.end());
    // A flat image (all zero) still needs a non-empty range.
    overlays.heat = heat_image(values, 0.0f, std::max(overlays.heat_max, 1.0f));
  }
  return overlays;
}

// View-axis distances for the depth test, or none when the renderer gave no records.
std::vector<float> pixel_distances(const RenderOutcome& outcome) {
  const size_t count = size_t(outcome.image.width) * size_t(outcome.image.height);
  if (outcome.pixels.size() != count) return {};
  std::vector<float> distances(count);
  for (size_t i = 0; i < count; ++i) distances[i] = outcome.pixels[i].depth;
  return distances;
}

std::string figure(const nlohmann::json& stats, const char* key) {
  const nlohmann::json& value = stats.at(key);
  if (value.is_null()) return "n/a";
  if (value.is_number_float()) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", value.get<double>());
    return text;
  }
  return value.dump();
}

ImVec4 to_imgui(const glm::vec4& c) { return {c.r, c.g, c.b, c.a}; }

void legend_row(const glm::vec4& colour, const std::string& label) {
  ImGui::ColorButton(("##" + label).c_str(), to_imgui(colour),
                     ImGuiColorEditFlags_NoTooltip | ImGuiColorEditFlags_NoDragDrop,
                     ImVec2(12, 12));
  ImGui::SameLine();
  ImGui::TextUnformatted(label.c_str());
}

// Long legends (one entry per traversal state) would cover the image: show the first few.
constexpr size_t kMaxLegendRows = 12;

void legend(const ShotJob& job, const Overlays& overlays) {
  for (const LineSet& set : overlays.lines) {
    if (set.coverage.shown() < set.coverage.total()) {
      // Wrapped at a fixed width: the window sizes itself to its content.
      ImGui::PushTextWrapPos(ImGui::GetFontSize() * 24.0f);
      ImGui::TextWrapped("%s", set.coverage.describe().c_str());
      ImGui::PopTextWrapPos();
    }
    const size_t shown = std::min(set.legend.size(), kMaxLegendRows);
    for (size_t i = 0; i < shown; ++i) legend_row(set.legend[i].color, set.legend[i].label);
    if (set.legend.size() > shown) ImGui::Text("... %zu more", set.legend.size() - shown);
  }
  if (job.overlays.heat == HeatKind::none) return;
  const auto colour = [](float x) {
    const std::array<uint8_t, 3> c = turbo(x);
    return glm::vec4(c[0] / 255.0f, c[1] / 255.0f, c[2] / 255.0f, 1.0f);
  };
  legend_row(colour(0.0f), std::string("heat:") + heat_name(job.overlays.heat) + " 0");
  legend_row(colour(1.0f), std::string("heat:") + heat_name(job.overlays.heat) + " " +
                               std::to_string(uint64_t(overlays.heat_max)));
}

// The statistics panel: the run's record, as `render --stats` would write it.
void panel(const ShotJob& job, const nlohmann::json& stats, const Overlays& overlays) {
  ImGui::SetNextWindowPos(ImVec2(10, 10));
  ImGui::SetNextWindowBgAlpha(0.85f);
  ImGui::Begin("gridscope", nullptr,
               ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoMove |
                   ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoCollapse);
  ImGui::Text("structure      %s", job.accel.c_str());
  ImGui::Text("triangles      %s", figure(stats, "triangles").c_str());
  ImGui::Text("nodes          %s", figure(stats, "nodes").c_str());
  ImGui::Text("subdivided     %s", figure(stats, "voxels_subdivided").c_str());
  ImGui::Text("states         %s", figure(stats, "traversal_states").c_str());
  ImGui::Text("rays/s         %s", figure(stats, "rays_per_second").c_str());
  if (!overlays.lines.empty() || job.overlays.heat != HeatKind::none) {
    ImGui::Separator();
    legend(job, overlays);
  }
  ImGui::End();
}

// Owns an ImGui context for one shot; never writes imgui.ini.
struct ImGuiScope {
  explicit ImGuiScope(int width, int height) {
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;
    io.LogFilename = nullptr;
    io.DisplaySize = ImVec2(float(width), float(height));
    io.DeltaTime = 1.0f / 60.0f;
  }
  ~ImGuiScope() { ImGui::DestroyContext(); }
};

void draw_panel(const ShotJob& job, const nlohmann::json& stats, const Overlays& overlays) {
  ImGuiScope scope(job.settings.width, job.settings.height);
  gl::ImGuiRenderer renderer;
  // An auto-sized window is measured in its first frame and shown from the second.
  for (int frame = 0; frame < 2; ++frame) {
    ImGui::NewFrame();
    panel(job, stats, overlays);
    ImGui::Render();
  }
  renderer.draw(ImGui::GetDrawData());
}

void draw_and_write(const ShotJob& job, const Scene& scene, const Camera& camera,
                    const RenderOutcome& outcome, const Overlays& overlays,
                    const nlohmann::json& stats) {
  const int width = job.settings.width, height = job.settings.height;
  gl::HeadlessContext context(width, height);
  const std::vector<float> distances = pixel_distances(outcome);
  gl::FrameInput input;
  input.image_width = width;
  input.image_height = height;
  input.rgba = overlays.heat.empty() ? outcome.image.rgba : overlays.heat;
  input.distance = distances;
  input.camera = camera;
  input.scene_box = scene.bounds();
  input.lines = overlays.lines;
  {
    gl::FrameRenderer frame;
    frame.draw(width, height, input);
  }
  if (job.ui) draw_panel(job, stats, overlays);
  write_png(job.out_path, width, height, gl::read_pixels(width, height));
}

}  // namespace

void run_shot(const ShotJob& job) {
  std::unique_ptr<Accelerator> accel = make_accelerator(job.accel, job.params);
  check_usage(job, *accel);
  const Scene scene = load_scene(job.scene);
  // A heatmap shows what each pixel's own rays cost; packets share a block's cost among its
  // pixels, so a heatmap is rendered one ray at a time (the same image either way).
  RenderSettings settings = job.settings;
  if (job.overlays.heat != HeatKind::none) settings.packets = false;
  const Camera camera = camera_for(job.camera, scene, settings);
  const auto [outcome, figures] = build_and_render(scene, *accel, camera, settings);
  const nlohmann::json stats = run_stats(scene, *accel, job.params.to_json(), figures);
  const Overlays overlays = make_overlays(job, *accel, camera, outcome);
  draw_and_write(job, scene, camera, outcome, overlays, stats);
}

}  // namespace gs::app
