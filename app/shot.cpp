#include "app/shot.h"

#include <imgui.h>

#include <algorithm>
#include <cstdio>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

#include "app/gl/frame.h"
#include "app/gl/headless.h"
#include "app/gl/imgui_renderer.h"
#include "core/accel/grid1d/grid1d.h"
#include "core/base/error.h"
#include "core/render/compare.h"
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

// What a side's frame shows besides the image, and what the panel says about it.
struct Overlays {
  std::vector<LineSet> lines;
  std::vector<float> heat_values;  // per pixel and sample; empty for no heatmap
  std::vector<uint8_t> heat;       // RGBA8 in place of the shaded image; empty for none
  float heat_max = 0.0f;           // the heatmap's scale: 0..heat_max
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
  if (chosen.heat != HeatKind::none)
    overlays.heat_values = heat_values(outcome.pixels, chosen.heat, job.settings.spp);
  return overlays;
}

// The heatmap through turbo over 0..heat_max (a flat map, all zero, still gets a range).
void paint_heat(Overlays& overlays, float heat_max) {
  if (overlays.heat_values.empty()) return;
  overlays.heat_max = heat_max;
  overlays.heat = heat_image(overlays.heat_values, 0.0f, std::max(heat_max, 1.0f));
}

float own_heat_max(const Overlays& overlays) {
  const std::vector<float>& v = overlays.heat_values;
  return v.empty() ? 0.0f : *std::max_element(v.begin(), v.end());
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

glm::vec4 to_colour(const std::array<uint8_t, 3>& c) {
  return {c[0] / 255.0f, c[1] / 255.0f, c[2] / 255.0f, 1.0f};
}

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
  const std::string name = std::string("heat:") + heat_name(job.overlays.heat);
  legend_row(to_colour(turbo(0.0f)), name + " 0");
  legend_row(to_colour(turbo(1.0f)), name + " " + std::to_string(uint64_t(overlays.heat_max)));
}

constexpr ImGuiWindowFlags kPanelFlags =
    ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoSavedSettings |
    ImGuiWindowFlags_NoCollapse;

