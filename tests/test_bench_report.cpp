// The benchmark's report.md and PNG plots, from hand-made records whose figures
// are chosen so that every table cell, verdict and bar height can be worked out by hand.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "app/plot.h"
#include "bench/report.h"
#include "tests/test_util.h"

namespace {

using json = nlohmann::json;

struct SceneSpec {
  const char* label;
  const char* role;
  bool varying;
  int triangles;
};
constexpr SceneSpec kScenes[] = {{"pyramid", "pyramid", false, 4096},
                                 {"lumpy", "lumpy", true, 12000},
                                 {"dragon", "drum", true, 100000}};

// A record as `gridscope bench` writes it, with the given figures.
json record(const std::string& scene, const std::string& accel, const json& figures,
            const std::string& setting = "default", int threads = 1,
            const std::string& workload = "primary_shadow") {
  json r = {
      {"scene", scene},
      {"accel", accel},
      {"setting", setting},
      {"threads", threads},
      {"workload", workload},
      {"machine", {{"cpu", "Test CPU"}, {"cores", 2}, {"os", "Debian 12"}, {"compiler", "GCC 12"}}},
      {"commit", "abc1234"},
      {"seed", 7},
      {"repetitions", 5},
      {"quick", false},
      {"width", 64},
      {"height", 48},
      {"spp", 1},
      {"params", json::object()},
      {"reference", "brute"}};
  for (const SceneSpec& spec : kScenes)
    if (scene == spec.label) {
      r["role"] = spec.role;
      r["varying_complexity"] = spec.varying;
      r["triangles"] = spec.triangles;
    }
  r.update(figures);
  return r;
}

// Three scenes; brute never runs, embree misses pyramid, bvh runs on pyramid only.
json sample_records() {
  return json::array({
      record("pyramid", "zero", {{"trace_seconds", 0.10}, {"relative_to_zero", 1.0}}),
      record("pyramid", "uniform", {{"trace_seconds", 0.15}, {"relative_to_zero", 1.5}}),
      record("pyramid", "grid3d", {{"trace_seconds", 0.20}, {"relative_to_zero", nullptr}}),
      record("pyramid", "grid1d", {{"trace_seconds", 0.14}, {"relative_to_zero", 1.4}}),
      record("pyramid", "bvh", {{"trace_seconds", 0.12}, {"relative_to_zero", 1.2}}),

      record("lumpy", "zero", {{"trace_seconds", 0.2}, {"relative_to_zero", 1.0}}),
      record("lumpy", "uniform",
             {{"trace_seconds", 2.0}, {"relative_to_zero", 10.0}, {"under_load", true}}),
      record("lumpy", "octree", {{"trace_seconds", 0.6}, {"relative_to_zero", 3.0}}),
      record("lumpy", "grid3d",
             {{"trace_seconds", 0.5},
              {"relative_to_zero", 2.5},
              {"params", {{"max_depth", 3}, {"leaf_size", 16}}}}),
      record("lumpy", "grid3d",
             {{"trace_seconds", 0.4},
              {"relative_to_zero", 2.0},
              {"tests_per_ray", 5.0},
              {"steps_per_ray", 9.0},
              {"params", {{"max_depth", 4}, {"leaf_size", 16}}}},
             "best"),
      record("lumpy", "grid1d",
             {{"trace_seconds", 0.3},
              {"relative_to_zero", 1.5},
              {"rays_per_second", 1e6},
              {"tests_per_ray", 3.0},
              {"steps_per_ray", 9.5},
              {"build_seconds", 0.05},
              {"first_pass_seconds", 0.35},
              {"lazy_build_seconds", 0.01},
              {"memory_bytes", 1.2e6},
              {"disagreeing_rays", 0},
              {"image_rmse", 0.0}}),
      record("lumpy", "grid1d", {{"trace_seconds", 0.15}, {"relative_to_zero", 0.75}}, "default",
             2),
      record("lumpy", "grid1d", {{"trace_seconds", 0.28}, {"relative_to_zero", 1.4}}, "calibrated"),
      record("lumpy", "embree",
             {{"trace_seconds", 0.1},
              {"relative_to_zero", 0.5},
              {"rays_per_second", 3e6},
              {"build_seconds", 0.2},
              {"first_pass_seconds", 0.1},
              {"disagreeing_rays", 12},
              {"image_rmse", 0.25}}),

      record("dragon", "zero", {{"trace_seconds", 0.5}, {"relative_to_zero", 1.0}}),
      record("dragon", "uniform",
             {{"trace_seconds", 50.0}, {"relative_to_zero", 100.0}, {"over_time_cap", true}}),
      record("dragon", "octree",
             {{"trace_seconds", 1.0},
              {"relative_to_zero", 2.0},
              {"tests_per_ray", 4.0},
              {"steps_per_ray", 20.0}}),
      record("dragon", "grid3d", {{"trace_seconds", 1.5}, {"relative_to_zero", 3.0}}),
      record("dragon", "grid1d",
             {{"trace_seconds", 1.25},
              {"relative_to_zero", 2.5},
              {"rays_per_second", 8e5},
              {"build_seconds", 0.1},
              {"first_pass_seconds", 1.4},
              {"tests_per_ray", 8.0},
              {"steps_per_ray", 12.0},
              {"disagreeing_rays", 0},
              {"reference", "bvh"}}),
      record("dragon", "grid1d",
             {{"trace_seconds", 0.75},
              {"relative_to_zero", 1.5},
              {"cpu_seconds", 1.5},
              {"wall_seconds", 0.8}},
             "default", 2),
      record("dragon", "embree",
             {{"trace_seconds", 1.25},
              {"relative_to_zero", 2.5},
              {"rays_per_second", 8e5},
              {"build_seconds", 0.3},
              {"first_pass_seconds", 1.3}}),

      {{"accel", "calibration"},
       {"workload", "calibration"},
       {"constants", {{"intcost", 0.8}, {"travcost", 0.35}}},
       {"defaults", {{"intcost", 1.0}, {"travcost", 0.5}}}},
  });
}

void expect_has(const std::string& text, const std::string& part) {
  EXPECT_NE(text.find(part), std::string::npos) << "missing: " << part << "\nin:\n" << text;
}

TEST(BenchReport, HeaderNamesMachineCommitSeedAndRepetitions) {
  const std::string md = gs::bench_report_markdown(sample_records());
  expect_has(md,
             "Machine: Test CPU, 2 cores, Debian 12, GCC 12. Commit `abc1234`, seed 7, 5 warm "
             "repetitions per figure (median). Images 64x48, 1 spp.");
  EXPECT_EQ(md.find("Quick run"), std::string::npos);
}

TEST(BenchReport, Figure12TablesHoldEachRecordsRelativeTime) {
  const std::string md = gs::bench_report_markdown(sample_records());
  // Columns: the structures that ran, in report order (brute never ran), then zero's seconds.
  expect_has(md,
             "| scene | triangles | uniform | octree | grid3d | grid1d | bvh | embree | "
             "zero (s) |");
  // Default settings: null prints n/a, a missing record —, the time cap †, a figure taken
  // under load ‡, the row's lowest relative time in bold.
  expect_has(md, "| pyramid | 4,096 | 1.50 | — | n/a | 1.40 | **1.20** | — | 0.1 |");
  expect_has(md, "| lumpy | 12,000 | 10.00‡ | 3.00 | 2.50 | 1.50 | — | **0.50** | 0.2 |");
  expect_has(md,
             "| dragon (as drum) | 100,000 | 100.00† | **2.00** | 3.00 | 2.50 | — | 2.50 | 0.5 |");
  // At the best setting grid3d's sweep point (2.00) replaces its default (2.50) on lumpy.
  expect_has(md, "| lumpy | 12,000 | 10.00‡ | 3.00 | 2.00 | 1.50 | — | **0.50** | 0.2 |");
  expect_has(md, "- lumpy, grid3d: max_depth 4 (default 3)");
  // 2 threads: relative time, then the speed-up 0.30 s / 0.15 s.
  expect_has(md, "| lumpy | 12,000 | — | — | — | **0.75** (2.00×) | — | — | — |");
  expect_has(md, "Not run: no diffuse records.");
}

TEST(BenchReport, TargetsStateMetOrMissedWithTheNumbers) {
  const std::string md = gs::bench_report_markdown(sample_records());
  // The paper's claim on lumpy and dragon (pyramid has no varying complexity): grid1d 1.50
  // beats grid3d's best 2.00 on lumpy, loses 2.50 to octree's 2.00 on dragon.
  expect_has(md, "- **missed** (1 of 2 scenes): grid1d at least as fast as the best of uniform");
  expect_has(md,
             "lumpy: grid1d 1.500× vs grid3d 2.000× (best setting) (met); dragon: grid1d "
             "2.500× vs octree 2.000× (missed).");
  // Embree: 0.5/1.5 = 0.333 misses, 2.5/2.5 = 1.000 meets (the bound is inclusive).
  expect_has(md, "- **missed** (1 of 2 scenes): grid1d at least 1.00 of Embree's");
  expect_has(md,
             "pyramid: embree not run; lumpy: 1.00 vs 3.00 Mrays/s = 0.333 (missed); "
             "dragon: 0.80 vs 0.80 Mrays/s = 1.000 (met).");
  // Time to the answer: 0.05 + 0.35 s against 0.2 + 0.1 s misses; 0.1 + 1.4 s against
  // 0.3 + 1.3 s meets.
  expect_has(md,
             "- **missed** (1 of 2 scenes): grid1d's time to the answer, its build, sampling "
             "pass and first render");
  expect_has(md, "lumpy: 0.400 s vs 0.300 s (missed); dragon: 1.500 s vs 1.600 s (met).");
  // Our BVH ran on pyramid only: grid1d 1.40 against its 1.20.
  expect_has(md, "- **missed** (0 of 1 scenes): grid1d faster than our scalar BVH on every scene");
  expect_has(md, "pyramid: grid1d 1.400× vs bvh 1.200× (missed)");
  // Speed-up: 0.30/0.15 = 2.000 meets, 1.25/0.75 = 1.667 misses, with its 2 threads' CPU
  // time over wall time, 1.5 s / 0.8 s.
  expect_has(md, "lumpy: 2.000× (met); dragon: 1.667× (1.88 cores busy) (missed).");
  // Calibrated constants: 0.28 s against 0.30 s.
  expect_has(md, "- **met** (1 of 1 scenes): grid1d with calibrated cost constants");
  expect_has(md, "lumpy: calibrated 1.400× vs default 1.500× (met)");
}

// The time to the answer is judged at each thread count the run has, both structures building
// and rendering on those threads; without 2-thread records there is no 2-thread line.
TEST(BenchReport, TimeToTheAnswerIsJudgedAtEachThreadCount) {
  const auto answer = [](const std::string& accel, double build, double first, int threads) {
    return record("lumpy", accel, {{"build_seconds", build}, {"first_pass_seconds", first}},
                  "default", threads);
  };
  json records = json::array({answer("grid1d", 0.05, 0.35, 1), answer("embree", 0.2, 0.1, 1)});
  EXPECT_EQ(gs::bench_report_markdown(records).find("2 threads for both"), std::string::npos);
  // 0.05 + 0.35 s against 0.2 + 0.1 s on one thread; 0.1 + 0.15 s against 0.2 + 0.06 s on two.
  records.push_back(answer("grid1d", 0.1, 0.15, 2));
  records.push_back(answer("embree", 0.2, 0.06, 2));
  const std::string md = gs::bench_report_markdown(records);
  expect_has(md,
             "- **missed** (0 of 1 scenes): grid1d's time to the answer, its build, sampling pass "
             "and first render (lazy build included), at most Embree's build and first render (1 "
             "thread for both builds and renders, default settings; seconds). lumpy: 0.400 s vs "
             "0.300 s (missed).");
  expect_has(md,
             "- **met** (1 of 1 scenes): grid1d's time to the answer, its build, sampling pass and "
             "first render (lazy build included), at most Embree's build and first render (2 "
             "threads for both builds and renders, default settings; seconds). lumpy: 0.250 s vs "
             "0.260 s (met).");
}

// Two figures taken minutes apart are compared by their times relative to zero-overhead,
// each measured against the floor rendered beside it, not by their raw seconds: here the
// machine was faster while grid3d and the calibrated constants ran.
TEST(BenchReport, VerdictsCompareTimesRelativeToZeroNotRawSeconds) {
  const json records = json::array({
      record("lumpy", "zero", {{"trace_seconds", 0.05}, {"relative_to_zero", 1.0}}),
      record("lumpy", "grid1d", {{"trace_seconds", 0.30}, {"relative_to_zero", 6.0}}),
      record("lumpy", "grid3d", {{"trace_seconds", 0.25}, {"relative_to_zero", 6.5}}),
      record("lumpy", "grid1d", {{"trace_seconds", 0.28}, {"relative_to_zero", 6.2}}, "calibrated"),
  });
  const std::string md = gs::bench_report_markdown(records);
  expect_has(md, "lumpy: grid1d 6.000× vs grid3d 6.500× (met)");
  expect_has(md, "lumpy: calibrated 6.200× vs default 6.000× (missed)");
  expect_has(md, "grid1d wins: 6.00× against 6.50× for grid3d");
}

// A 2-thread record's paired speed-up (its "speedup") wins over the ratio of its seconds to
// the 1-thread record's, taken minutes apart (here 0.30 s / 0.10 s = 3.0 on two cores).
TEST(BenchReport, SpeedUpIsThePairedOneWhereTheRecordHasIt) {
  const json records = json::array({
      record("lumpy", "zero", {{"trace_seconds", 0.05}, {"relative_to_zero", 1.0}}),
      record("lumpy", "grid1d", {{"trace_seconds", 0.30}, {"relative_to_zero", 6.0}}),
      record("lumpy", "grid1d",
             {{"trace_seconds", 0.10}, {"relative_to_zero", 3.5}, {"speedup", 1.7}}, "default", 2),
  });
  const std::string md = gs::bench_report_markdown(records);
  expect_has(md, "- **missed** (0 of 1 scenes): grid1d's 2-thread speed-up");
  expect_has(md, "lumpy: 1.700× (missed)");
  expect_has(md, "**3.50** (1.70×)");
}

TEST(BenchReport, EmbreeBuildAgreementAndCalibrationTables) {
  const std::string md = gs::bench_report_markdown(sample_records());
  expect_has(md, "| lumpy | 1.00 | 3.00 | 0.33 | 1.50 | 0.50 |");
  expect_has(md, "| dragon (as drum) | 0.80 | 0.80 | 1.00 | 2.50 | 2.50 |");
  // 0.05 s up front + 0.01 s lazily; 1.2e6 bytes / 12,000 triangles.
  expect_has(md, "0.05+0.01 s, 100 B");
  // Disagreeing rays / RMSE, with the reference each scene used.
  expect_has(md, "| lumpy | brute | n/a | n/a | n/a | 0 / 0.00 | — | 12 / 0.25 |");
  expect_has(md, "| dragon (as drum) | bvh |");
  expect_has(md, "| intcost | 0.8 | 1 |");
  expect_has(md, "| travcost | 0.35 | 0.5 |");
  expect_has(md, "`bvh` is our plain scalar traversal");
}

// sample_records with packet measurements on lumpy: grid1d's packets 0.30 s -> 0.075 s
// (4.00x), 3.2 Mrays/s against Embree's packets' 4 Mrays/s; on diffuse rays 1.00 s -> 1.04 s.
json records_with_packets() {
  json records = sample_records();
  for (const json& r :
       {record("lumpy", "grid1d",
               {{"trace_seconds", 0.075},
                {"relative_to_zero", 0.375},
                {"rays_per_second", 3.2e6},
                {"packet_active_fraction", 0.625},
                {"packet_fallback_fraction", 0.02},
                {"disagreeing_rays", 0},
                {"image_rmse", 0.0}},
               "packets"),
        record("lumpy", "embree",
               {{"trace_seconds", 0.06}, {"relative_to_zero", 0.3}, {"rays_per_second", 4e6}},
               "packets"),
        record("lumpy", "zero", {{"trace_seconds", 0.5}, {"relative_to_zero", 1.0}}, "default", 1,
               "diffuse"),
        record("lumpy", "grid1d", {{"trace_seconds", 1.0}, {"relative_to_zero", 2.0}}, "default", 1,
               "diffuse"),
        record("lumpy", "grid1d", {{"trace_seconds", 1.04}, {"relative_to_zero", 2.08}}, "packets",
               1, "diffuse")})
    records.push_back(r);
  return records;
}

TEST(BenchReport, PacketColumnsAndTargets) {
  const std::string md = gs::bench_report_markdown(records_with_packets());
  // Figure 12: the packet columns follow the structures; lumpy's fastest is embree packets.
  expect_has(md,
             "| scene | triangles | uniform | octree | grid3d | grid1d | bvh | embree | grid1d "
             "packets | embree packets | zero (s) |");
  expect_has(md,
             "| lumpy | 12,000 | 10.00‡ | 3.00 | 2.50 | 1.50 | — | 0.50 | 0.38 | **0.30** | 0.2 |");
  // Diffuse: Embree's packets were not measured there, so no column.
  expect_has(md, "| lumpy | 12,000 | — | — | — | **2.00** | — | — | 2.08 | 0.5 |");
  // Targets: 0.30 / 0.075 = 4.000 meets the gain; 0.30 / 0.375 = 0.800 misses Embree's packets;
  // 1.04 / 1.00 = 1.040 is within 5%.
  expect_has(md, "lumpy: 4.000× (active 0.62, fallback 2.0%) (met)");
  expect_has(md, "lumpy: 3.20 vs 4.00 Mrays/s = 0.800 (missed)");
  expect_has(md, "lumpy: packets / single time 1.040 (met)");
  // Embree table: packets' rays/s and their ratio.
  expect_has(md, "| lumpy | 1.00 | 3.00 | 0.33 | 1.50 | 0.50 | 3.20 | 4.00 | 0.80 |");
  // Agreement: the packet measurements' column.
  expect_has(md, "| lumpy | brute | n/a | n/a | n/a | 0 / 0.00 | — | 12 / 0.25 | 0 / 0.00 | n/a |");
}

TEST(BenchReport, DiscussionExplainsWinsAndLossesFromTheCounts) {
  const std::string md = gs::bench_report_markdown(sample_records());
  expect_has(md,
             "grid1d wins: 1.50× against 2.00× for grid3d, the fastest of uniform, octree "
             "and grid3d (25% less time). Likely why: fewer triangle tests per ray (3.0 "
             "against 5.0).");
  expect_has(md,
             "grid1d loses: 2.50× against 2.00× for octree, the fastest of uniform, octree "
             "and grid3d (25% more time). Likely why: more triangle tests per ray (8.0 "
             "against 4.0), despite fewer cell steps per ray (12.0 against 20.0).");
  // pyramid: 0.14 s against uniform's 0.15 s (grid3d's 0.20 s), and no counts recorded.
  expect_has(md,
             "grid1d wins: 1.40× against 1.50× for uniform, the fastest of uniform, octree "
             "and grid3d (7% less time). No per-ray counts to compare.");
  expect_has(md, "No varying local complexity here");
}

TEST(BenchReport, NamesWhatDidNotRun) {
  json records = sample_records();
  records.erase(std::remove_if(records.begin(), records.end(),
                               [](const json& r) { return r.value("accel", "") == "embree"; }),
                records.end());
  const std::string md = gs::bench_report_markdown(records);
  expect_has(md, "- structure embree: not in this build or not asked for");
  expect_has(md, "- structure brute: not asked for");
  expect_has(md, "- the paper's trike scene: no scene stands for it");
  expect_has(md, "Not run: embree (not in this build or not asked for).");
  expect_has(md, "- **not checked**: grid1d at least 1.00 of Embree's single-thread speed");
  EXPECT_EQ(md.find("| embree"), std::string::npos);
}

TEST(BenchReport, MalformedRecordsGiveAReportNotACrash) {
  for (const json& records :
       {json::object(), json::array(), json::array({1, "x", nullptr, json::array()}),
        json::array({{{"scene", 5}},
                     {{"scene", "a"}, {"accel", "grid1d"}, {"trace_seconds", "fast"}},
                     {{"scene", "a"}, {"accel", "zero"}, {"threads", nullptr}, {"points", 3}}})}) {
    std::string md;
    EXPECT_NO_THROW(md = gs::bench_report_markdown(records)) << records.dump();
    expect_has(md, "# gridscope benchmark report");
  }
  EXPECT_NE(gs::bench_report_markdown(json::array()).find("No measurements"), std::string::npos);
}

// ---- Plots -----------------------------------------------------------------------------

using gs::test::Png;

std::string plot_dir(const std::string& name) {
  const std::string dir = gs::test::temp_path(name);
  std::filesystem::create_directories(dir);
  return dir;
}

bool has_colour(const Png& png, int x, int y, std::array<uint8_t, 3> colour) {
  const unsigned char* p = png.at(x, y);
  return p[0] == colour[0] && p[1] == colour[1] && p[2] == colour[2];
}

// The tallest vertical run of exactly `colour` in any column (a bar's height; a legend
// swatch is short) and the mean column of the runs that tall (the bar's centre).
struct BarRun {
  int height = 0;
  double column = -1;
};
BarRun tallest_run(const Png& png, std::array<uint8_t, 3> colour) {
  BarRun best;
  int columns = 0;
  for (int x = 0; x < png.width; ++x) {
    int run = 0, longest = 0;
    for (int y = 0; y < png.height; ++y) {
      run = has_colour(png, x, y, colour) ? run + 1 : 0;
      longest = std::max(longest, run);
    }
    if (longest > best.height)
      best = {longest, double(x)}, columns = 1;
    else if (longest == best.height && longest > 0)
      best.column = (best.column * columns + x) / (columns + 1), ++columns;
  }
  return best;
}

// Pixels of exactly `colour` in rows from `first_row` down.
int pixels_of(const Png& png, std::array<uint8_t, 3> colour, int first_row = 0) {
  int count = 0;
  for (int y = first_row; y < png.height; ++y)
    for (int x = 0; x < png.width; ++x) count += has_colour(png, x, y, colour);
  return count;
}

TEST(BenchPlots, RelativeBarsAreLogScaledInStructureColours) {
  const json records = json::array({
      record("s", "uniform", {{"relative_to_zero", 8.0}}),
      record("s", "octree", {{"relative_to_zero", 4.0}}),
      record("s", "grid3d", {{"relative_to_zero", 2.0}}),
      record("s", "grid1d", {{"relative_to_zero", nullptr}}),
  });
  const std::string dir = plot_dir("plots-relative");
  const std::vector<std::string> written = gs::app::write_bench_plots(records, dir);
  // No 2-thread, convergence or sweep records: only the relative-time plot.
  ASSERT_EQ(written, std::vector<std::string>{"relative_to_zero.png"});
  EXPECT_FALSE(std::filesystem::exists(dir + "/speedup.png"));

  const Png png = gs::test::load_png(dir + "/relative_to_zero.png");
  ASSERT_EQ(png.width, gs::app::kPlotWidth);
  ASSERT_EQ(png.height, gs::app::kBarPlotHeight);
  const BarRun uniform = tallest_run(png, gs::app::structure_colour("uniform"));
  const BarRun octree = tallest_run(png, gs::app::structure_colour("octree"));
  const BarRun grid3d = tallest_run(png, gs::app::structure_colour("grid3d"));
  // Bars grow from 1 (zero-overhead) on a log axis: 2, 4, 8 are equally spaced heights.
  EXPECT_GT(grid3d.height, 40);
  EXPECT_NEAR(octree.height, 2 * grid3d.height, 2);
  EXPECT_NEAR(uniform.height, 3 * grid3d.height, 3);
  // Side by side in the report's structure order.
  EXPECT_LT(uniform.column, octree.column);
  EXPECT_LT(octree.column, grid3d.column);
  // A null figure draws no bar (only its legend swatch and "n/a"); a structure that did not
  // run is not drawn at all.
  EXPECT_LT(tallest_run(png, gs::app::structure_colour("grid1d")).height, grid3d.height / 2);
  EXPECT_EQ(pixels_of(png, gs::app::structure_colour("bvh")), 0);
}

TEST(BenchPlots, PacketBarsFollowTheirStructureInALighterColour) {
  json records = json::array({
      record("s", "grid1d", {{"relative_to_zero", 4.0}}),
      record("s", "grid1d", {{"relative_to_zero", 2.0}}, "packets"),
  });
  EXPECT_EQ(gs::packet_column_structure("grid1d packets"), "grid1d");
  EXPECT_EQ(gs::packet_column_structure("grid1d"), std::nullopt);
  const std::array<uint8_t, 3> red = gs::app::structure_colour("grid1d");
  const std::array<uint8_t, 3> light = gs::app::structure_colour("grid1d packets");
  for (int c = 0; c < 3; ++c) EXPECT_EQ(light[c], (red[c] + 255) / 2);
  const std::string dir = plot_dir("plots-packets");
  ASSERT_EQ(gs::app::write_bench_plots(records, dir),
            std::vector<std::string>{"relative_to_zero.png"});
  const Png png = gs::test::load_png(dir + "/relative_to_zero.png");
  const BarRun single = tallest_run(png, red), packets = tallest_run(png, light);
  // Log axis from 1: the bar of 4 is twice the bar of 2; packets to the right.
  EXPECT_GT(packets.height, 40);
  EXPECT_NEAR(single.height, 2 * packets.height, 2);
  EXPECT_LT(single.column, packets.column);
}

// A figure at the zero-overhead floor (1, or a hair below) still draws a bar: a few pixels
// of its colour at the floor, below the legend, where a structure that did not run has none.
TEST(BenchPlots, BarsAtTheFloorStillShow) {
  const json records = json::array({
      record("s", "octree", {{"relative_to_zero", 4.0}}),
      record("s", "grid1d", {{"relative_to_zero", 1.0}}),
      record("s", "embree", {{"relative_to_zero", 0.999}}),
  });
  const std::string dir = plot_dir("plots-floor");
  ASSERT_EQ(gs::app::write_bench_plots(records, dir),
            std::vector<std::string>{"relative_to_zero.png"});
  const Png png = gs::test::load_png(dir + "/relative_to_zero.png");
  const BarRun octree = tallest_run(png, gs::app::structure_colour("octree"));
  ASSERT_GT(octree.height, 40);
  // Rows below the legend's swatches (the top quarter holds the title and the legend).
  const int below_legend = png.height / 4;
  for (const char* accel : {"grid1d", "embree"}) {
    const int pixels = pixels_of(png, gs::app::structure_colour(accel), below_legend);
    EXPECT_GT(pixels, 0) << accel;
    EXPECT_LT(pixels, octree.height * 10) << accel;
  }
  EXPECT_EQ(pixels_of(png, gs::app::structure_colour("bvh"), below_legend), 0);
}

TEST(BenchPlots, SpeedupConvergenceAndSweepPlotsAreWritten) {
  json records = json::array({
      record("s", "grid1d", {{"trace_seconds", 1.0}}),
      record("s", "grid1d", {{"trace_seconds", 0.5}}, "default", 2),
      // The progressive renderer runs on every core: convergence records have any thread count.
      record("s", "grid1d", {{"points", {{0.1, 40.0}, {0.5, 10.0}, {2.0, 1.0}}}}, "default", 2,
             "convergence"),
      record("s", "octree", {{"points", {{0.2, 50.0}, {1.0, 20.0}, {3.0, 2.0}}}}, "default", 2,
             "convergence"),
  });
  for (int g : {2, 8, 20, 64})
    records.push_back(record("s", "grid1d",
                             {{"sweep_param", "max_granularity"},
                              {"sweep_value", g},
                              {"trace_seconds", 1.0 + 10.0 / g},
                              {"memory_bytes", 1e5 * g}},
                             "sweep", 1, "sweep"));
  const std::string dir = plot_dir("plots-all");
  const std::vector<std::string> written = gs::app::write_bench_plots(records, dir);
  EXPECT_EQ(written, (std::vector<std::string>{"speedup.png", "rmse_vs_time.png", "sweep.png"}));

  const auto red = gs::app::structure_colour("grid1d");
  const Png speedup = gs::test::load_png(dir + "/speedup.png");
  ASSERT_EQ(speedup.width, gs::app::kPlotWidth);
  ASSERT_EQ(speedup.height, gs::app::kBarPlotHeight);
  // One bar, 1.0 s / 0.5 s = 2, on a linear axis from 0 to 2.5: most of the plot's height.
  EXPECT_GT(tallest_run(speedup, red).height, speedup.height / 2);

  for (const char* name : {"rmse_vs_time.png", "sweep.png"}) {
    const Png png = gs::test::load_png(dir + "/" + name);
    ASSERT_EQ(png.width, gs::app::kPlotWidth) << name;
    // grid1d's lines reach the lower half of the image, far below the legend at the top
    // (RMSE falls to its lowest values there; memory is the lower panel), and a structure
    // without data has no colour anywhere.
    EXPECT_GT(pixels_of(png, red, png.height / 2), 0) << name;
    EXPECT_EQ(pixels_of(png, gs::app::structure_colour("bvh")), 0) << name;
  }
}

}  // namespace
