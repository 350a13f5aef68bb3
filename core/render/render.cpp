#include "core/render/render.h"

#include <stb_image_write.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <glm/geometric.hpp>
#include <optional>
#include <stdexcept>

#include "core/base/error.h"
#include "core/base/files.h"
#include "core/base/hash.h"
#include "core/base/timing.h"
#include "core/geometry/ray_io.h"
#include "core/scene/lighting.h"
#include "core/trace/sampling.h"

namespace gs {

namespace {

constexpr glm::vec3 kAlbedo{0.85f, 0.80f, 0.72f};
constexpr float kAmbient = 0.15f;

float unit_float(uint32_t bits) { return float(bits >> 8) * (1.0f / 16777216.0f); }

// A uniform number in [0, 1) for stream `stream` of a seed: the pixel jitter and the
// bounce directions, the same every run.
float hashed_unit(uint32_t seed, uint32_t stream) {
  return unit_float(mix_bits(seed ^ mix_bits(stream)));
}

// Casts one sample's rays, each under its key (set as the context's ray_index, so that
// "zero" finds its answer), counting them and, when answers is given, recording them.
struct SampleTracer {
  const Scene& scene;
  const Accelerator& accel;
  ThreadContext& context;
  const RenderSettings& settings;
  const Lighting& lighting;
  Hit* answers;  // render_ray_keys() hits, or null
  uint64_t& rays;
  size_t pixel;
  int sample;

