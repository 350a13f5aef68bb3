// The structure-against-brute comparison the differential and ray-file fuzz targets share.
#pragma once
#include <vector>

#include "core/accel/accelerator.h"
#include "core/geometry/ray.h"
#include "core/scene/scene.h"
#include "tests/fuzz/fuzz_entries.h"

namespace gs::fuzz {

// How the structures are built and traced (the command line's choices).
struct StructureSettings {
  AccelParams params;
  int threads = 1;             // tracing threads (parallel_chunks)
  bool sample = true;          // run the §6.5 sampling pass on every sample_every-th ray
  bool any_hit_first = false;  // a lazy structure is first built by any-hit walks
  size_t packet = 0;           // rays per packet for structures that walk packets; 0: single
};

// Builds every exact structure (all but brute, embree and zero), lazily and eagerly, and
// checks its nearest and any-hit answers (in packets where settings.packet asks and the
// structure walks packets) for `rays` against brute force's (README
// "Exactness"); adds the answers compared to outcome.checks and each disagreement to
// outcome.problems.
void check_against_brute(const Scene& scene, const std::vector<Ray>& rays,
                         const StructureSettings& settings, Outcome& outcome);

}  // namespace gs::fuzz
