#include "core/render/render.h"

#include <png.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <glm/geometric.hpp>
#include <optional>
#include <span>
#include <stdexcept>

#include "core/base/error.h"
#include "core/base/files.h"
#include "core/base/hash.h"
#include "core/base/timing.h"
#include "core/geometry/ray_io.h"
#include "core/render/display.h"
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

// The rays a render casts go through here, each under its key (set as the context's
// ray_index, or passed to trace_packet, so that "zero" finds its answer), counted and, when
// answers is given, recorded.
struct RayCaster {
  const Accelerator& accel;
  ThreadContext& context;
  Hit* answers;  // render_ray_keys() hits, or null
  uint64_t& rays;

  Hit cast(const Ray& ray, uint64_t key, RayKind kind) {
    context.ray_index = key;
    ++rays;
    const Hit hit =
        kind == RayKind::nearest ? accel.intersect(ray, context) : accel.any_hit(ray, context);
    if (answers) answers[key] = hit;  // keys are disjoint between threads: no lock
    return hit;
  }

  // Up to kMaxPacketRays rays of one kind walked together (Accelerator::trace_packet):
  // each answer is the one cast() gives.
  void cast_packet(std::span<const Ray> packet, std::span<const uint64_t> keys, std::span<Hit> hits,
                   RayKind kind) {
    if (packet.empty()) return;
    rays += packet.size();
    accel.trace_packet(packet, keys, hits, kind == RayKind::shadow, context);
    if (answers)
      for (size_t i = 0; i < packet.size(); ++i) answers[keys[i]] = hits[i];
  }
};

// One sample of one pixel: casts its rays under their keys.
struct SampleTracer {
  const Scene& scene;
  RayCaster& caster;
  const RenderSettings& settings;
  const Lighting& lighting;
  size_t pixel;
  int sample;