  Hit cast(const Ray& ray, int bounce, RayKind kind) {
    const uint64_t key = render_ray_key(settings, pixel, sample, bounce, kind);
    context.ray_index = key;
    ++rays;
    const Hit hit =
        kind == RayKind::nearest ? accel.intersect(ray, context) : accel.any_hit(ray, context);
    if (answers) answers[key] = hit;  // keys are disjoint between threads: no lock
    return hit;
  }
};

// The cosine of the light's angle to the normal, 0 when the light is behind the surface or
// the shadow ray (bounce's, cast only toward a lit side) is blocked.
float direct_light(SampleTracer& tracer, const Surface& surface, int bounce) {
  const std::optional<LightPath> path = light_path(surface, tracer.lighting);
  if (!path) return 0.0f;
  return tracer.cast(path->shadow, bounce, RayKind::shadow).found() ? 0.0f : path->lambert;
}

// A cosine-weighted direction about the unit normal from two uniform numbers (Malley's
// method: a uniform point on the disc lifted to the hemisphere), in the orthonormal basis
// of Duff et al. 2017 ("Building an Orthonormal Basis, Revisited").
glm::vec3 cosine_direction(const glm::vec3& n, float u1, float u2) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float b = n.x * n.y * a;
  const glm::vec3 tangent{1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x};
  const glm::vec3 bitangent{b, sign + n.y * n.y * a, -n.y};
  const float r = std::sqrt(u1), phi = 6.28318530718f * u2;
  return r * std::cos(phi) * tangent + r * std::sin(phi) * bitangent +
         std::sqrt(std::max(0.0f, 1.0f - u1)) * n;
}

// Linear radiance arriving at `surface` along diffuse bounce `bounce` (1..settings.bounces)
// and the ones after it: the bounce hit's direct light plus, by the same rule, what it
// receives (a cosine-weighted direction makes the estimate albedo * incoming radiance).
// A bounce that leaves the scene brings nothing.
glm::vec3 bounce_light(SampleTracer& tracer, const Surface& surface, int bounce) {
  if (bounce > tracer.settings.bounces) return glm::vec3(0.0f);
  const uint32_t seed = mix_bits(uint32_t(tracer.pixel) + 0x9e3779b9u * uint32_t(bounce));
  Ray ray;
  ray.origin = ray_start(surface, tracer.lighting);
  ray.dir = cosine_direction(surface.normal, hashed_unit(seed, 2 * uint32_t(tracer.sample)),
                             hashed_unit(seed, 2 * uint32_t(tracer.sample) + 1));
  const Hit hit = tracer.cast(ray, bounce, RayKind::nearest);
  if (!hit.found()) return glm::vec3(0.0f);
  const Surface next = surface_at(tracer.scene, hit, ray.dir);
  const float lambert = direct_light(tracer, next, bounce);
  return kAlbedo * ((1.0f - kAmbient) * lambert + bounce_light(tracer, next, bounce + 1));
}

// Display-space colour of one primary ray; reports its hit's t (+inf for a miss) for the
// pixel's depth.
glm::vec3 shade(SampleTracer& tracer, const Ray& ray, float& hit_t) {
  static const glm::vec3 background =
      glm::vec3(kBackground[0], kBackground[1], kBackground[2]) / 255.0f;
  const Hit hit = tracer.cast(ray, 0, RayKind::nearest);
  hit_t = hit.t;
  if (!hit.found()) return background;
  const Surface surface = surface_at(tracer.scene, hit, ray.dir);
  // With no bounces the sum adds an exact 0: the paper's workload's colours, unchanged.
  const float lambert = direct_light(tracer, surface, 0);
  const glm::vec3 linear = kAlbedo * (kAmbient + (1.0f - kAmbient) * lambert) +
                           kAlbedo * bounce_light(tracer, surface, 1);
  return glm::pow(glm::min(linear, 1.0f), glm::vec3(1.0f / 2.2f));
}

// A counter difference as a PixelRecord field; saturates rather than wrapping (only a huge
// spp on a huge scene could exceed it).
uint32_t count_since(uint64_t now, uint64_t before) {
  return uint32_t(std::min<uint64_t>(now - before, UINT32_MAX));
}

// What the pixel's rays cost, from the thread's counters before and after it: the context
// belongs to this thread alone, so the difference is exactly this pixel's work.
void record_costs(const TraceCounters& before, const TraceCounters& after, PixelRecord& record) {
  record.steps = count_since(after.traversal_steps, before.traversal_steps);
  record.tests = count_since(after.intersection_tests, before.intersection_tests);
  record.built = count_since(after.voxels_built, before.voxels_built);
}

// Shades one tile row of the image. With stride 1 the tile row is image row `ty` and each
// pixel takes samples [first_sample, settings.spp), added to its running sum in `sums` when
// given (the image shows the sum over settings.spp samples). With stride > 1 (the coarse
// pass) one ray goes through the pixel image_sample_pixels picks in each stride x stride
// tile, whose pixels all get its colour and record. rgba and records are the whole image's.
void shade_row(const Scene& scene, const Accelerator& accel, ThreadContext& context,
               const Camera& camera, const RenderSettings& settings, const Lighting& lighting,
               int stride, int ty, int first_sample, glm::vec3* sums, uint8_t* rgba,
               PixelRecord* records, Hit* answers, uint64_t& rays) {
  const int w = settings.width, h = settings.height, spp = settings.spp;
  const glm::vec3 forward = camera.forward();
  const int py = stride == 1 ? ty : std::min(ty * stride + stride / 2, h - 1);
  for (int tx = 0; tx * stride < w; ++tx) {
    const int px = stride == 1 ? tx : std::min(tx * stride + stride / 2, w - 1);
    const size_t index = size_t(py) * size_t(w) + size_t(px);
    PixelRecord& record = records[index];
    const TraceCounters before = context.counters;
    glm::vec3 sum = sums && first_sample > 0 ? sums[index] : glm::vec3(0.0f);
    const uint32_t seed = mix_bits(uint32_t(py) * uint32_t(w) + uint32_t(px));
    for (int s = first_sample; s < spp; ++s) {
      const float jx = spp == 1 ? 0.5f : hashed_unit(seed, 2 * uint32_t(s));
      const float jy = spp == 1 ? 0.5f : hashed_unit(seed, 2 * uint32_t(s) + 1);
      const Ray ray = camera.primary_ray(px, py, w, h, jx, jy);
      SampleTracer tracer{scene, accel, context, settings, lighting, answers, rays, index, s};
      float hit_t = 0.0f;
      sum += shade(tracer, ray, hit_t);
      // t is in units of the unnormalised direction: its projection on the unit forward
      // vector turns it into distance along the view axis (what a depth buffer compares).
      if (s == 0) record.depth = std::isinf(hit_t) ? hit_t : hit_t * glm::dot(ray.dir, forward);
    }
    if (sums) sums[index] = sum;
    record_costs(before, context.counters, record);
    const glm::vec3 colour = glm::clamp(sum / float(spp), 0.0f, 1.0f) * 255.0f + 0.5f;
    uint8_t* pixel = &rgba[4 * index];
    for (int k = 0; k < 3; ++k) pixel[k] = uint8_t(colour[k]);
    pixel[3] = 255;
    if (stride == 1) continue;
    // Fill the tile with the ray's pixel.
    const int x0 = tx * stride, y0 = ty * stride;
    const int x1 = std::min(x0 + stride, w), y1 = std::min(y0 + stride, h);
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        const size_t other = size_t(y) * size_t(w) + size_t(x);
        if (other == index) continue;
        records[other] = record;
        std::copy(pixel, pixel + 4, &rgba[4 * other]);
      }
  }
}

