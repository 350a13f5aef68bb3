// The `bench` command's outputs: runs bench/bench.h's protocol and writes
// results.json, report.md and the PNG plots into one directory.
#pragma once
#include <string>

#include "bench/bench.h"

namespace gs::app {

struct BenchJob {
  BenchOptions options;
  std::string out_dir = "bench-out";
  // With a path: no measuring; report.md and the plots are made again from that results.json.
  std::string from_path;
  // Every step's line instead of the one progress line (bench/progress.h).
  bool verbose = false;
};

// Throws UsageError for bad options before measuring, InputError naming the directory or file
// that cannot be written.
void run_bench_job(const BenchJob& job);

}  // namespace gs::app
