#include "core/accelerator.h"

#include <nlohmann/json.hpp>

#include "core/brute.h"
#include "core/error.h"
#include "core/grid1d.h"

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
          {"sample_every", sample_every}};
}

void TraceCounters::add(const TraceCounters& other) {
  intersection_tests += other.intersection_tests;
  mailbox_rejections += other.mailbox_rejections;
  traversal_steps += other.traversal_steps;
  voxels_built += other.voxels_built;
  lazy_build_seconds += other.lazy_build_seconds;
}

void Accelerator::sample(std::span<const Ray>, double) {}

std::vector<std::string> accelerator_names() { return {"brute", "grid1d"}; }

std::unique_ptr<Accelerator> make_accelerator(const std::string& name, const AccelParams& params) {
  if (name == "brute") return std::make_unique<BruteForce>();
  if (name == "grid1d") return std::make_unique<Grid1D>(params);
  std::string known;
  for (const auto& n : accelerator_names()) known += (known.empty() ? "" : ", ") + n;
  throw UsageError("unknown structure '" + name + "' (known: " + known + ")");
}

}  // namespace gs
