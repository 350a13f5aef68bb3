#include "core/trace/trace_job.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <thread>

#include "core/base/error.h"
#include "core/geometry/ray_io.h"
#include "core/render/render.h"
#include "core/accel/zero_overhead.h"

namespace gs {

namespace {

// Big enough that taking a chunk costs nothing next to tracing it, small enough that
// threads finish together when some rays are much slower than others.
constexpr size_t kRayChunk = 1024;

nlohmann::json optional_json(const std::optional<uint64_t>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

// A regular subset of the run's rays (DESIGN.md §1 "Cost function"): indices 0, k, 2k, ...
std::vector<Ray> sample_subset(const std::vector<Ray>& rays, int every) {
  std::vector<Ray> subset;
  subset.reserve(rays.size() / size_t(every) + 1);
  for (size_t i = 0; i < rays.size(); i += size_t(every)) subset.push_back(rays[i]);
  return subset;
}

// The sampling pass's rays: the image's sample pixels, or every sample_every-th ray.
std::vector<Ray> sample_of(const std::vector<Ray>& rays, const TraceJob& job) {
  if (job.sample_image_width == 0) return sample_subset(rays, job.params.sample_every);
  const size_t pixels = size_t(job.sample_image_width) * size_t(job.sample_image_height);
  if (rays.size() != pixels)
    fail_input(job.rays_path, "holds " + std::to_string(rays.size()) + " rays, not the " +
                                  std::to_string(pixels) + " of a " +
                                  std::to_string(job.sample_image_width) + "x" +
                                  std::to_string(job.sample_image_height) + " image");
  std::vector<Ray> subset;
  for (const size_t pixel : image_sample_pixels(job.sample_image_width, job.sample_image_height))
    subset.push_back(rays[pixel]);
  return subset;
}

nlohmann::json trace_parameters(const TraceJob& job) {
  nlohmann::json parameters = job.params.to_json();
  parameters["threads"] = job.threads;
  parameters["eager"] = job.eager;
  parameters["occluded"] = job.occluded;
  parameters["repeat"] = job.repeat;
  return parameters;
}

// Builds, samples and (with --eager) builds everything; returns the seconds spent.
double prepare(Accelerator& accel, const Scene& scene, const std::vector<Ray>& rays,
               const TraceJob& job) {
  double seconds = seconds_of([&] { accel.build(scene); });
  // With no rays there is nothing to sample, and a count of zero rays would mean nothing.
  if (!rays.empty()) {
    const std::vector<Ray> subset = sample_of(rays, job);
    seconds += seconds_of([&] { accel.sample(subset, double(rays.size())); });
  }
  if (job.eager) seconds += seconds_of([&] { accel.build_all(); });
  return seconds;
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

int default_thread_count() {
  return int(std::clamp(std::thread::hardware_concurrency(), 1u, unsigned(kMaxThreads)));
}

void check_thread_count(int threads) {
  if (threads < 1 || threads > kMaxThreads)
    throw UsageError("--threads " + std::to_string(threads) + ": must be between 1 and " +
                     std::to_string(kMaxThreads));
}

TraceCounters parallel_chunks(const Accelerator& accel, size_t count, size_t chunk, int threads,
                              const ChunkBody& body) {
  const size_t chunks = (count + chunk - 1) / chunk;
  const size_t workers = std::min(size_t(std::max(threads, 1)), chunks);
  std::vector<std::unique_ptr<ThreadContext>> contexts;
  for (size_t w = 0; w < workers; ++w) contexts.push_back(accel.make_context());
  std::vector<std::exception_ptr> errors(workers);
  std::atomic<size_t> next{0};
  auto work = [&](size_t worker) {
    try {
      for (size_t c; (c = next.fetch_add(1, std::memory_order_relaxed)) < chunks;)
        body(*contexts[worker], c * chunk, std::min(count, (c + 1) * chunk));
    } catch (...) {
      errors[worker] = std::current_exception();
      next.store(chunks);  // the others stop after their current chunk
    }
  };
  {
    // jthreads join on destruction, also when starting one of them throws.
    std::vector<std::jthread> pool;
    for (size_t w = 1; w < workers; ++w) pool.emplace_back(work, w);
    if (workers > 0) work(0);
  }
  TraceCounters merged;
  for (size_t w = 0; w < workers; ++w) {
    if (errors[w]) std::rethrow_exception(errors[w]);
    merged.add(contexts[w]->counters);
  }
  return merged;
}

nlohmann::json run_trace(const TraceJob& job) {
  check_thread_count(job.threads);
  std::unique_ptr<Accelerator> accel = make_accelerator(job.accel, job.params);
  const Scene scene = load_scene(job.scene);
  const std::vector<Ray> rays = read_rays(job.rays_path);

  RunFigures figures;
  figures.rays = rays.size();
  figures.build_seconds = prepare(*accel, scene, rays, job);
  if (const auto* zero = dynamic_cast<const ZeroOverhead*>(accel.get()))
    zero->check_ray_count(rays.size());
  std::vector<Hit> hits(rays.size());
  TraceCounters counters;
  const auto pass = [&] {
    return seconds_of([&] {
      counters = parallel_chunks(*accel, rays.size(), kRayChunk, job.threads,
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

nlohmann::json run_stats(const Scene& scene, const Accelerator& accel, nlohmann::json parameters,
                         const RunFigures& figures) {
  const StructureStats structure = accel.stats();
  const TraceCounters& counters = figures.counters;
  nlohmann::json stats;
  stats["accel"] = accel.name();
  stats["parameters"] = std::move(parameters);
  stats["scene"] = scene.name;
  stats["triangles"] = scene.triangle_count();
  stats["degenerate_triangles"] = scene.degenerate_count();
  stats["rays"] = figures.rays;
  stats["build_seconds"] = figures.build_seconds + counters.lazy_build_seconds;
  stats["lazy_build_seconds"] = counters.lazy_build_seconds;
  stats["trace_seconds"] = figures.trace_seconds;
  stats["rays_per_second"] =
      figures.trace_seconds > 0.0 ? double(figures.rays) / figures.trace_seconds : 0.0;
  stats["nodes"] = optional_json(structure.nodes);
  stats["voxels_subdivided"] = optional_json(structure.voxels_subdivided);
  stats["leaves"] = optional_json(structure.leaves);
  stats["traversal_states"] = optional_json(structure.traversal_states);
  // A counter the structure cannot measure (embree) is null, never a made-up 0.
  const auto counted = [](bool measured, uint64_t value) {
    return measured ? nlohmann::json(value) : nlohmann::json(nullptr);
  };
  stats["intersection_tests"] = counted(structure.counts_tests, counters.intersection_tests);
  stats["mailbox_rejections"] = counted(structure.counts_tests, counters.mailbox_rejections);
  stats["traversal_steps"] = counted(structure.counts_steps, counters.traversal_steps);
  stats["memory_bytes"] = structure.memory_bytes;
  stats["voxels_over_budget"] = structure.voxels_over_budget;
  return stats;
}

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const size_t mid = values.size() / 2;
  return values.size() % 2 ? values[mid] : 0.5 * (values[mid - 1] + values[mid]);
}

void write_json(const std::string& path, const nlohmann::json& json) {
  // Paths in the record need not be UTF-8; replace what is not instead of failing.
  const std::string text =
      json.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
  write_file(path, text);
}

}  // namespace gs