// Renders tile rows of `stride`-pixel tiles into a fresh outcome, rows spread over the
// threads; run_row (when given) runs or skips each row.
RenderOutcome render_rows(const Scene& scene, const Accelerator& accel, const Camera& camera,
                          const RenderSettings& settings, int stride, int first_sample,
                          glm::vec3* sums, Hit* answers, const RowRunner& run_row) {
  RenderOutcome outcome;
  Image& image = outcome.image;
  image.width = settings.width;
  image.height = settings.height;
  image.rgba.resize(size_t(image.width) * size_t(image.height) * 4);
  outcome.pixels.resize(size_t(image.width) * size_t(image.height));
  const Lighting lighting = make_lighting(scene, camera, settings.light);
  const size_t tile_rows = size_t((settings.height + stride - 1) / stride);
  std::atomic<uint64_t> rays{0};
  const TraceChunk rows = [&](ThreadContext& context, size_t begin, size_t end) {
    uint64_t row_rays = 0;
    for (size_t ty = begin; ty < end; ++ty) {
      auto row = [&] {
        shade_row(scene, accel, context, camera, settings, lighting, stride, int(ty), first_sample,
                  sums, image.rgba.data(), outcome.pixels.data(), answers, row_rays);
      };
      if (run_row)
        run_row(row);
      else
        row();
    }
    rays.fetch_add(row_rays, std::memory_order_relaxed);
  };
  outcome.seconds = seconds_of(
      [&] { outcome.counters = trace_chunks(accel, tile_rows, 1, settings.threads, rows); });
  outcome.rays = rays.load();
  return outcome;
}

nlohmann::json render_parameters(const RenderJob& job, const Camera& camera) {
  nlohmann::json parameters = job.params.to_json();
  parameters["threads"] = job.settings.threads;
  parameters["width"] = job.settings.width;
  parameters["height"] = job.settings.height;
  parameters["spp"] = job.settings.spp;
  parameters["bounces"] = job.settings.bounces;
  parameters["camera"] = to_string(camera);
  return parameters;
}

}  // namespace

void check_render_settings(const RenderSettings& settings) {
  if (settings.width < 1 || settings.width > kMaxImageSide || settings.height < 1 ||
      settings.height > kMaxImageSide)
    throw UsageError("--size " + std::to_string(settings.width) + "x" +
                     std::to_string(settings.height) + ": each side must be 1.." +
                     std::to_string(kMaxImageSide));
  if (settings.spp < 1 || settings.spp > kMaxSpp)
    throw UsageError("--spp " + std::to_string(settings.spp) + ": must be 1.." +
                     std::to_string(kMaxSpp));
  if (settings.bounces < 0 || settings.bounces > kMaxBounces)
    throw UsageError("--bounces " + std::to_string(settings.bounces) + ": must be 0.." +
                     std::to_string(kMaxBounces));
  check_thread_count(settings.threads);
}

uint64_t render_ray_keys(const RenderSettings& settings) {
  return uint64_t(settings.width) * uint64_t(settings.height) * uint64_t(settings.spp) *
         uint64_t(settings.bounces + 1) * 2;
}

