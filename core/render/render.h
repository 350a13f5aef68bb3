// The CPU renderer behind `gridscope render` (and the viewer's image): one primary ray per
// sample, Lambert shading from the geometric normal with one shadow ray toward a point
// light above and behind the camera, an ambient term, a constant background (the paper's
// workload, §7); optionally diffuse bounces, each hit lit the same way.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/accel/accelerator.h"
#include "core/base/parallel.h"
#include "core/scene/camera.h"
#include "core/scene/scene.h"
#include "core/trace/run.h"

namespace gs {

// Dark grey-blue, 8-bit RGB exactly as written for pixels whose rays all miss.
constexpr std::array<uint8_t, 3> kBackground = {28, 32, 44};

constexpr int kMaxImageSide = 16384;
constexpr int kMaxSpp = 65536;
constexpr int kMaxBounces = 4;

struct RenderSettings {
  int width = 640;
  int height = 480;
  // 1: one ray through each pixel centre; more: jittered with a fixed per-pixel/sample hash,
  // so that every run gives the same image.
  int spp = 1;
  int threads = default_thread_count();
  // 0: the paper's workload, a primary ray and a shadow ray per sample. N: also N chained
  // diffuse bounces (cosine-weighted, fixed hash), each hit lit with its own shadow ray.
  int bounces = 0;
  // Where the point light is; default: above and behind the camera. A closed interior (the
  // bench's cathedral) needs it inside, or every shadow ray ends on the roof.
  std::optional<glm::vec3> light = std::nullopt;
  // With a structure that walks rays together (Accelerator::traces_packets): the primary
  // rays of each 8x8 pixel block, then the shadow rays from their hits, go to trace_packet
  // together. Same answers, same image; the pixels' records then share their block's cost.
  // Bounces scatter and are traced one at a time.
  bool packets = true;
};

// Throws UsageError unless the size is 1..kMaxImageSide per side, spp 1..kMaxSpp, bounces
// 0..kMaxBounces and the thread count is valid.
void check_render_settings(const RenderSettings& settings);

struct Image {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgba;  // row-major from the top-left pixel, 4 bytes per pixel
};

// What one pixel's rays cost (summed over its samples, primary and shadow rays) and how far
// its primary hit is: the data behind the heatmaps and the depth-tested overlays.
struct PixelRecord {
  float depth = 0.0f;  // distance of the first sample's primary hit along the view axis
                       // (camera forward), +inf for background
  uint32_t steps = 0;  // traversal_steps
  uint32_t tests = 0;  // intersection_tests
  uint32_t built = 0;  // voxels_built (lazily, while tracing this pixel)
};

struct RenderOutcome {
  Image image;
  std::vector<PixelRecord> pixels;  // width * height, row-major from the top-left
  uint64_t rays = 0;                // primary plus shadow rays
  double seconds = 0.0;
  // This process's CPU time (all threads) over the same window as `seconds`: the cores the
  // trace kept busy, without the image's allocation around it.
  double cpu_seconds = 0.0;
  TraceCounters counters;
};

// The paper's sampling pass for an image (docs/design.md §1.5): the primary ray of one pixel
// in every 8x8 block, standing for all width * height * spp primary rays, and the shadow ray
// from its hit, standing for the shadow rays of those primaries.
void sample_image(const Scene& scene, Accelerator& accel, const Camera& camera,
                  const RenderSettings& settings);

// Which of a bounce's two rays: the nearest-hit ray (primary or diffuse bounce) or the
// shadow ray from its hit toward the light.
enum class RayKind { nearest = 0, shadow = 1 };

// Every ray a render may cast has a key, a pure function of (pixel, sample, bounce, kind)
// and never of thread scheduling: the renderer puts it in ThreadContext::ray_index, the
// "zero" oracle and --record-hits are indexed by it. Keys run over [0, render_ray_keys()):
// pixel-major, then sample, bounce (0 = the primary ray's) and kind.
inline uint64_t render_ray_key(const RenderSettings& settings, size_t pixel, int sample, int bounce,
                               RayKind kind) {
  const uint64_t bounce_slot = (uint64_t(pixel) * uint64_t(settings.spp) + uint64_t(sample)) *
                                   uint64_t(settings.bounces + 1) +
                               uint64_t(bounce);
  return bounce_slot * 2 + uint64_t(kind);
}
// width * height * spp * (bounces + 1) * 2.
uint64_t render_ray_keys(const RenderSettings& settings);

// Renders with an accelerator already built over `scene`, rows spread over the threads.
// With `answers`, it becomes render_ray_keys() hits, each the answer to the ray of that key
// (intersect's for nearest rays, any_hit's for shadow rays), a miss for rays not cast: the
// oracle "zero" replays. With "zero", throws InputError unless its oracle holds one hit
// per key.
RenderOutcome render_image(const Scene& scene, const Accelerator& accel, const Camera& camera,
                           const RenderSettings& settings, std::vector<Hit>* answers = nullptr);

// How render_pass runs each band of rows: run_row(row) calls row() to render it, or returns
// without calling it to skip it (a cancelled pass). A band is a row of tiles (the coarse
// pass), 8 rows with packets, or one row. Called on the rendering threads, one band at a
// time per thread; it may block (to pause the pass between bands).
using RowRunner = std::function<void(const std::function<void()>& row)>;

// One pass of the viewer's progressive renderer (core/render/progressive.h), by render_image's own
// shading, rows spread over settings.threads threads.
// - stride 1: samples [first_sample, settings.spp) of every pixel, the samples render_image
//   takes for settings.spp (pixel centres for spp 1, its fixed jitter otherwise). `sums`
//   (width * height display-space colours; may be null when first_sample is 0) keeps each
//   pixel's running sum, started afresh when first_sample is 0, and the image is that sum
//   divided by settings.spp: after passes covering samples 0 .. spp - 1 it equals render_image's
//   image for settings.spp exactly. The pixels' records count this pass's samples (depth only when
//   it takes sample 0, else 0).
// - stride > 1 (spp 1, no sums; the coarse pass): one ray through the centre of the pixel
//   image_sample_pixels picks in each stride x stride tile (for 8), every pixel of the tile
//   taking its colour and record.
// run_row, when given, runs or skips each band of rows; a skipped band leaves its pixels
// as `storage` had them (zero when it brought none). The outcome's image and records are
// written into `storage`'s vectors (resized to the image: an earlier pass's of the same
// size cost no allocation). Throws std::invalid_argument for inconsistent arguments.
struct PassStorage {
  std::vector<uint8_t> rgba;
  std::vector<PixelRecord> pixels;
};
RenderOutcome render_pass(const Scene& scene, const Accelerator& accel, const Camera& camera,
                          const RenderSettings& settings, int stride, int first_sample,
                          std::vector<glm::vec3>* sums, const RowRunner& run_row = {},
                          PassStorage storage = {});

// Throws InputError naming the path when the PNG cannot be written.
void write_png(const std::string& path, int width, int height, const std::vector<uint8_t>& rgba);

// The camera a job asked for, or the default one framing the scene for this image size.
Camera camera_for(const std::optional<Camera>& camera, const Scene& scene,
                  const RenderSettings& settings);

// Builds the structure over the scene, runs the image's sampling pass and renders: what
// `render` and `shot` both do. The figures are the run's, for run_stats.
struct RenderRun {
  RenderOutcome outcome;
  RunFigures figures;
};
// `answers` as in render_image.
RenderRun build_and_render(const Scene& scene, Accelerator& accel, const Camera& camera,
                           const RenderSettings& settings, std::vector<Hit>* answers = nullptr);

struct RenderJob {
  std::string scene;
  std::string out_path;    // PNG
  std::string stats_path;  // stats JSON; empty for none
  std::string hits_path;   // every ray's answer by key (--record-hits); empty for none
  std::string accel = "grid1d";
  AccelParams params;
  RenderSettings settings;
  std::optional<Camera> camera;  // default: frame_box of the scene
};

// The `render` command: makes the accelerator (usage errors first), loads the scene, builds,
// samples, renders, writes the PNG and, if asked, the recorded hits and the stats (the keys
// of trace's, with rays = every ray cast). Returns the stats.
nlohmann::json run_render(const RenderJob& job);

}  // namespace gs