  uint64_t key(int bounce, RayKind kind) const {
    return render_ray_key(settings, pixel, sample, bounce, kind);
  }
  Hit cast(const Ray& ray, int bounce, RayKind kind) {
    return caster.cast(ray, key(bounce, kind), kind);
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

// Linear colour of a primary ray's hit lit by `lambert` (0 when shadowed) and by the light
// its bounces brought.
glm::vec3 hit_colour(float lambert, const glm::vec3& bounced) {
  return kAlbedo * (kAmbient + (1.0f - kAmbient) * lambert) + kAlbedo * bounced;
}

// A counter difference as a PixelRecord field; saturates rather than wrapping (only a huge
// spp on a huge scene could exceed it).
uint32_t count_since(uint64_t now, uint64_t before) {
  return uint32_t(std::min<uint64_t>(now - before, UINT32_MAX));
}

// A block's total split over its n pixels so that the shares add up to it: total / n each,
// one more for the first total % n pixels.
struct Share {
  uint32_t each, extra;
  Share(uint32_t total, size_t n) : each(uint32_t(total / n)), extra(uint32_t(total % n)) {}
  uint32_t of(size_t i) const { return each + (i < extra ? 1 : 0); }
};

// Packets trace blocks of 8x8 pixels (kMaxPacketRays rays): the primary rays of neighbouring
// pixels, and the shadow rays from their hits toward the one light, walk nearly the same cells.
constexpr int kPacketSide = 8;
constexpr size_t kMaxBlock = Accelerator::kMaxPacketRays;
static_assert(kPacketSide * kPacketSide == kMaxBlock);

// A pixel a block traces: where its ray goes through the image, and its index.
struct BlockPixel {
  int x, y;
  size_t index;
};

// Shades blocks of pixels: one pixel at a time (single rays), or up to kMaxBlock pixels whose
// primary rays, then shadow rays, go to trace_packet together. Bounces, which scatter, are
// traced one at a time either way.
struct BlockShader {
  const Scene& scene;
  RayCaster& caster;
  const Camera& camera;
  const RenderSettings& settings;
  const Lighting& lighting;
  bool packets;
  const glm::vec3 forward = camera.forward();
  // Set up once per band: a block may be a single pixel.
  const PrimaryRays primary_ray{camera, settings.width, settings.height};
  // A block's rays and what they found, kept here rather than on each sample's stack: Ray,
  // Hit and the vectors initialise their members, kilobytes per sample of a single pixel.
  struct Scratch {
    std::array<Ray, kMaxBlock> primary, shadow;
    std::array<uint64_t, kMaxBlock> keys, shadow_keys;
    std::array<Hit, kMaxBlock> hits, blocked;
    std::array<Surface, kMaxBlock> surfaces;
    std::array<float, kMaxBlock> lambert;
    std::array<size_t, kMaxBlock> lit;
    std::array<glm::vec3, kMaxBlock> colours;
    std::array<std::array<uint8_t, 3>, kMaxBlock> bytes;
  } scratch = {};

  // Rays of one kind, each answered as cast() answers it.
  void cast_all(std::span<const Ray> rays, std::span<const uint64_t> keys, std::span<Hit> hits,
                RayKind kind) {
    if (packets) return caster.cast_packet(rays, keys, hits, kind);
    for (size_t i = 0; i < rays.size(); ++i) hits[i] = caster.cast(rays[i], keys[i], kind);
  }

  // Adds sample s of each pixel (pixel centres for spp 1, a fixed jitter otherwise) to its
  // display-space colour or, given `bytes` (an image of one sample that keeps no sums), sets
  // the pixel's bytes from its linear colour by the display table: the same bytes. With
  // sample 0, sets each pixel's record's depth.
  void shade_sample(std::span<const BlockPixel> pixels, int s, glm::vec3* colours,
                    std::array<uint8_t, 3>* bytes, PixelRecord* records) {
    static const glm::vec3 background =
        glm::vec3(kBackground[0], kBackground[1], kBackground[2]) / 255.0f;
    static const std::array<uint8_t, 3> background_bytes = display_bytes(background);
    const int w = settings.width, spp = settings.spp;
    const size_t n = pixels.size();
    auto& primary = scratch.primary;
    auto& shadow = scratch.shadow;
    auto& keys = scratch.keys;
    auto& shadow_keys = scratch.shadow_keys;
    auto& hits = scratch.hits;
    auto& blocked = scratch.blocked;
    auto& surfaces = scratch.surfaces;
    auto& lambert = scratch.lambert;
    auto& lit = scratch.lit;
    for (size_t i = 0; i < n; ++i) {
      const uint32_t seed = mix_bits(uint32_t(pixels[i].y) * uint32_t(w) + uint32_t(pixels[i].x));
      const float jx = spp == 1 ? 0.5f : hashed_unit(seed, 2 * uint32_t(s));
      const float jy = spp == 1 ? 0.5f : hashed_unit(seed, 2 * uint32_t(s) + 1);
      primary[i] = primary_ray(pixels[i].x, pixels[i].y, jx, jy);
      keys[i] = render_ray_key(settings, pixels[i].index, s, 0, RayKind::nearest);
    }
    cast_all({primary.data(), n}, {keys.data(), n}, {hits.data(), n}, RayKind::nearest);
    // The shadow rays of the hits whose surface faces the light.
    size_t shadows = 0;
    for (size_t i = 0; i < n; ++i) {
      lambert[i] = 0.0f;
      if (!hits[i].found()) continue;
      surfaces[i] = surface_at(scene, hits[i], primary[i].dir);
      const std::optional<LightPath> path = light_path(surfaces[i], lighting);
      if (!path) continue;
      lambert[i] = path->lambert;
      shadow[shadows] = path->shadow;
      shadow_keys[shadows] = render_ray_key(settings, pixels[i].index, s, 0, RayKind::shadow);
      lit[shadows++] = i;
    }
    cast_all({shadow.data(), shadows}, {shadow_keys.data(), shadows}, {blocked.data(), shadows},
             RayKind::shadow);
    for (size_t k = 0; k < shadows; ++k)
      if (blocked[k].found()) lambert[lit[k]] = 0.0f;
    for (size_t i = 0; i < n; ++i) {
      // t is in units of the unnormalised direction: its projection on the unit forward
      // vector turns it into distance along the view axis (what a depth buffer compares).
      const float t = hits[i].t;
      if (s == 0)
        records[pixels[i].index].depth = std::isinf(t) ? t : t * glm::dot(primary[i].dir, forward);
      if (!hits[i].found()) {
        if (bytes)
          bytes[i] = background_bytes;
        else
          colours[i] += background;
        continue;
      }
      // With no bounces the sum adds an exact 0: the paper's workload's colours, unchanged.
      glm::vec3 bounced(0.0f);
      if (settings.bounces > 0) {
        SampleTracer tracer{scene, caster, settings, lighting, pixels[i].index, s};
        bounced = bounce_light(tracer, surfaces[i], 1);
      }
      const glm::vec3 linear = hit_colour(lambert[i], bounced);
      if (bytes)
        bytes[i] = linear_bytes(linear);
      else
        colours[i] += display_colour(linear);
    }
  }

  // Shades samples [first_sample, spp) of each pixel, added to its running sum in `sums`
  // when given (the image shows the sum over spp samples). The pixels' records share what
  // the block's rays cost (a pixel of its own with single rays: exactly its rays' cost).
  void shade_block(std::span<const BlockPixel> pixels, int first_sample, glm::vec3* sums,
                   uint8_t* rgba, PixelRecord* records) {
    const size_t n = pixels.size();
    const TraceCounters before = caster.context.counters;
    auto& colours = scratch.colours;
    const bool one_sample = settings.spp == 1 && !sums;
    for (size_t i = 0; i < n; ++i)
      colours[i] = sums && first_sample > 0 ? sums[pixels[i].index] : glm::vec3(0.0f);
    for (int s = first_sample; s < settings.spp; ++s)
      shade_sample(pixels, s, colours.data(), one_sample ? scratch.bytes.data() : nullptr, records);
    const TraceCounters& after = caster.context.counters;
    const Share steps(count_since(after.traversal_steps, before.traversal_steps), n);
    const Share tests(count_since(after.intersection_tests, before.intersection_tests), n);
    const Share built(count_since(after.voxels_built, before.voxels_built), n);
    for (size_t i = 0; i < n; ++i) {
      const size_t index = pixels[i].index;
      if (sums) sums[index] = colours[i];
      const std::array<uint8_t, 3> rgb =
          one_sample ? scratch.bytes[i] : display_bytes(colours[i] / float(settings.spp));
      uint8_t* pixel = &rgba[4 * index];
      std::copy(rgb.begin(), rgb.end(), pixel);
      pixel[3] = 255;
      if (first_sample > 0) records[index].depth = 0.0f;  // set by sample 0 only
      records[index].steps = steps.of(i);
      records[index].tests = tests.of(i);
      records[index].built = built.of(i);
    }
  }
};

// Shades band `band` of the image. With stride 1 the band is `side` image rows (1 for single
// rays, kPacketSide for packets), shaded in blocks of side x side pixels; each pixel takes
// samples [first_sample, settings.spp). With stride > 1 (the coarse pass) the band is a row of
// stride x stride tiles: one ray goes through the pixel image_sample_pixels picks in each,
// `side` tiles to a block, and every pixel of a tile gets its colour and record.
void shade_band(BlockShader& shader, int side, int stride, int band, int first_sample,
                glm::vec3* sums, uint8_t* rgba, PixelRecord* records) {
  const int w = shader.settings.width, h = shader.settings.height;
  std::array<BlockPixel, kMaxBlock> block;
  const auto at = [&](int x, int y) { return BlockPixel{x, y, size_t(y) * size_t(w) + size_t(x)}; };
  if (stride == 1) {
    const int y0 = band * side, y1 = std::min(y0 + side, h);
    for (int x0 = 0; x0 < w; x0 += side) {
      size_t n = 0;
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < std::min(x0 + side, w); ++x) block[n++] = at(x, y);
      shader.shade_block({block.data(), n}, first_sample, sums, rgba, records);
    }
    return;
  }
  const int tiles = (w + stride - 1) / stride;
  const int py = std::min(band * stride + stride / 2, h - 1);
  for (int t0 = 0; t0 < tiles; t0 += side) {
    size_t n = 0;
    for (int tx = t0; tx < std::min(t0 + side, tiles); ++tx)
      block[n++] = at(std::min(tx * stride + stride / 2, w - 1), py);
    shader.shade_block({block.data(), n}, first_sample, sums, rgba, records);
    // Fill each tile with its ray's pixel.
    for (size_t i = 0; i < n; ++i) {
      const int tx = t0 + int(i);
      const int x0 = tx * stride, y0 = band * stride;
      const int x1 = std::min(x0 + stride, w), y1 = std::min(y0 + stride, h);
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
          const size_t other = size_t(y) * size_t(w) + size_t(x);
          if (other == block[i].index) continue;
          records[other] = records[block[i].index];
          std::copy_n(&rgba[4 * block[i].index], 4, &rgba[4 * other]);
        }
    }
  }
}

