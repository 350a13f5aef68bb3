#include "core/accel/registry.h"

#include <algorithm>

#include "core/accel/brute.h"
#include "core/accel/bvh.h"
#include "core/accel/grid1d/grid1d.h"
#include "core/accel/grid3d.h"
#include "core/accel/octree.h"
#include "core/accel/uniform_grid.h"
#include "core/accel/zero_overhead.h"
#include "core/base/error.h"
#if GRIDSCOPE_HAVE_EMBREE
#include "core/accel/embree_accel.h"
#endif

namespace gs {
namespace {

template <class Kind>
std::unique_ptr<Accelerator> make(const AccelParams& params) {
  return std::make_unique<Kind>(params);
}

std::unique_ptr<Accelerator> make_brute(const AccelParams&) {
  return std::make_unique<BruteForce>();
}

ParamUse uses(Param param) { return {param, ""}; }
ParamUse uses(Param param, int default_value) { return {param, std::to_string(default_value)}; }

std::vector<Structure> make_structures() {
  // Tableau's categorical palette, one hue per structure, the paper's four first.
  return {
      {.name = "uniform",
       .description = "uniform grid, about cbrt(N) cells per side, 3D DDA (Fujimoto et al. "
                      "1986); the paper's comparison",
       .group = StructureGroup::paper,
       .make = make<UniformGrid>,
       .params = {{Param::density, "cbrt(N) cells per side, the paper's"},
                  uses(Param::memory_budget)},
       .sweep = {{Param::density, {0.125, 0.25, 0.5, 1, 2, 4, 8}}},
       .colour = {31, 119, 180}},  // blue
      {.name = "octree",
       .description = "Glassner's octree (1984), built up front; the paper's comparison",
       .group = StructureGroup::paper,
       .make = make<Octree>,
       .depth_cap = Octree::kDepthCap,
       .params = {uses(Param::max_depth, Octree::kDefaultMaxDepth),
                  uses(Param::leaf_size, Octree::kDefaultLeafSize), uses(Param::memory_budget)},
       .sweep = {{Param::max_depth, {4, 5, 6, 7, 8, 10}}, {Param::leaf_size, {1, 2, 4, 8, 16}}},
       .colour = {255, 127, 14}},  // orange
      {.name = "grid3d",
       .description = "adaptive nested 3D grids (Jevans & Wyvill 1989), built lazily; the "
                      "paper's comparison",
       .group = StructureGroup::paper,
       .make = make<NestedGrid>,
       .depth_cap = NestedGrid::kMaxDepthCap,
       .params = {uses(Param::max_depth, NestedGrid::kDefaultMaxDepth),
                  uses(Param::leaf_size, NestedGrid::kDefaultLeafSize), uses(Param::memory_budget)},
       .sweep = {{Param::max_depth, {1, 2, 3, 4}}, {Param::leaf_size, {4, 8, 16, 32, 64}}},
       .colour = {44, 160, 44}},  // green
      {.name = "grid1d",
       .description = "the paper's hierarchical adaptive 1D grid (Jevans 1990), built lazily "
                      "by the §6 cost function",
       .group = StructureGroup::paper,
       .make = make<Grid1D>,
       .params = {uses(Param::intcost), uses(Param::repcost), uses(Param::travcost),
                  uses(Param::vertcost), uses(Param::subcost), uses(Param::max_granularity),
                  uses(Param::max_root_granularity), uses(Param::axis),
                  uses(Param::max_depth, Grid1D::kDefaultMaxDepth), uses(Param::memory_budget),
                  uses(Param::sample_every)},
       .sweep = {{Param::max_granularity, {2, 4, 8, 20, 32, 64}},
                 {Param::max_root_granularity, {4, 20}},
                 {Param::intcost, {0.5, 2}},
                 {Param::repcost, {0.5, 2.5}},
                 {Param::travcost, {12, 50}},
                 {Param::vertcost, {15, 60}},
                 {Param::subcost, {25, 100}}},
       .colour = {214, 39, 40},  // red
       .traces_packets = true},
      {.name = "bvh",
       .description = "binned SAH bounding volume hierarchy, built up front",
       .group = StructureGroup::modern,
       .make = make<Bvh>,
       // Its traversal stack would allow Bvh::kMaxDepthCap; the common cap is lower.
       .depth_cap = std::min(kMaxDepth, Bvh::kMaxDepthCap),
       .params = {uses(Param::max_depth, Bvh::kDefaultMaxDepth),
                  uses(Param::leaf_size, Bvh::kDefaultLeafSize), uses(Param::memory_budget)},
       .sweep = {{Param::leaf_size, {1, 2, 4, 8, 16}}},
       .colour = {148, 103, 189}},  // purple
      {.name = "embree",
       .description = "Intel Embree 3's BVH in robust mode, when CMake found Embree 3",
       .group = StructureGroup::modern,
#if GRIDSCOPE_HAVE_EMBREE
       .make = make<EmbreeAccel>,
#else
       .make = nullptr,
       .missing = "gridscope was built without Embree",
#endif
       .params = {uses(Param::build_threads)},
       .colour = {140, 86, 75},  // brown
       .traces_packets = true},
      {.name = "brute",
       .description = "every ray against every triangle: the reference answers",
       .group = StructureGroup::reference,
       .make = make_brute,
       .colour = {23, 190, 207},  // cyan
       .takes_any_flag = true},
      {.name = "zero",
       .description = "the paper's zero-overhead method (§7): each ray tested against the one "
                      "triangle --oracle recorded for it; the time floor",
       .group = StructureGroup::reference,
       .make = make<ZeroOverhead>,
       .params = {uses(Param::oracle)},
       .colour = {227, 119, 194},  // pink
       .needs_oracle = true},
  };
}

}  // namespace

const ParamUse* Structure::use(Param param) const {
  const auto found = std::ranges::find(params, param, &ParamUse::param);
  return found == params.end() ? nullptr : &*found;
}

const std::vector<Structure>& structures() {
  static const std::vector<Structure> list = make_structures();
  return list;
}

const Structure* find_structure(std::string_view name) {
  const auto found = std::ranges::find(structures(), name, &Structure::name);
  return found == structures().end() ? nullptr : &*found;
}

const Structure& structure_named(std::string_view name) {
  const Structure* structure = find_structure(name);
  if (!structure) {
    std::string known;
    for (const Structure& s : structures())
      if (s.available()) known += (known.empty() ? "" : ", ") + s.name;
    throw UsageError("unknown structure '" + std::string(name) + "' (known: " + known + ")");
  }
  if (!structure->available()) throw UsageError(structure->missing);
  return *structure;
}

std::vector<std::string_view> structure_names(StructureGroup group) {
  std::vector<std::string_view> names;
  for (const Structure& structure : structures())
    if (structure.group == group) names.push_back(structure.name);
  return names;
}

std::string_view group_name(StructureGroup group) {
  switch (group) {
    case StructureGroup::paper:
      return "paper";
    case StructureGroup::modern:
      return "modern";
    case StructureGroup::reference:
      break;
  }
  return "reference";
}

}  // namespace gs
