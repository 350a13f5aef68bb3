// Resource limits and degenerate input: scene file size and counts, structure
// parameter ranges, the memory budget of every structure, and builds that end with bounded
// depth on input that defeats the cost models. Every answer is compared with brute force;
// the limits are tested through their check functions with small injected values, never
// with multi-gigabyte files.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>

#include "core/accel/bvh.h"
#include "core/accel/grid1d/grid1d.h"
#include "core/accel/grid3d.h"
#include "core/accel/octree.h"
#include "core/accel/uniform_grid.h"
#include "core/base/error.h"
#include "core/base/stable_array.h"
#include "tests/cases.h"

namespace gs {
namespace {

// ---------------------------------------------------------------------------------------
// Lazily grown storage

TEST(StableArray, ElementsStayWhereTheyAreAndAFullReservationSaysSo) {
  StableArray<uint64_t> array(1000 * sizeof(uint64_t));
  ASSERT_EQ(array.append(10), 0u);
  uint64_t* first = &array[0];
  for (uint64_t i = 0; i < 10; ++i) array[i] = i * i;
  EXPECT_EQ(array.append(990), 10u);
  EXPECT_EQ(&array[0], first);
  EXPECT_EQ(array[9], 81u);
  EXPECT_EQ(array[999], 0u);  // value-initialised
  EXPECT_EQ(array.append(1), SIZE_MAX);
  EXPECT_EQ(array.size(), 1000u);
}

// The kernel's flags of the mapping holding `address` (/proc/self/smaps' VmFlags line).
std::string mapping_flags(const void* address) {
  std::ifstream smaps("/proc/self/smaps");
  std::string line;
  bool inside = false;
  const auto at = reinterpret_cast<uintptr_t>(address);
  while (std::getline(smaps, line)) {
    uintptr_t lo = 0, hi = 0;
    char dash = 0;
    std::istringstream range(line);
    if (range >> std::hex >> lo >> dash >> hi && dash == '-') inside = lo <= at && at < hi;
    if (inside && line.rfind("VmFlags:", 0) == 0) return line;
  }
  return "";
}

// A small array takes ordinary pages (a huge page would be zeroed whole at its first
// write); past the prefix the system is asked for huge pages.
TEST(StableArray, HugePagesAreAskedForOnlyPastTheSmallPrefix) {
  if (!std::filesystem::exists("/sys/kernel/mm/transparent_hugepage/enabled"))
    GTEST_SKIP() << "this kernel has no transparent huge pages";
  StableArray<uint8_t> array(size_t{64} << 20);
  ASSERT_EQ(array.append(StableArray<uint8_t>::kSmallPrefix + 1), 0u);
  const std::string small = mapping_flags(&array[0]);
  const std::string small_end = mapping_flags(&array[StableArray<uint8_t>::kSmallPrefix - 1]);
  const std::string huge = mapping_flags(&array[StableArray<uint8_t>::kSmallPrefix]);
  EXPECT_NE(small.find(" nh"), std::string::npos) << small;
  EXPECT_NE(small_end.find(" nh"), std::string::npos) << small_end;
  EXPECT_NE(huge.find(" hg"), std::string::npos) << huge;
  EXPECT_EQ(huge.find(" nh"), std::string::npos) << huge;
}

// ---------------------------------------------------------------------------------------
// Scene files and counts

using test::input_error;

TEST(SceneLimits, FileSizeIsCheckedBeforeReading) {
  const std::string path = test::write_temp_file("limit.obj", std::string(1000, '#'));
  EXPECT_EQ(detail::read_scene_file(path, 1000, 1000).size(), 1000u);  // at the limit: read
  EXPECT_EQ(input_error([&] { detail::read_scene_file(path, 1000, 999); }),
            path + ": file is larger than the 999-byte limit");
  // A plain file's bytes are its data: the data limit applies too.
  EXPECT_EQ(input_error([&] { detail::read_scene_file(path, 999, 1000); }),
            path + ": file is larger than the 999-byte limit");
}

TEST(SceneLimits, CountsAboveTheLimitsAreOneLineErrors) {
  EXPECT_EQ(input_error([] { check_scene_counts("s.ply", 10, 20, 10, 20); }), "");
  EXPECT_EQ(input_error([] { check_scene_counts("s.ply", 11, 20, 10, 20); }),
            "s.ply: 11 vertices, more than the limit of 10");
  EXPECT_EQ(input_error([] { check_scene_counts("s.ply", 10, 21, 10, 20); }),
            "s.ply: 21 triangles, more than the limit of 20");
  // The defaults: 2^28 of each (scene.h gives the memory arithmetic behind them).
  EXPECT_EQ(input_error([] { check_scene_counts("s.ply", 1 << 28, 1 << 28); }), "");
  EXPECT_NE(input_error([] { check_scene_counts("s.ply", 0, (1 << 28) + 1); }), "");
}

// ---------------------------------------------------------------------------------------
// Structure parameters

const std::vector<std::string>& structure_names() {
  static const std::vector<std::string> names = {"uniform", "octree", "grid3d", "grid1d", "bvh"};
  return names;
}

// The UsageError message make_accelerator throws for `name` with `params` ("" for none).
std::string usage_error(const std::string& name, const AccelParams& params) {
  try {
    make_accelerator(name, params);
  } catch (const UsageError& e) {
    return e.what();
  }
  return "";
}

TEST(ParameterLimits, OutOfRangeValuesNameTheFlag) {
  struct Bad {
    std::function<void(AccelParams&)> set;
    std::string message;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<Bad> bad = {
      {[](AccelParams& p) { p.intcost = -1; }, "--intcost -1: expected a finite number >= 0"},
      {[&](AccelParams& p) { p.subcost = nan; }, "--subcost nan: expected a finite number >= 0"},
      {[](AccelParams& p) { p.vertcost = HUGE_VAL; }, "--vertcost inf: expected a finite"},
      {[](AccelParams& p) { p.max_granularity = 0; }, "--max-granularity 0: expected"},
      {[](AccelParams& p) { p.max_granularity = kMaxGranularity + 1; },
       "--max-granularity 4097: expected an integer in 1..4096"},
      {[](AccelParams& p) { p.max_depth = -1; }, "--max-depth -1: expected"},
      {[](AccelParams& p) { p.max_depth = kMaxDepth + 1; }, "--max-depth 65: expected"},
      {[](AccelParams& p) { p.leaf_size = kMaxLeafSize + 1; }, "--leaf-size 1048577: expected"},
      {[&](AccelParams& p) { p.density = nan; }, "--density nan: expected"},
      {[](AccelParams& p) { p.sample_every = 0; }, "--sample-every 0: expected"},
      {[](AccelParams& p) { p.build_threads = -1; }, "--build-threads -1: expected"},
      {[](AccelParams& p) { p.memory_budget = kMaxMemoryBudget + 1; },
       "--memory-budget 1099511627777: expected at most"},
  };
  for (const std::string name : {"grid1d", "bvh", "brute"})
    for (const Bad& b : bad) {
      AccelParams params;
      b.set(params);
      EXPECT_EQ(usage_error(name, params).rfind(b.message, 0), 0u)
          << name << ": " << usage_error(name, params) << " (wanted " << b.message << ")";
    }
}

TEST(ParameterLimits, EachStructureKeepsItsOwnDepthCap) {
  for (const auto& [name, cap] :
       {std::pair{"octree", Octree::kDepthCap}, std::pair{"grid3d", NestedGrid::kMaxDepthCap},
        std::pair{"bvh", kMaxDepth}, std::pair{"grid1d", kMaxDepth}}) {
    AccelParams params;
    params.max_depth = cap;
    EXPECT_EQ(usage_error(name, params), "") << name;
    params.max_depth = cap + 1;
    EXPECT_EQ(usage_error(name, params), "--max-depth " + std::to_string(cap + 1) +
                                             ": expected an integer in 1.." + std::to_string(cap) +
                                             " for " + name);
  }
}

TEST(ParameterLimits, TheExtremesAreAccepted) {
  AccelParams params;
  params.intcost = params.repcost = params.travcost = params.vertcost = params.subcost = 0.0;
  params.max_granularity = kMaxGranularity;
  params.leaf_size = kMaxLeafSize;
  params.memory_budget = kMaxMemoryBudget;  // address space is reserved, never committed
  for (const std::string& name : structure_names())
    EXPECT_EQ(usage_error(name, params), "") << name;
}

TEST(ParameterLimits, CommandLineReportsThemWithExitStatusTwo) {
  const auto outcome =
      test::run_gridscope("render builtin:pyramid --out " + test::quoted(test::temp_path("x.png")) +
                          " --accel octree --max-depth 21");
  EXPECT_EQ(outcome.status, 2);
  EXPECT_NE(outcome.err.find("--max-depth 21: expected an integer in 1..20 for octree"),
            std::string::npos)
      << outcome.err;
  const auto budget =
      test::run_gridscope("render builtin:pyramid --out " + test::quoted(test::temp_path("x.png")) +
                          " --memory-budget 2048G");
  EXPECT_EQ(budget.status, 2);
  EXPECT_NE(budget.err.find("--memory-budget"), std::string::npos) << budget.err;
}

// ---------------------------------------------------------------------------------------
// Structures on a budget and on degenerate input

bool is_lazy(const std::string& name) { return name == "grid1d" || name == "grid3d"; }

// Built as the command line builds: build, the sampling pass over every 16th ray, then
// (eager) everything the rays could reach; traced by two threads.
test::StructureRun run_of(const std::string& name, AccelParams params, bool eager) {
  params.sample_every = 16;
  return {name, params, true, eager, 2};
}

std::unique_ptr<Accelerator> built(const std::string& name, const AccelParams& params,
                                   const Scene& scene, const std::vector<Ray>& rays, bool eager) {
  return test::build_structure(run_of(name, params, eager), scene, rays);
}

// Lazy structures traced before and after building everything; the others once: the
// (run, ray) pairs whose answers differ from brute's `expected`.
size_t disagreements(const std::string& name, const AccelParams& params, const Scene& scene,
                     const std::vector<Ray>& rays, const std::vector<Hit>& expected) {
  std::vector<test::StructureRun> runs = {run_of(name, params, false)};
  if (is_lazy(name)) runs.push_back(run_of(name, params, true));
  return test::disagreements(scene, rays, runs, expected);
}

std::vector<Ray> mixed_rays(const Scene& scene, int count) {
  Box box = scene.bounds();
  // A flat scene's box has no depth: rays from around it still cross it.
  for (int a = 0; a < 3; ++a)
    if (box.hi[a] - box.lo[a] < 1e-3f * (box.hi - box.lo)[(a + 1) % 3])
      box.lo[a] -= 1.0f, box.hi[a] += 1.0f;
  return test::mixed_rays(scene, box,
                          {.camera_width = 30,
                           .camera_height = 30,
                           .chords = count,
                           .axis_parallel = count,
                           .edges_and_vertices = count,
                           .chord_seed = 5,
                           .axis_seed = 6,
                           .edge_seed = 7});
}

// --- Memory budget ---------------------------------------------------------------------

Scene budget_scene() { return test::small_sphere_in_soup(1500); }

class MemoryBudget : public testing::TestWithParam<std::string> {};

// Budgets from none to a good part of what the structure wants: some voxels or nodes stay
// leaves (the uniform grid gets fewer cells) and stats count them; the structure stays
// within the budget plus what it builds whatever the budget (its triangles and its root:
// what budget 0 gives); the answers stay brute's.
TEST_P(MemoryBudget, BudgetsBoundTheStructureAndNeverChangeAnswers) {
  const std::string name = GetParam();
  const Scene scene = budget_scene();
  const std::vector<Ray> rays = mixed_rays(scene, 1000);
  const std::vector<Hit> expected = test::brute_answers(scene, rays);
  const StructureStats unbounded = built(name, AccelParams{}, scene, rays, true)->stats();
  EXPECT_EQ(unbounded.voxels_over_budget, 0u);
  AccelParams params;
  params.memory_budget = 0;
  // grid1d counts its root voxel against the budget too and refuses a budget that cannot
  // hold the root's triangle list with a usage error: its floor is what it builds on the
  // smallest budget used here.
  if (name == "grid1d") {
    EXPECT_THROW(built(name, params, scene, rays, true), UsageError);
    params.memory_budget = 16 << 10;
  }
  const uint64_t floor = built(name, params, scene, rays, true)->stats().memory_bytes;
  bool refused = false;
  for (const uint64_t budget : {0, 16 << 10, 64 << 10, 512 << 10}) {
    if (name == "grid1d" && budget == 0) continue;
    params.memory_budget = budget;
    const StructureStats stats = built(name, params, scene, rays, true)->stats();
    std::printf("%s, budget %llu: %llu bytes, %llu over budget (unbounded: %llu bytes)\n",
                name.c_str(), (unsigned long long)budget, (unsigned long long)stats.memory_bytes,
                (unsigned long long)stats.voxels_over_budget,
                (unsigned long long)unbounded.memory_bytes);
    EXPECT_LE(stats.memory_bytes, budget + floor) << budget;
    if (stats.voxels_over_budget > 0) {
      refused = true;
      EXPECT_LT(stats.memory_bytes, unbounded.memory_bytes) << budget;
    }
    EXPECT_EQ(disagreements(name, params, scene, rays, expected), 0u) << budget;
  }
  EXPECT_TRUE(refused);
}

INSTANTIATE_TEST_SUITE_P(Structures, MemoryBudget, testing::ValuesIn(structure_names()),
                         [](const auto& info) { return info.param; });

// --- Degenerate input ------------------------------------------------------------------

// 2,000 triangles in the tilted plane x + y + z = 0 (no axis is flat, the cost model's
// spread is all in two dimensions).
Scene tilted_plane_scene() {
  Scene scene = test::make_soup(9, 2000, glm::vec3(-1.0f), glm::vec3(1.0f), 0.05f);
  for (glm::vec3& v : scene.vertices) v.z = -v.x - v.y;
  return scene;
}

// Zero extent along x: every vertex at x = 0.25.
Scene flat_x_scene() {
  Scene scene = test::make_soup(10, 2000, glm::vec3(-1.0f), glm::vec3(1.0f), 0.05f);
  for (glm::vec3& v : scene.vertices) v.x = 0.25f;
  return scene;
}

// A small scene a million units from the origin, where float spacing is 1/16.
Scene far_away_scene() {
  return test::transformed(budget_scene(), 100.0f, glm::vec3(1e6f, -2e6f, 1e6f));
}

struct DegenerateCase {
  std::string structure;
  std::string scene;
};

Scene degenerate_scene(const std::string& name) {
  if (name == "coincident") return test::coincident_scene();
  if (name == "tilted_plane") return tilted_plane_scene();
  if (name == "flat_x") return flat_x_scene();
  if (name == "slivers") return test::sliver_scene();
  return far_away_scene();
}

// The deepest level the structure built (its top node, voxel or grid is level 0).
int depth_built(const Accelerator& accel) { return int(accel.stats().depth.value_or(0)); }

// Each structure's documented depth cap at its default parameters.
int default_depth_cap(const std::string& name) {
  if (name == "octree") return Octree::kDefaultMaxDepth;
  if (name == "grid3d") return NestedGrid::kDefaultMaxDepth;
  if (name == "grid1d") return 32;
  if (name == "bvh") return Bvh::kDefaultMaxDepth;
  return 0;
}

class Degenerate : public testing::TestWithParam<DegenerateCase> {};

// Everything built (eager), with depth within the cap and at most 64 nodes per triangle;
// every answer brute's, lazy and eager.
TEST_P(Degenerate, BuildEndsBoundedAndAnswersEqualBrute) {
  const auto& [name, scene_name] = GetParam();
  const Scene scene = degenerate_scene(scene_name);
  const std::vector<Ray> rays = mixed_rays(scene, 800);
  const std::vector<Hit> expected = test::brute_answers(scene, rays);
  const auto accel = built(name, AccelParams{}, scene, rays, true);
  const StructureStats stats = accel->stats();
  std::printf("%s on %s: %llu nodes, depth %d, %llu bytes\n", name.c_str(), scene_name.c_str(),
              (unsigned long long)*stats.nodes, depth_built(*accel),
              (unsigned long long)stats.memory_bytes);
  EXPECT_LE(depth_built(*accel), default_depth_cap(name));
  EXPECT_LE(*stats.nodes, 64 * scene.triangle_count());
  EXPECT_EQ(disagreements(name, AccelParams{}, scene, rays, expected), 0u);
}

std::vector<DegenerateCase> degenerate_cases() {
  std::vector<DegenerateCase> cases;
  for (const std::string& s : structure_names())
    for (const char* scene : {"coincident", "tilted_plane", "flat_x", "slivers", "far_away"})
      cases.push_back({s, scene});
  return cases;
}

INSTANTIATE_TEST_SUITE_P(Structures, Degenerate, testing::ValuesIn(degenerate_cases()),
                         [](const auto& info) {
                           return info.param.structure + "_" + info.param.scene;
                         });

// The largest granularity and depth together on input no cut can separate: grid1d's
// absolute granularity cap and cut rules end the build, with bounded memory.
TEST(GranularityTimesDepth, TheLargestBothOnInseparableInputEnd) {
  const Scene scene = test::coincident_scene();
  const std::vector<Ray> rays = mixed_rays(scene, 800);
  AccelParams params;
  params.max_granularity = kMaxGranularity;
  params.max_depth = kMaxDepth;
  params.subcost = params.vertcost = params.travcost = 0.0;  // every cut pays
  const auto accel = built("grid1d", params, scene, rays, true);
  std::printf("grid1d, g 4096 depth 64 on coincident: %llu nodes, depth %d, %llu bytes\n",
              (unsigned long long)*accel->stats().nodes, depth_built(*accel),
              (unsigned long long)accel->stats().memory_bytes);
  EXPECT_LE(depth_built(*accel), kMaxDepth);
  EXPECT_LT(accel->stats().memory_bytes, uint64_t{1} << 30);
  EXPECT_EQ(test::count_mismatches("grid1d", test::trace_all(*accel, rays, 2),
                                   test::brute_answers(scene, rays)),
            0u);
}

}  // namespace
}  // namespace gs