// Renders bands of rows (shade_band) into an outcome whose image and records are written
// into `storage` (every pixel of every band run, so what storage held does not show), bands
// spread over the threads; run_row (when given) runs or skips each band.
RenderOutcome render_rows(const Scene& scene, const Accelerator& accel, const Camera& camera,
                          const RenderSettings& settings, int stride, int first_sample,
                          glm::vec3* sums, Hit* answers, const RowRunner& run_row,
                          PassStorage storage) {
  RenderOutcome outcome;
  Image& image = outcome.image;
  image.width = settings.width;
  image.height = settings.height;
  image.rgba = std::move(storage.rgba);
  image.rgba.resize(size_t(image.width) * size_t(image.height) * 4);
  outcome.pixels = std::move(storage.pixels);
  outcome.pixels.resize(size_t(image.width) * size_t(image.height));
  const Lighting lighting = make_lighting(accel.bounds(), camera, settings.light);
  const bool packets = settings.packets && accel.traces_packets();
  const int side = packets ? kPacketSide : 1;
  const int band_rows = stride > 1 ? stride : side;
  const size_t bands = size_t((settings.height + band_rows - 1) / band_rows);
  std::atomic<uint64_t> rays{0};
  const TraceChunk rows = [&](ThreadContext& context, size_t begin, size_t end) {
    uint64_t band_rays = 0;
    RayCaster caster{accel, context, answers, band_rays};
    BlockShader shader{scene, caster, camera, settings, lighting, packets};
    for (size_t band = begin; band < end; ++band) {
      auto shade = [&] {
        shade_band(shader, side, stride, int(band), first_sample, sums, image.rgba.data(),
                   outcome.pixels.data());
      };
      if (run_row)
        run_row(shade);
      else
        shade();
    }
    rays.fetch_add(band_rays, std::memory_order_relaxed);
  };
  const double cpu_start = process_cpu_seconds();
  outcome.seconds =
      seconds_of([&] { outcome.counters = trace_chunks(accel, bands, 1, settings.threads, rows); });
  outcome.cpu_seconds = process_cpu_seconds() - cpu_start;
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
  parameters["packets"] = job.settings.packets;
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
  const PrimaryRays primary_ray(camera, w, h);
  for (const size_t pixel : image_sample_pixels(w, h))
    primaries.push_back(primary_ray(int(pixel % size_t(w)), int(pixel / size_t(w))));
  sample_image_rays(accel, scene, make_lighting(accel.bounds(), camera, settings.light), primaries,
                    size_t(w) * size_t(h) * size_t(settings.spp), settings.threads);
}