// The statistics panel: the run's record, as `render --stats` would write it; titled with
// the side's label in a comparison.
void panel(const ShotJob& job, const std::string& label, const nlohmann::json& stats,
           const Overlays& overlays) {
  ImGui::SetNextWindowPos(ImVec2(10, 10));
  ImGui::SetNextWindowBgAlpha(0.85f);
  ImGui::Begin(label.empty() ? "gridscope" : label.c_str(), nullptr, kPanelFlags);
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

// The difference map's panel: what its colours mean.
void difference_panel(HeatKind kind, float range) {
  ImGui::SetNextWindowPos(ImVec2(10, 10));
  ImGui::SetNextWindowBgAlpha(0.85f);
  ImGui::Begin("B - A", nullptr, kPanelFlags);
  const std::string name = std::string("heat:") + heat_name(kind);
  char text[64];
  std::snprintf(text, sizeof text, " B - A <= -%.3g", double(range));
  legend_row(to_colour(diverging(-1.0f)), name + text);
  legend_row(to_colour(diverging(0.0f)), name + " B - A = 0");
  std::snprintf(text, sizeof text, " B - A >= +%.3g", double(range));
  legend_row(to_colour(diverging(1.0f)), name + text);
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

void draw_panel(int width, int height, const std::function<void()>& contents) {
  ImGuiScope scope(width, height);
  gl::ImGuiRenderer renderer;
  // An auto-sized window is measured in its first frame and shown from the second.
  for (int frame = 0; frame < 2; ++frame) {
    ImGui::NewFrame();
    contents();
    ImGui::Render();
  }
  renderer.draw(ImGui::GetDrawData());
}

// One frame of the PNG: an image with its lines and, with --ui, a panel over it.
struct Frame {
  std::vector<uint8_t> rgba;  // shaded image, heatmap or difference map
  std::vector<float> distances;
  std::vector<LineSet> lines;
  std::function<void()> panel;  // ImGui contents; null: none
};

// One side (A, or B of a comparison): its structure and settings, and its run.
struct Side {
  std::string label;  // "A: grid1d" in a comparison, else empty
  ShotJob job;
  std::unique_ptr<Accelerator> accel;
  RenderOutcome outcome;
  nlohmann::json stats;
  Overlays overlays;
};

// Side A is the command line's; with --compare, side B changes what the spec names.
std::vector<Side> make_sides(const ShotJob& job) {
  std::vector<Side> sides;
  sides.push_back({"", job, make_accelerator(job.accel, job.params), {}, {}, {}});
  if (job.compare) {
    ShotJob b = job;
    const CompareSide changed = side_b(*job.compare, job.accel, job.params);
    b.accel = changed.accel;
    b.params = changed.params;
    b.settings.packets = job.compare->packets.value_or(job.settings.packets);
    sides.push_back({side_b_label(*job.compare, job.accel),
                     b,
                     make_accelerator(b.accel, b.params),
                     {},
                     {},
                     {}});
    sides[0].label = "A: " + job.accel;
  }
  for (const Side& side : sides) check_usage(side.job, *side.accel);
  return sides;
}

void run_side(Side& side, const Scene& scene, const Camera& camera) {
  // A heatmap shows what each pixel's own rays cost; packets share a block's cost among its
  // pixels, so a heatmap is rendered one ray at a time (the same image either way). And on
  // one thread: on several, a ray reaching a voxel another thread is still cutting tests the
  // voxel's triangles directly, so lazily built structures' counts would vary run to run
  // (one grid1d pixel of the pyramid counted 4096 tests once, 72 at most another time).
  RenderSettings settings = side.job.settings;
  if (side.job.overlays.heat != HeatKind::none) settings.packets = false, settings.threads = 1;
  const auto [outcome, figures] = build_and_render(scene, *side.accel, camera, settings);
  side.outcome = outcome;
  side.stats = run_stats(scene, *side.accel, side.job.params.to_json(), figures);
  side.overlays = make_overlays(side.job, *side.accel, camera, side.outcome);
}

Frame side_frame(const Side& side) {
  const Overlays& overlays = side.overlays;
  return {overlays.heat.empty() ? side.outcome.image.rgba : overlays.heat,
          pixel_distances(side.outcome), overlays.lines,
          [&side] { panel(side.job, side.label, side.stats, side.overlays); }};
}

// A comparison's frames: A and B, and with a heatmap B - A; both heatmaps on one scale. The
// totals side by side go to stdout.
std::vector<Frame> comparison_frames(std::vector<Side>& sides) {
  Overlays &a = sides[0].overlays, &b = sides[1].overlays;
  const float shared = shared_heat_max(a.heat_values, b.heat_values);
  paint_heat(a, shared);
  paint_heat(b, shared);
  std::fputs(totals_table(compare_totals(sides[0].label, sides[0].stats),
                          compare_totals(sides[1].label, sides[1].stats))
                 .c_str(),
             stdout);
  std::vector<Frame> frames = {side_frame(sides[0]), side_frame(sides[1])};
  if (a.heat_values.empty()) return frames;
  const HeatKind kind = sides[0].job.overlays.heat;
  const float range = difference_range(a.heat_values, b.heat_values);
  std::printf(
      "heat:%s on one scale 0..%.6g; B - A from -%.6g (blue) to +%.6g (red), beyond saturated\n",
      heat_name(kind), double(shared), double(range), double(range));
  frames.push_back({difference_image(a.heat_values, b.heat_values), {}, {}, [kind, range] {
                      difference_panel(kind, range);
                    }});
  return frames;
}

// Draws each frame in turn and lays them side by side, left to right, in one PNG.
void draw_and_write(const std::string& path, int width, int height, const Scene& scene,
                    const Camera& camera, const std::vector<Frame>& frames, bool ui) {
  gl::HeadlessContext context(width, height);
  const size_t row = size_t(width) * 4, wide_row = row * frames.size();
  std::vector<uint8_t> png(wide_row * size_t(height));
  for (size_t f = 0; f < frames.size(); ++f) {
    gl::FrameInput input;
    input.image_width = width;
    input.image_height = height;
    input.rgba = frames[f].rgba;
    input.distance = frames[f].distances;
    input.camera = camera;
    input.scene_box = scene.bounds();
    input.lines = frames[f].lines;
    {
      gl::FrameRenderer renderer;
      renderer.draw(width, height, input);
    }
    if (ui && frames[f].panel) draw_panel(width, height, frames[f].panel);
    const std::vector<uint8_t> pixels = gl::read_pixels(width, height);
    for (int y = 0; y < height; ++y)
      std::copy_n(pixels.begin() + ptrdiff_t(row * size_t(y)), row,
                  png.begin() + ptrdiff_t(wide_row * size_t(y) + row * f));
  }
  write_png(path, int(frames.size()) * width, height, png);
}

}  // namespace

void run_shot(const ShotJob& job) {
  std::vector<Side> sides = make_sides(job);
  const Scene scene = load_scene(job.scene);
  const Camera camera = camera_for(job.camera, scene, job.settings);
  for (Side& side : sides) run_side(side, scene, camera);
  std::vector<Frame> frames;
  if (sides.size() == 2) {
    frames = comparison_frames(sides);
  } else {
    paint_heat(sides[0].overlays, own_heat_max(sides[0].overlays));
    frames.push_back(side_frame(sides[0]));
  }
  draw_and_write(job.out_path, job.settings.width, job.settings.height, scene, camera, frames,
                 job.ui);
}

}  // namespace gs::app
