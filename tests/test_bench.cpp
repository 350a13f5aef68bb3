// The benchmark driver (bench/bench.h): the records it writes hold the protocol's figures,
// and those figures agree with answers computed independently here.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "bench/bench.h"
#include "bench/progress.h"
#include "bench/scenes.h"
#include "core/base/error.h"
#include "core/render/render.h"
#include "tests/test_util.h"

namespace gs {
namespace {

using nlohmann::json;

TEST(BenchRmse, ClosedForm) {
  // Two 2-pixel images: channel differences 3, 4, 0 and 0, 0, 12 (alpha ignored):
  // sqrt((9 + 16 + 144) / 6).
  const std::vector<uint8_t> a = {10, 20, 30, 255, 0, 0, 0, 255};
  const std::vector<uint8_t> b = {13, 16, 30, 0, 0, 0, 12, 7};
  EXPECT_DOUBLE_EQ(image_rmse(a, b), std::sqrt(169.0 / 6.0));
  EXPECT_DOUBLE_EQ(image_rmse(a, a), 0.0);
  EXPECT_THROW(image_rmse(a, {1, 2, 3, 4}), std::invalid_argument);
}

// The probe that estimates a structure's render time first traces every 32nd band of rows;
// a lazy structure builds what those rows reach (a grid1d's upper levels, which every row
// crosses), and that building is part of the time to the answer: the first render's figures
// carry it. Binary fractions: the sums are exact.
TEST(BenchTimeToAnswer, TheFirstRenderCarriesTheLazyBuildItsProbeSetOff) {
  RenderOutcome first;
  first.seconds = 0.25;
  first.counters.lazy_build_seconds = 0.0625;
  const FirstPassFigures figures = first_pass_figures(first, 0.125);
  EXPECT_EQ(figures.seconds, 0.375);
  EXPECT_EQ(figures.lazy_build_seconds, 0.1875);
  EXPECT_EQ(first_pass_figures(first, 0.0).seconds, 0.25);  // a structure built up front
}

TEST(BenchOptions, UnknownStructureIsAUsageError) {
  BenchOptions options;
  options.accels = {"bvh", "kd-tree"};
  EXPECT_THROW(check_bench_options(options), UsageError);
  options.accels = {"zero"};  // measured always, as the floor: not a structure to ask for
  EXPECT_THROW(check_bench_options(options), UsageError);
}

TEST(BenchProgress, EtaIsTheStepsLeftAtThePaceOfThoseDone) {
  EXPECT_EQ(eta_seconds(10.0, 5, 10), 10.0);  // half done in 10 s: 10 s left
  EXPECT_EQ(eta_seconds(30.0, 3, 4), 10.0);
  EXPECT_EQ(eta_seconds(12.0, 4, 4), 0.0);
  EXPECT_FALSE(eta_seconds(3.0, 0, 4).has_value());  // no pace yet
}

TEST(BenchProgress, LineSaysStepsStepElapsedAndTimeLeft) {
  EXPECT_EQ(progress_line({50, 100, 10.0, "lumpy", "bvh", ""}),
            "50/100 steps (50%) | lumpy bvh | 10s elapsed | ETA 10s");
  EXPECT_EQ(progress_line({1, 4, 125.0, "", "grid1d", ""}),
            "1/4 steps (25%) | grid1d | 2m05s elapsed | ETA 6m15s");
}

// What a printer writes for `steps` steps, `seconds_per_step` apart.
std::string printed(bool terminal, bool verbose, int steps, double seconds_per_step) {
  std::string out;
  BenchProgressPrinter printer(terminal, verbose, [&out](std::string_view text) { out += text; });
  for (int i = 1; i <= steps; ++i)
    printer.step({i, steps, i * seconds_per_step, "lumpy", "bvh", "step " + std::to_string(i)});
  printer.finish();
  return out;
}

size_t count_of(const std::string& text, const std::string& part) {
  size_t count = 0;
  for (size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++count;
  return count;
}

TEST(BenchProgress, ALogGetsALinePerTenthAndVerboseALinePerStep) {
  // 100 steps in 10 s: a line at each tenth, then the summary; no step's own line.
  const std::string log = printed(false, false, 100, 0.1);
  EXPECT_EQ(count_of(log, "\n"), 11u) << log;
  EXPECT_EQ(count_of(log, "ETA"), 10u) << log;
  EXPECT_EQ(count_of(log, "step "), 0u) << log;
  EXPECT_NE(log.find("bench: 100/100 steps (100%)"), std::string::npos) << log;
  EXPECT_NE(log.find("bench: 100 of 100 steps in 10s\n"), std::string::npos) << log;
  // Slow steps: a line at least every kLogInterval seconds, though no new tenth is passed.
  EXPECT_EQ(count_of(printed(false, false, 100, BenchProgressPrinter::kLogInterval), "ETA"), 100u);
  // --verbose: every step's line and the summary.
  const std::string verbose = printed(false, true, 100, 0.1);
  EXPECT_EQ(count_of(verbose, "\n"), 101u);
  for (int i = 1; i <= 100; ++i)
    EXPECT_NE(verbose.find("bench: step " + std::to_string(i) + "\n"), std::string::npos) << i;
  EXPECT_EQ(count_of(verbose, "ETA"), 0u);
}

TEST(BenchProgress, ATerminalGetsOneLineRewrittenInPlace) {
  const std::string shown = printed(true, false, 20, 1.0);
  EXPECT_EQ(count_of(shown, "\r"), 20u);
  EXPECT_EQ(count_of(shown, "\n"), 2u);  // the progress line's end, then the summary
  EXPECT_EQ(count_of(shown, "step "), 0u);
  EXPECT_NE(shown.find("\rbench: 20/20 steps (100%) | lumpy bvh | 20s elapsed | ETA 0s"),
            std::string::npos)
      << shown;
}

TEST(BenchScenes, SuiteSceneWithoutSharedMeshesIsSkippedWithTheReason) {
  std::string why;
  EXPECT_FALSE(load_bench_scene("dragon", "/nonexistent-shared", why));
  EXPECT_NE(why.find("dragon"), std::string::npos) << why;
  EXPECT_THROW(load_bench_scene("/nonexistent/scene.obj", "", why), InputError);
  const auto lumpy = load_bench_scene("lumpy", "", why);
  ASSERT_TRUE(lumpy);
  EXPECT_EQ(lumpy->role, "lumpy");
  EXPECT_EQ(lumpy->scene->triangle_count(), 60620u);
}

// A small closed sphere bench, quick protocol, two exact structures and 2 threads.
class BenchRunTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    path_ = new std::string(test::temp_path("bench-sphere.obj"));
    export_obj(test::make_sphere({0.0f, 0.0f, 0.0f}, 1.0f, 12, 16), *path_);
    BenchOptions options;
    options.scenes = {*path_, "dragon"};
    options.accels = {"bvh", "uniform"};
    options.quick = true;
    options.threads = 2;
    options.assets_dir = "/nonexistent-shared";
    steps_ = new std::vector<BenchStep>;
    options.progress = [](const BenchStep& step) { steps_->push_back(step); };
    records_ = new json(run_bench(options));
  }
  static void TearDownTestSuite() {
    delete records_;
    delete steps_;
    delete path_;
  }

