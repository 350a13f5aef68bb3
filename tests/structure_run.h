// One structure built the way the command line builds it, and the threads that trace it:
// what the structure suites (tests/cases.h) and the differential fuzz target compare with
// brute force. Header-only, and free of GoogleTest, because the fuzz targets link neither.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "core/accel/accelerator.h"
#include "core/geometry/ray.h"
#include "core/scene/scene.h"
#include "core/trace/sampling.h"

namespace gs::test {

struct StructureRun {
  std::string accel;     // make_accelerator's name
  AccelParams params{};  // params.sample_every spaces the sampling pass's rays
  bool sample = false;   // run the sampling pass (§6.5) over the traced rays first
  bool eager = false;    // build everything before tracing (--eager)
  int threads = 1;       // tracing threads
  size_t packet = 0;     // rays per packet (Accelerator::trace_packet); 0: one at a time
};

// make_accelerator and build, then as `trace` does: the sampling pass over every
// params.sample_every-th of `rays` (none when there are no rays: a run of zero rays means
// nothing to the cost model), then with `eager` the whole structure.
inline std::unique_ptr<Accelerator> build_structure(const StructureRun& run, const Scene& scene,
                                                    const std::vector<Ray>& rays = {}) {
  std::unique_ptr<Accelerator> accel = make_accelerator(run.accel, run.params);
  accel->build(scene);
  if (run.sample && !rays.empty())
    sample_run(*accel, sample_subset(rays, run.params.sample_every), rays.size(), run.threads);
  if (run.eager) accel->build_all();
  return accel;
}

}  // namespace gs::test
