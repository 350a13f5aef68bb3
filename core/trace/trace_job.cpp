#include "core/trace/trace_job.h"

#include <algorithm>
#include <cmath>

#include "core/base/error.h"
#include "core/base/files.h"
#include "core/base/timing.h"
#include "core/geometry/ray_io.h"
#include "core/trace/run.h"
#include "core/trace/sampling.h"

namespace gs {

namespace {

// Big enough that taking a chunk costs nothing next to tracing it, small enough that
// threads finish together when some rays are much slower than others.
constexpr size_t kRayChunk = 1024;

// The sampling pass's rays: the image's sample pixels, or every sample_every-th ray.
std::vector<Ray> sample_of(const std::vector<Ray>& rays, const TraceJob& job) {
  if (job.sample_image_width == 0) return sample_subset(rays, job.params.sample_every);
  const size_t pixels = size_t(job.sample_image_width) * size_t(job.sample_image_height);
  if (rays.size() != pixels)
    fail_input(job.rays_path, "holds " + std::to_string(rays.size()) + " rays, not the " +
                                  std::to_string(pixels) + " of a " +
                                  std::to_string(job.sample_image_width) + "x" +
                                  std::to_string(job.sample_image_height) + " image");
  return image_sample(rays, job.sample_image_width, job.sample_image_height);
}

nlohmann::json trace_parameters(const TraceJob& job) {
  nlohmann::json parameters = job.params.to_json();
  parameters["threads"] = job.threads;
  parameters["eager"] = job.eager;
  parameters["occluded"] = job.occluded;
  parameters["repeat"] = job.repeat;
  parameters["packets"] = job.packets;
  return parameters;
}

// Builds, samples and (with --eager) builds everything; returns the seconds spent.
double prepare(Accelerator& accel, const Scene& scene, const std::vector<Ray>& rays,
               const TraceJob& job) {
  double seconds = seconds_of([&] { accel.build(scene); });
  // With no rays there is nothing to sample, and a count of zero rays would mean nothing.
  if (!rays.empty()) {
    const std::vector<Ray> subset = sample_of(rays, job);
    seconds += seconds_of([&] {
      if (job.sample_camera)
        sample_image_rays(accel, scene,
                          make_lighting(accel.bounds(), *job.sample_camera, std::nullopt), subset,
                          rays.size(), job.threads);
      else
        sample_run(accel, subset, rays.size(), job.threads);
    });
  }
  if (job.eager) seconds += seconds_of([&] { accel.build_all(); });
  return seconds;
}

// The rays in the order packets take them, and where each packet starts in that order (one
// more entry: the end). Consecutive rays (`rays` empty: the file's order), or an image's
// k x k tiles, row by row of tiles.
struct PacketOrder {
  std::vector<uint32_t> rays;
  std::vector<size_t> starts;
};
PacketOrder packet_order(size_t count, const TraceJob& job) {
  PacketOrder order;
  const auto side = size_t(std::lround(std::sqrt(double(job.packets))));
  if (job.sample_image_width == 0) {
    for (size_t i = 0; i < count; i += size_t(job.packets)) order.starts.push_back(i);
  } else {
    if (side * side != size_t(job.packets))
      throw UsageError("trace: --packets " + std::to_string(job.packets) +
                       " with --sample-image must be a square (4, 9, ..., 64): the image's "
                       "tiles are k x k pixels");
    const auto w = size_t(job.sample_image_width), h = size_t(job.sample_image_height);
    for (size_t y0 = 0; y0 < h; y0 += side)
      for (size_t x0 = 0; x0 < w; x0 += side) {
        order.starts.push_back(order.rays.size());
        for (size_t y = y0; y < std::min(y0 + side, h); ++y)
          for (size_t x = x0; x < std::min(x0 + side, w); ++x)
            order.rays.push_back(uint32_t(y * w + x));
      }
  }
  order.starts.push_back(count);
  return order;
}

// One pass over the rays in packets (job.packets > 0). Consecutive rays go to the structure
// where they lie; an image's tiles are gathered into a packet and their hits scattered back
// (copying every ray and hit took 6.5% of a packet trace of the cathedral's shadow rays).
TraceCounters trace_packets(const Accelerator& accel, const std::vector<Ray>& rays,
                            const PacketOrder& order, const TraceJob& job, std::vector<Hit>& hits) {
  const size_t packets = order.starts.size() - 1;
  const size_t chunk = std::max<size_t>(1, kRayChunk / size_t(job.packets));
  const bool consecutive = order.rays.empty();
  return trace_chunks(
      accel, packets, chunk, job.threads, [&](ThreadContext& context, size_t begin, size_t end) {
        Ray gathered[Accelerator::kMaxPacketRays];
        uint64_t keys[Accelerator::kMaxPacketRays];
        Hit answers[Accelerator::kMaxPacketRays];
        for (size_t p = begin; p < end; ++p) {
          const size_t first = order.starts[p], n = order.starts[p + 1] - first;
          if (consecutive) {
            for (size_t k = 0; k < n; ++k) keys[k] = first + k;
            accel.trace_packet({&rays[first], n}, {keys, n}, {&hits[first], n}, job.occluded,
                               context);
            continue;
          }
          for (size_t k = 0; k < n; ++k)
            keys[k] = order.rays[first + k], gathered[k] = rays[keys[k]];
          accel.trace_packet({gathered, n}, {keys, n}, {answers, n}, job.occluded, context);
          for (size_t k = 0; k < n; ++k) hits[keys[k]] = answers[k];
        }
      });
}

// Re-traces ray job.walk_ray with the recorder, on the structure the run built.
void write_walk(const Accelerator& accel, const std::vector<Ray>& rays, const TraceJob& job) {
  if (size_t(job.walk_ray) >= rays.size())
    fail_input(job.rays_path, "has " + std::to_string(rays.size()) + " rays, so --walk " +
                                  std::to_string(job.walk_ray) + " is out of range");
  const std::unique_ptr<ThreadContext> context = accel.make_context();
  const std::optional<Walk> walk = accel.record_walk(rays[size_t(job.walk_ray)], *context);
  if (!walk) throw UsageError("--walk: structure '" + accel.name() + "' has no cells to walk");
  write_json(job.walk_path, to_json(*walk));
}

}  // namespace

nlohmann::json run_trace(const TraceJob& job) {
  check_thread_count(job.threads);
  std::unique_ptr<Accelerator> accel = make_accelerator(job.accel, job.params);
  if (job.packets > 0 && !accel->traces_packets())
    throw UsageError("trace: --packets: structure '" + job.accel +
                     "' has no packet traversal (it would trace the rays one by one)");
  const Scene scene = load_scene(job.scene);
  const std::vector<Ray> rays = read_rays(job.rays_path);

  RunFigures figures;
  figures.rays = rays.size();
  figures.build_seconds = prepare(*accel, scene, rays, job);
  accel->check_ray_keys(rays.size(), "ray");
  std::vector<Hit> hits(rays.size());
  TraceCounters counters;
  const PacketOrder order = job.packets > 0 ? packet_order(rays.size(), job) : PacketOrder{};
  const auto pass = [&] {
    return seconds_of([&] {
      if (job.packets > 0) {
        counters = trace_packets(*accel, rays, order, job, hits);
        return;
      }
      counters = trace_chunks(*accel, rays.size(), kRayChunk, job.threads,
                              [&](ThreadContext& context, size_t begin, size_t end) {
                                for (size_t i = begin; i < end; ++i) {
                                  context.ray_index = i;  // the oracle's key ("zero")
                                  hits[i] = job.occluded ? accel->any_hit(rays[i], context)
                                                         : accel->intersect(rays[i], context);
                                }
                              });
    });
  };
  figures.trace_seconds = pass();
  figures.counters = counters;  // the statistics describe the first pass
  std::vector<double> warm;
  for (int k = 1; k < job.repeat; ++k) warm.push_back(pass());
  write_hits(job.out_path, hits);
  if (job.walk_ray >= 0) write_walk(*accel, rays, job);

  nlohmann::json stats = run_stats(scene, *accel, trace_parameters(job), figures);
  stats["warm_trace_seconds"] = nullptr;
  stats["warm_rays_per_second"] = nullptr;
  if (!warm.empty()) {
    const double warm_seconds = median(warm);
    stats["warm_trace_seconds"] = warm_seconds;
    stats["warm_rays_per_second"] = warm_seconds > 0.0 ? double(rays.size()) / warm_seconds : 0.0;
  }
  if (!job.stats_path.empty()) write_json(job.stats_path, stats);
  return stats;
}

}  // namespace gs
