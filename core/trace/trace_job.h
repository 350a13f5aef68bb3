// The `trace` job as a library function (the CLI only parses): a ray file through a
// structure into a hit file and a stats record.
#pragma once
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/accel/accelerator.h"
#include "core/base/parallel.h"
#include "core/scene/camera.h"
#include "core/scene/scene.h"

namespace gs {

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
  // With the image's camera too, the pass also samples the shadow rays of the sample pixels'
  // hits toward the light render places for that camera, as render does.
  std::optional<Camera> sample_camera;
  // With packets > 0: rays go to Accelerator::trace_packet this many at a time, consecutive
  // rays of the file, or with the image's size tiles of packets = k * k pixels.
  int packets = 0;
  // With walk_ray >= 0: that ray's walk, recorded after the run, is written to walk_path.
  int64_t walk_ray = -1;
  std::string walk_path;
};

// Makes the accelerator (so a usage error is reported before any file is read), loads the
// scene and rays, builds, runs the sampling pass on every params.sample_every-th ray,
// traces with job.threads threads, writes the hit file and, if asked, the stats file.
// Returns the stats. Throws UsageError or InputError.
nlohmann::json run_trace(const TraceJob& job);

}  // namespace gs
