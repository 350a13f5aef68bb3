#include "core/accel/accelerator.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <nlohmann/json.hpp>

#include "core/accel/brute.h"
#include "core/accel/bvh.h"
#include "core/accel/grid1d/grid1d.h"
#include "core/accel/grid3d.h"
#include "core/accel/octree.h"
#include "core/accel/uniform_grid.h"
#include "core/accel/zero_overhead.h"
#include "core/base/error.h"
#include "core/base/parallel.h"
#if GRIDSCOPE_HAVE_EMBREE
#include "core/accel/embree_accel.h"
#endif

namespace gs {
namespace {

// Worded as the CLI words a value out of range: "--flag VALUE: expected RANGE".
[[noreturn]] void out_of_range(const std::string& flag, const std::string& value,
                               const std::string& expected) {
  throw UsageError(flag + " " + value + ": expected " + expected);
}

void check_int(const std::string& flag, long long value, long long lo, long long hi,
               const std::string& context = "") {
  if (value < lo || value > hi)
    out_of_range(flag, std::to_string(value),
                 "an integer in " + std::to_string(lo) + ".." + std::to_string(hi) + context);
}

void check_non_negative(const std::string& flag, double value) {
  if (std::isfinite(value) && value >= 0.0) return;
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  out_of_range(flag, text, "a finite number >= 0");
}

// The deepest tree structure `name` builds: the octree's finest cells must stay exact
// integers, grid3d's walk recurses once per level.
int depth_cap(const std::string& name) {
  if (name == "octree") return Octree::kDepthCap;
  if (name == "grid3d") return NestedGrid::kMaxDepthCap;
  return kMaxDepth;
}

}  // namespace

void check_params(const std::string& name, const AccelParams& params) {
  check_non_negative("--intcost", params.intcost);
  check_non_negative("--repcost", params.repcost);
  check_non_negative("--travcost", params.travcost);
  check_non_negative("--vertcost", params.vertcost);
  check_non_negative("--subcost", params.subcost);
  check_non_negative("--density", params.density);
  check_int("--max-granularity", params.max_granularity, 1, kMaxGranularity);
  if (params.max_depth != 0)  // 0: the structure's default
    check_int("--max-depth", params.max_depth, 1, depth_cap(name), " for " + name);
  check_int("--leaf-size", params.leaf_size, 0, kMaxLeafSize);
  check_int("--sample-every", params.sample_every, 1, std::numeric_limits<int>::max());
  check_int("--build-threads", params.build_threads, 0, kMaxThreads);
  if (params.memory_budget > kMaxMemoryBudget)
    out_of_range("--memory-budget", std::to_string(params.memory_budget),
                 "at most " + std::to_string(kMaxMemoryBudget) + " bytes (1 TiB)");
}

nlohmann::json AccelParams::to_json() const {
  return {{"intcost", intcost},
          {"repcost", repcost},
          {"travcost", travcost},
          {"vertcost", vertcost},
          {"subcost", subcost},
          {"max_granularity", max_granularity},
          {"axis", axis == AxisRule::alternate ? "alternate" : "cost"},
          {"max_depth", max_depth},
          {"leaf_size", leaf_size},
          {"density", density},
          {"memory_budget", memory_budget},
          {"sample_every", sample_every},
          {"build_threads", build_threads},
          {"oracle", oracle_path.empty() ? nlohmann::json(nullptr) : nlohmann::json(oracle_path)}};
}

void TraceCounters::add(const TraceCounters& other) {
  intersection_tests += other.intersection_tests;
  mailbox_rejections += other.mailbox_rejections;
  traversal_steps += other.traversal_steps;
  voxels_built += other.voxels_built;
  lazy_build_seconds += other.lazy_build_seconds;
}

void Accelerator::sample(std::span<const Ray>, double) {}

std::vector<std::string> accelerator_names() {
  std::vector<std::string> names = {"brute", "grid1d", "uniform", "octree", "grid3d", "bvh"};
#if GRIDSCOPE_HAVE_EMBREE
  names.push_back("embree");
#endif
  names.push_back("zero");
  return names;
}

std::unique_ptr<Accelerator> make_accelerator(const std::string& name, const AccelParams& params) {
  const std::vector<std::string> names = accelerator_names();
  if (std::find(names.begin(), names.end(), name) != names.end()) check_params(name, params);
  if (name == "brute") return std::make_unique<BruteForce>();
  if (name == "grid1d") return std::make_unique<Grid1D>(params);
  if (name == "uniform") return std::make_unique<UniformGrid>(params);
  if (name == "octree") return std::make_unique<Octree>(params);
  if (name == "grid3d") return std::make_unique<NestedGrid>(params);
  if (name == "bvh") return std::make_unique<Bvh>(params);
#if GRIDSCOPE_HAVE_EMBREE
  if (name == "embree") return std::make_unique<EmbreeAccel>(params);
#else
  if (name == "embree") throw UsageError("gridscope was built without Embree");
#endif
  if (name == "zero") return std::make_unique<ZeroOverhead>(params);
  std::string known;
  for (const auto& n : accelerator_names()) known += (known.empty() ? "" : ", ") + n;
  throw UsageError("unknown structure '" + name + "' (known: " + known + ")");
}

}  // namespace gs
