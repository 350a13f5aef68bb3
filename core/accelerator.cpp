#include "core/accelerator.h"

#include <nlohmann/json.hpp>

#include "core/brute.h"
#include "core/bvh.h"
#include "core/error.h"
#include "core/grid1d.h"
#include "core/grid3d.h"
#include "core/octree.h"
#include "core/uniform_grid.h"
#include "core/zero_overhead.h"
#if GRIDSCOPE_HAVE_EMBREE
#include "core/embree_accel.h"
#endif

namespace gs {

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