void sample_image(const Scene& scene, Accelerator& accel, const Camera& camera,
                  const RenderSettings& settings) {
  const int w = settings.width, h = settings.height;
  std::vector<Ray> primaries;
  for (const size_t pixel : image_sample_pixels(w, h))
    primaries.push_back(camera.primary_ray(int(pixel % size_t(w)), int(pixel / size_t(w)), w, h));
  sample_image_rays(accel, scene, make_lighting(scene, camera, settings.light), primaries,
                    size_t(w) * size_t(h) * size_t(settings.spp));
}

RenderOutcome render_image(const Scene& scene, const Accelerator& accel, const Camera& camera,
                           const RenderSettings& settings, std::vector<Hit>* answers) {
  accel.check_ray_keys(render_ray_keys(settings), "ray key of this render");
  if (answers) answers->assign(render_ray_keys(settings), Hit{});
  return render_rows(scene, accel, camera, settings, 1, 0, nullptr,
                     answers ? answers->data() : nullptr, {});
}

RenderOutcome render_pass(const Scene& scene, const Accelerator& accel, const Camera& camera,
                          const RenderSettings& settings, int stride, int first_sample,
                          std::vector<glm::vec3>* sums, const RowRunner& run_row) {
  if (stride < 1 || first_sample < 0 || first_sample >= settings.spp ||
      (stride > 1 && (settings.spp != 1 || sums)) ||
      (sums && sums->size() != size_t(settings.width) * size_t(settings.height)) ||
      (!sums && first_sample > 0))
    throw std::invalid_argument("render_pass: inconsistent stride, samples or sums");
  return render_rows(scene, accel, camera, settings, stride, first_sample,
                     sums ? sums->data() : nullptr, nullptr, run_row);
}

void write_png(const std::string& path, int width, int height, const std::vector<uint8_t>& rgba) {
  // Encoded in memory and written by write_file, which checks the write and the close;
  // stbi_write_png's own file output checks neither.
  std::vector<char> png;
  auto append = [](void* context, void* data, int size) {
    auto* out = static_cast<std::vector<char>*>(context);
    out->insert(out->end(), static_cast<char*>(data), static_cast<char*>(data) + size);
  };
  if (!stbi_write_png_to_func(append, &png, width, height, 4, rgba.data(), width * 4))
    fail_input(path, "cannot encode PNG");
  write_file(path, png);
}

Camera camera_for(const std::optional<Camera>& camera, const Scene& scene,
                  const RenderSettings& settings) {
  return camera ? *camera
                : frame_box(scene.bounds(), float(settings.width) / float(settings.height));
}

RenderRun build_and_render(const Scene& scene, Accelerator& accel, const Camera& camera,
                           const RenderSettings& settings, std::vector<Hit>* answers) {
  RenderRun run;
  run.figures.build_seconds = seconds_of([&] { accel.build(scene); }) +
                              seconds_of([&] { sample_image(scene, accel, camera, settings); });
  run.outcome = render_image(scene, accel, camera, settings, answers);
  run.figures.rays = run.outcome.rays;
  run.figures.trace_seconds = run.outcome.seconds;
  run.figures.counters = run.outcome.counters;
  return run;
}

nlohmann::json run_render(const RenderJob& job) {
  check_render_settings(job.settings);
  std::unique_ptr<Accelerator> accel = make_accelerator(job.accel, job.params);
  const Scene scene = load_scene(job.scene);
  const Camera camera = camera_for(job.camera, scene, job.settings);
  std::vector<Hit> answers;
  const auto [outcome, figures] = build_and_render(scene, *accel, camera, job.settings,
                                                   job.hits_path.empty() ? nullptr : &answers);
  write_png(job.out_path, outcome.image.width, outcome.image.height, outcome.image.rgba);
  if (!job.hits_path.empty()) write_hits(job.hits_path, answers);

  nlohmann::json stats = run_stats(scene, *accel, render_parameters(job, camera), figures);
  if (!job.stats_path.empty()) write_json(job.stats_path, stats);
  return stats;
}

}  // namespace gs