  static std::vector<json> select(const std::string& workload, const std::string& accel = "") {
    std::vector<json> found;
    for (const json& r : *records_)
      if (r["workload"] == workload && (accel.empty() || r["accel"] == accel)) found.push_back(r);
    return found;
  }

  static std::string* path_;
  static json* records_;
  static std::vector<BenchStep>* steps_;
};
std::string* BenchRunTest::path_ = nullptr;
json* BenchRunTest::records_ = nullptr;
std::vector<BenchStep>* BenchRunTest::steps_ = nullptr;

TEST_F(BenchRunTest, ProgressCountsEveryStepAndEndsAtTheTotal) {
  // The sphere's steps: each of its records (measurements and convergence curves) and the
  // reference of each workload. Dragon, skipped, would have had as many but for the
  // convergence curves (the quick protocol follows them on lumpy and on users' scenes).
  const size_t sphere_records = std::count_if(records_->begin(), records_->end(),
                                              [](const json& r) { return r["scene"] == *path_; });
  const size_t curves = select("convergence").size();
  ASSERT_EQ(curves, 2u);
  const int sphere_steps = int(sphere_records) + 2;
  const int dragon_steps = sphere_steps - int(curves);
  ASSERT_EQ(steps_->size(), size_t(sphere_steps) + 1);  // dragon's steps reported at once
  for (size_t i = 0; i < steps_->size(); ++i) {
    const BenchStep& step = (*steps_)[i];
    EXPECT_EQ(step.total, sphere_steps + dragon_steps);
    EXPECT_EQ(step.done, i < size_t(sphere_steps) ? int(i) + 1 : step.total) << i;
    if (i > 0) {
      EXPECT_GE(step.elapsed, (*steps_)[i - 1].elapsed);
    }
  }
  EXPECT_EQ(steps_->back().scene, "dragon");
  EXPECT_NE(steps_->back().line.find("skipped"), std::string::npos);
}

TEST_F(BenchRunTest, MissingSharedSceneIsASkippedRecord) {
  const auto skipped = select("skipped");
  ASSERT_EQ(skipped.size(), 1u);
  EXPECT_EQ(skipped[0]["scene"], "dragon");
}

TEST_F(BenchRunTest, EveryStructureThreadCountAndWorkloadIsMeasured) {
  for (const char* workload : {"primary_shadow", "diffuse"})
    for (const char* accel : {"zero", "bvh", "uniform"}) {
      const auto records = select(workload, accel);
      std::vector<int> threads;
      for (const json& r : records)
        if (r["setting"] == "default") threads.push_back(r["threads"].get<int>());
      EXPECT_EQ(threads, (std::vector<int>{1, 2})) << workload << " " << accel;
    }
}

// Every structure builds on the threads its run traces on (Embree's build would otherwise
// take every core, also for a 1-thread figure).
TEST_F(BenchRunTest, EveryStructureBuildsOnItsRunsThreads) {
  size_t checked = 0;
  for (const json& r : select("primary_shadow"))
    if (r["setting"] == "default" && r["accel"] != "reference") {
      EXPECT_EQ(r["params"]["build_threads"], r["threads"]) << r["accel"];
      ++checked;
    }
  EXPECT_GE(checked, 6u);
}

TEST_F(BenchRunTest, RayCountsMatchAnIndependentRender) {
  const Scene scene = load_scene(*path_);
  for (const json& r : select("primary_shadow")) {
    if (r["setting"] != "default") continue;
    RenderSettings settings;
    settings.width = r["width"];
    settings.height = r["height"];
    settings.bounces = 0;
    auto brute = make_accelerator("brute", AccelParams{});
    brute->build(scene);
    const RenderOutcome expected =
        render_image(scene, *brute, parse_camera(r["camera"].get<std::string>()), settings);
    EXPECT_EQ(r["rays"].get<uint64_t>(), expected.rays) << r["accel"];
  }
}

TEST_F(BenchRunTest, ExactStructuresAgreeWithTheReferenceAndZeroIsTheFloor) {
  for (const char* workload : {"primary_shadow", "diffuse"})
    for (const json& r : select(workload)) {
      EXPECT_EQ(r["disagreeing_rays"], 0) << workload << " " << r["accel"];
      EXPECT_EQ(r["image_rmse"], 0.0) << workload << " " << r["accel"];
      EXPECT_EQ(r["reference"], "bvh");
      if (r["accel"] == "zero") {
        EXPECT_EQ(r["relative_to_zero"], 1.0);
        // The oracle tests at most one triangle per ray.
        EXPECT_LE(r["tests_per_ray"].get<double>(), 1.0);
      }
      EXPECT_EQ(r["warm_seconds"].size(), size_t(r["repetitions"].get<int>()));
      // The warm renders' wall time is the sum of the repetitions (not of the renders paired
      // with them); their CPU time, taken over the same windows, is spent by at most the
      // run's threads (plus the clocks' granularity).
      const double wall = r["wall_seconds"], cpu = r["cpu_seconds"];
      double sum = 0.0;
      for (const json& seconds : r["warm_seconds"]) sum += seconds.get<double>();
      EXPECT_DOUBLE_EQ(wall, sum);
      EXPECT_LE(cpu, wall * r["threads"].get<double>() + 0.02) << r["accel"];
      EXPECT_GE(r["others_busy_cores"].get<double>(), 0.0);
      EXPECT_EQ(r["under_load"], r["others_busy_cores"].get<double>() > 0.25);
      EXPECT_GE(r["load_before"].get<double>(), 0.0);
    }
}

// The median of ratios of paired times (the quick protocol's 3 repetitions: odd).
double median_ratio(const json& numerators, const json& denominators) {
  std::vector<double> ratios;
  for (size_t i = 0; i < numerators.size(); ++i)
    ratios.push_back(numerators[i].get<double>() / denominators[i].get<double>());
  std::sort(ratios.begin(), ratios.end());
  return ratios.empty() ? 0.0 : ratios[ratios.size() / 2];
}

// Each warm render of a structure is followed by one of the zero-overhead floor; the time
// relative to zero is the median of the pairs' ratios, not the ratio of two medians taken
// minutes apart.
TEST_F(BenchRunTest, RelativeToZeroIsTheMedianRatioOfRendersPairedWithTheFloor) {
  size_t paired = 0;
  for (const char* workload : {"primary_shadow", "diffuse"})
    for (const json& r : select(workload)) {
      if (r["accel"] == "zero") {
        EXPECT_FALSE(r.contains("zero_warm_seconds"));
        continue;
      }
      const auto& warm = r["warm_seconds"];
      const auto& floor = r.at("zero_warm_seconds");
      ASSERT_EQ(floor.size(), warm.size()) << r["accel"] << " " << r["setting"];
      ASSERT_EQ(warm.size() % 2, 1u);
      EXPECT_DOUBLE_EQ(r["relative_to_zero"].get<double>(), median_ratio(warm, floor))
          << workload << " " << r["accel"] << " " << r["setting"];
      ++paired;
    }
  // bvh and uniform by default, 1 and 2 threads, two workloads, and each one's best.
  EXPECT_EQ(paired, 2u * 2u * 2u + 2u);
}

// On 2 threads each warm render is followed by one of the same structure on 1 thread; the
// speed-up is the median of those pairs' ratios.
TEST_F(BenchRunTest, SpeedUpIsTheMedianRatioOfOneThreadRendersPairedWithEachWarmRender) {
  size_t paired = 0;
  for (const char* workload : {"primary_shadow", "diffuse"})
    for (const json& r : select(workload)) {
      if (r["threads"] == 1) {
        EXPECT_FALSE(r.contains("speedup")) << r["accel"];
        continue;
      }
      const auto& one = r.at("one_thread_warm_seconds");
      ASSERT_EQ(one.size(), r["warm_seconds"].size()) << r["accel"];
      ASSERT_EQ(one.size() % 2, 1u);
      EXPECT_DOUBLE_EQ(r["speedup"].get<double>(), median_ratio(one, r["warm_seconds"]))
          << workload << " " << r["accel"];
      ++paired;
    }
  // zero, bvh and uniform on 2 threads, two workloads.
  EXPECT_EQ(paired, 3u * 2u);
}

// Records timed in rounds: each one's k-th warm render begins before any other's (k+1)-th.
void expect_rounds(const std::vector<json>& group, const std::string& label) {
  for (const json& a : group)
    for (const json& b : group) {
      const auto& early = a.at("warm_started_seconds");
      const auto& late = b.at("warm_started_seconds");
      ASSERT_EQ(early.size(), size_t(a["repetitions"].get<int>())) << label;
      for (size_t k = 0; k + 1 < early.size(); ++k)
        EXPECT_LT(early[k].get<double>(), late[k + 1].get<double>())
            << label << " " << a["accel"] << " " << a["params"] << " " << b["accel"] << " "
            << b["params"] << " " << k;
    }
}

// The structures compared with each other (one scene, workload, thread count and kind of
// setting) take their warm renders in rounds, and so do a structure's sweep points, so that
// the machine's drift falls on all of them alike.
TEST_F(BenchRunTest, StructuresComparedWithEachOtherAreTimedInRounds) {
  size_t groups = 0;
  for (const char* workload : {"primary_shadow", "diffuse"})
    for (const int threads : {1, 2})
      for (const char* setting : {"default", "best"}) {
        std::vector<json> group;
        for (const json& r : select(workload))
          if (r["threads"] == threads && r["setting"] == setting && r["accel"] != "zero")
            group.push_back(r);
        if (group.empty()) continue;
        const std::string label =
            std::string(workload) + " " + std::to_string(threads) + " " + setting;
        ASSERT_EQ(group.size(), 2u) << label;
        expect_rounds(group, label);
        ++groups;
      }
  // Defaults on 1 and 2 threads for both workloads, and the bests.
  EXPECT_EQ(groups, 5u);
  for (const char* accel : {"bvh", "uniform"}) expect_rounds(select("sweep", accel), accel);
}

TEST_F(BenchRunTest, SweepsCoverEveryValueAndTheBestIsMeasuredInFull) {
  EXPECT_EQ(select("sweep", "uniform").size(), 7u);  // density 1/8 .. 8
  EXPECT_EQ(select("sweep", "bvh").size(), 5u);      // leaf size 1 .. 16
  for (const char* accel : {"bvh", "uniform"}) {
    size_t best = 0;
    for (const json& r : select("primary_shadow", accel)) best += r["setting"] == "best";
    EXPECT_EQ(best, 1u) << accel;
  }
}

TEST_F(BenchRunTest, ConvergenceEndsAtZeroErrorForExactStructures) {
  const auto curves = select("convergence");
  ASSERT_EQ(curves.size(), 2u);
  for (const json& curve : curves) {
    ASSERT_FALSE(curve["points"].empty()) << curve["accel"];
    // The last pass completes the converged image's samples: the same image exactly.
    EXPECT_EQ(curve["points"].back()[1], 0.0) << curve["accel"];
  }
}

}  // namespace
}  // namespace gs
