// The `trace` job as a library function (the CLI only parses), and the pieces it shares
// with the renderer: the threaded chunk loop, the stats record, timing.
#pragma once
#include <chrono>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/accel/accelerator.h"
#include "core/scene/scene.h"

namespace gs {

constexpr int kMaxThreads = 1024;
// std::thread::hardware_concurrency(), or 1 where it is unknown.
int default_thread_count();
// Throws UsageError unless 1 <= threads <= kMaxThreads.
void check_thread_count(int threads);

struct TraceJob {
  std::string scene;       // a path or builtin:NAME
  std::string rays_path;   // ray file to trace
  std::string out_path;    // hit file to write
  std::string stats_path;  // stats JSON to write; empty for none
  std::string accel = "grid1d";
  AccelParams params;
  int threads = default_thread_count();
  bool eager = false;     // build everything before tracing (Accelerator::build_all)
  bool occluded = false;  // any-hit answers instead of nearest hits
  // Passes over the rays: the first builds lazily; the others (warm) are timed apart, their
  // median reported as warm_trace_seconds / warm_rays_per_second (null for one pass).
  int repeat = 1;
  // With a size: the ray file holds a width x height image's primary rays (`gridscope rays`)
  // and the sampling pass takes the image's pixels (one per 8x8 block) as `render`, `shot`
  // and the viewer do, so the structure is theirs.
  int sample_image_width = 0, sample_image_height = 0;
  // With walk_ray >= 0: that ray's walk, recorded after the run, is written to walk_path.
  int64_t walk_ray = -1;
  std::string walk_path;
};

// Makes the accelerator (so a usage error is reported before any file is read), loads the
// scene and rays, builds, runs the sampling pass on every params.sample_every-th ray,
// traces with job.threads threads, writes the hit file and, if asked, the stats file.
// Returns the stats. Throws UsageError or InputError.
nlohmann::json run_trace(const TraceJob& job);

// body(context, begin, end) handles items [begin, end) with the context of the thread it
// runs on. Chunks of `chunk` items of [0, count) are handed out dynamically to `threads`
// threads (the caller's among them); each thread has its own context. Returns the merged
// counters. An exception in any thread stops the loop and is rethrown here.
using ChunkBody = std::function<void(ThreadContext&, size_t, size_t)>;
TraceCounters parallel_chunks(const Accelerator& accel, size_t count, size_t chunk, int threads,
                              const ChunkBody& body);

// What a run measured besides the structure's own figures.
struct RunFigures {
  uint64_t rays = 0;
  double build_seconds = 0.0;  // build + sampling pass + eager build; lazy work comes from counters
  double trace_seconds = 0.0;
  TraceCounters counters;
};

// The stats record (DESIGN.md §3 `--stats`); `parameters` is echoed as given.
nlohmann::json run_stats(const Scene& scene, const Accelerator& accel, nlohmann::json parameters,
                         const RunFigures& figures);
// Writes JSON with a final newline. Throws InputError naming the path when it cannot.
void write_json(const std::string& path, const nlohmann::json& json);

// The median of timed repetitions (the mean of the middle two for an even count); 0 for none.
double median(std::vector<double> values);

template <class Work>
double seconds_of(Work&& work) {
  const auto start = std::chrono::steady_clock::now();
  work();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace gs
