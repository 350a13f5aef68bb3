// `gridscope bench`: the paper's experiment (section 7, Figure 12) redone for every
// structure, plus the modern ones, as run time against error.
//
// Protocol: per scene, structure, thread count (1 and all cores) and workload
// ("primary_shadow": the paper's one primary ray per pixel plus a shadow ray; "diffuse": one
// more diffuse bounce with its own shadow ray), the structure is built, the image's sampling
// pass run, a first render (with the lazy build) timed apart, then warm renders repeated and
// their median taken. Each render's answers and image are compared with a reference
// structure's (brute where affordable, else bvh, which the suites check equal to brute bit
// for bit). The zero-overhead oracle replays the reference's answers (keyed by pixel, sample,
// bounce and kind) to give the floor `relative_to_zero` divides by. Each structure's own
// parameters are swept on a smaller image and its best setting measured again in full; the
// progressive renderer's error is followed over wall time; grid1d is run with constants
// calibrated on the machine. Records are described in README "Benchmark".
#pragma once
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bench/progress.h"
#include "core/render/render.h"
#include "core/trace/trace_job.h"

namespace gs {

struct BenchOptions {
  std::vector<std::string> scenes;       // suite names, builtin:NAME or paths; empty: the suite
  std::vector<std::string> accels;       // empty: every structure this build has (but brute, zero)
  bool quick = false;                    // smaller images, fewer repetitions, built-in scenes only
  uint64_t seed = 1;                     // calibration's random scenes
  int threads = default_thread_count();  // the "all cores" thread count
  std::string assets_dir;                // the scene files' folder; empty: find_shared_dir()
  // When set, each scene's reference image (primary and shadow rays) is written there as
  // scene-LABEL.png, so that a reader sees what was measured.
  std::string image_dir;
  // Called after each step: every measurement, reference, calibration and convergence curve
  // (a skipped scene's planned steps are reported as one).
  std::function<void(const BenchStep&)> progress;
};

// The structures the bench measures (the paper's and the modern ones of the registry), in
// report order, this build's or not.
std::vector<std::string> bench_structures();

// Throws UsageError for an unknown structure or scene name before measuring anything.
void check_bench_options(const BenchOptions& options);

// Runs the benchmark and returns its records (a JSON array). Scenes whose shared meshes are
// missing are skipped with a "skipped" record naming why.
nlohmann::json run_bench(const BenchOptions& options);

// A structure's first render in the time to the answer: its seconds and its lazy build's,
// each with the lazy build the probe of its time (a pass over every 32nd band of rows, made
// first so that a structure that breaks down is not rendered in full) set off before it. The
// probe's tracing is no part of the answer; what it built is, and the first render no longer
// pays for it (the upper levels of a grid1d, which every row's rays cross, are cut there).
struct FirstPassFigures {
  double seconds = 0.0;
  double lazy_build_seconds = 0.0;
};
FirstPassFigures first_pass_figures(const RenderOutcome& first, double probe_lazy_build_seconds);

// The 8-bit RGB root-mean-square difference of two equal-sized RGBA images.
double image_rmse(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b);

}  // namespace gs