RenderOutcome render_image(const Scene& scene, const Accelerator& accel, const Camera& camera,
                           const RenderSettings& settings, std::vector<Hit>* answers) {
  accel.check_ray_keys(render_ray_keys(settings), "ray key of this render");
  if (answers) answers->assign(render_ray_keys(settings), Hit{});
  return render_rows(scene, accel, camera, settings, 1, 0, nullptr,
                     answers ? answers->data() : nullptr, {}, {});
}

RenderOutcome render_pass(const Scene& scene, const Accelerator& accel, const Camera& camera,
                          const RenderSettings& settings, int stride, int first_sample,
                          std::vector<glm::vec3>* sums, const RowRunner& run_row,
                          PassStorage storage) {
  if (stride < 1 || first_sample < 0 || first_sample >= settings.spp ||
      (stride > 1 && (settings.spp != 1 || sums)) ||
      (sums && sums->size() != size_t(settings.width) * size_t(settings.height)) ||
      (!sums && first_sample > 0))
    throw std::invalid_argument("render_pass: inconsistent stride, samples or sums");
  return render_rows(scene, accel, camera, settings, stride, first_sample,
                     sums ? sums->data() : nullptr, nullptr, run_row, std::move(storage));
}

void write_png(const std::string& path, int width, int height, const std::vector<uint8_t>& rgba) {
  // libpng's fast setting (no row filter, zlib level 3): for a rendered frame 8 times faster
  // than stb's encoder, whose per-row filter search and own deflate took as long as the
  // frame's tracing, and still smaller files than stb wrote. Encoded into memory in one pass
  // (the buffer is the format's bound) and written by write_file, which checks the write
  // and the close.
  // Checked before the buffer is sized from them.
  if (width <= 0 || height <= 0 || rgba.size() != size_t(width) * size_t(height) * 4)
    fail_input(path, "cannot encode PNG: a bad image size");
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = png_uint_32(width);
  image.height = png_uint_32(height);
  image.format = PNG_FORMAT_RGBA;
  image.flags = PNG_IMAGE_FLAG_FAST;
  png_alloc_size_t size = PNG_IMAGE_PNG_SIZE_MAX(image);
  std::vector<char> png(size);
  const bool encoded =
      png_image_write_to_memory(&image, png.data(), &size, 0, rgba.data(), width * 4, nullptr);
  const std::string problem = image.message;
  png_image_free(&image);
  if (!encoded) fail_input(path, "cannot encode PNG: " + problem);
  png.resize(size);
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
