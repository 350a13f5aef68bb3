// Calibration of the §6.2 code timings: the fit against closed-form data, the file format
// and its errors, and a short real run (no timing thresholds: only that it measures).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>

#include "bench/calibrate.h"
#include "core/base/error.h"
#include "core/base/files.h"
#include "core/trace/trace_job.h"
#include "tests/test_util.h"

namespace gs {
namespace {

using json = nlohmann::json;

// Seconds per unit of each term, chosen unlike the defaults' ratios.
struct KnownCosts {
  double ray = 40e-9, test = 20e-9, rejection = 3e-9, step = 8e-9, descent = 15e-9;
  double leaf_triangle = 1e-9, cell = 0.5e-9;
  double seconds_of(const WorkSample& row) const {
    return ray + test * row.tests + rejection * row.rejections + step * row.steps +
           descent * row.descents + leaf_triangle * row.leaf_triangles + cell * row.cells;
  }
};

// Counts shaped like the calibration's scenarios (leaves whose boxes the rays cross or miss,
// walks, walks past cells, slivers, descents), and their exact times under `costs`.
std::vector<WorkSample> exact_rows(const KnownCosts& costs, bool with_rejections = true,
                                   bool with_box_misses = true, bool with_cells_passed = true) {
  std::vector<WorkSample> rows = {
      {"leaf 8", 100, 8, 0, 1, 0, 10, 0},           {"leaf 512", 100, 512, 0, 1, 0, 514, 0},
      {"walk 16", 100, 9, 0, 8, 1, 16, 15},         {"walk 256", 100, 129, 0, 128, 1, 256, 255},
      {"cells 64", 100, 8, 0, 8, 1, 16, 63},        {"cells 256", 100, 8, 0, 8, 1, 16, 255},
      {"slivers 16", 100, 48, 496, 31, 1, 517, 31}, {"slivers 64", 100, 96, 1920, 30, 1, 1572, 30},
      {"descents 3", 100, 1, 0, 1, 3, 1, 0.01},     {"descents 12", 100, 1, 0, 1, 12, 1, 0.4},
      {"box tests 64", 100, 0, 0, 1, 0, 64, 0},     {"box tests 512", 100, 0, 0, 1, 0, 512, 0},
  };
  for (WorkSample& row : rows) {
    if (!with_rejections) row.rejections = 0;
    // Without leaves whose boxes the rays miss, leaf triangles follow tests and steps.
    if (!with_box_misses) row.leaf_triangles = row.tests + row.steps;
    // Without cells passed by, every cell crossed is one searched.
    if (!with_cells_passed) row.cells = row.steps;
    row.seconds = costs.seconds_of(row);
  }
  return rows;
}

// A quarter of a searched leaf's triangles tested for real, half a cell searched per cell
// crossed.
constexpr RealRayShares kShares{0.25, 0.5};

const std::vector<BuildSample> kBuilds = {{"a", 1000, 1000 * 50e-9}, {"b", 3000, 3000 * 50e-9}};

TEST(Calibrate, FitRecoversKnownCosts) {
  const KnownCosts costs;
  const CostFit fit = fit_costs(exact_rows(costs));
  const double expected[kFitTerms] = {costs.ray,  costs.test,    costs.rejection,
                                      costs.step, costs.descent, costs.leaf_triangle,
                                      costs.cell};
  for (int t = 0; t < kFitTerms; ++t) {
    EXPECT_TRUE(fit.fitted[t]) << t;
    EXPECT_NEAR(fit.seconds[t], expected[t], 1e-9 * expected[t]) << t;
    EXPECT_LE(fit.standard_error[t], 1e-6 * expected[t]) << t;
  }
  EXPECT_LT(fit.rms_relative_residual, 1e-9);
}

// The unit is a searched leaf's triangle: its box test (1 ns) and, for the tested share of
// them, a real test (20 ns): 1 + 0.25 * 20 = 6 ns. Travcost is a cell crossed: passing it
// (0.5 ns) and, for the cells searched per cell crossed, a step into one (8 ns):
// 0.5 + 0.5 * 8 = 4.5 ns.
TEST(Calibrate, ConstantsAreRelativeToALeafTriangle) {
  const Calibration calibration =
      calibration_from_measurements(exact_rows(KnownCosts{}), kBuilds, kShares);
  EXPECT_DOUBLE_EQ(calibration.intcost, 1.0);
  EXPECT_NEAR(calibration.nanoseconds_per_unit, 6.0, 1e-9);
  EXPECT_NEAR(calibration.repcost, 3.0 / 6.0, 1e-9);
  EXPECT_NEAR(calibration.travcost, 4.5 / 6.0, 1e-9);
  EXPECT_NEAR(calibration.vertcost, 15.0 / 6.0, 1e-9);
  EXPECT_NEAR(calibration.subcost, 50.0 / 6.0, 1e-9);
  EXPECT_TRUE(calibration.detail.at("unidentified").empty());
  EXPECT_NEAR(calibration.detail.at("per_ray_nanoseconds").get<double>(), 40.0, 1e-6);
  EXPECT_EQ(calibration.detail.at("tested_share").get<double>(), 0.25);
  EXPECT_EQ(calibration.detail.at("searched_per_cell").get<double>(), 0.5);

  // Every triangle tested for real: the unit is a box test and a test; none: a box test
  // (1 ns). No cell searched: Travcost is passing a cell; two searched per cell crossed
  // (rays that go down into cells): two steps and a cell passed.
  const auto with_shares = [](RealRayShares shares) {
    return calibration_from_measurements(exact_rows(KnownCosts{}), kBuilds, shares);
  };
  EXPECT_NEAR(with_shares({1.0, 0.5}).nanoseconds_per_unit, 21.0, 1e-9);
  EXPECT_NEAR(with_shares({0.0, 0.0}).travcost, 0.5, 1e-9);
  EXPECT_NEAR(with_shares({0.0, 2.0}).travcost, 16.5, 1e-9);
}

TEST(Calibrate, UnmeasuredConstantKeepsItsDefaultAndSaysWhy) {
  const AccelParams defaults;
  // No rejections anywhere: repcost cannot be measured.
  Calibration calibration =
      calibration_from_measurements(exact_rows(KnownCosts{}, false), kBuilds, kShares);
  EXPECT_EQ(calibration.repcost, defaults.repcost);
  EXPECT_TRUE(calibration.detail.at("unidentified").contains("repcost"));
  EXPECT_NEAR(calibration.travcost, 4.5 / 6.0, 1e-9);

  // Leaf triangles that only ever come with tests and steps (no leaf whose boxes the rays
  // miss): a box test cannot be told from a test, so the unit is not measured.
  calibration =
      calibration_from_measurements(exact_rows(KnownCosts{}, true, false), kBuilds, kShares);
  EXPECT_EQ(calibration.nanoseconds_per_unit, 0.0);
  EXPECT_EQ(calibration.travcost, defaults.travcost);
  EXPECT_EQ(calibration.detail.at("unidentified").size(), 5u);

  // A step that "saves" time is no timing.
  KnownCosts negative;
  negative.step = -2e-9;
  calibration = calibration_from_measurements(exact_rows(negative), kBuilds, kShares);
  EXPECT_EQ(calibration.travcost, defaults.travcost);
  EXPECT_TRUE(calibration.detail.at("unidentified").contains("travcost"));

  // Every cell crossed searched (none passed by): a cell crossed cannot be told from a step,
  // so Travcost is not measured, and says which timing is missing.
  calibration =
      calibration_from_measurements(exact_rows(KnownCosts{}, true, true, false), kBuilds, kShares);
  EXPECT_EQ(calibration.travcost, defaults.travcost);
  EXPECT_NEAR(calibration.repcost, 3.0 / 6.0, 1e-9);
  EXPECT_EQ(calibration.detail.at("unidentified").size(), 1u);
  EXPECT_NE(
      calibration.detail.at("unidentified").at("travcost").get<std::string>().find("cell crossed"),
      std::string::npos);

  // No build measured: subcost stays.
  calibration = calibration_from_measurements(exact_rows(KnownCosts{}), {}, kShares);
  EXPECT_EQ(calibration.subcost, defaults.subcost);
  EXPECT_TRUE(calibration.detail.at("unidentified").contains("subcost"));

  // Without the unit nothing can be expressed in it: every default, every one named.
  calibration = calibration_from_measurements({}, kBuilds, kShares);
  EXPECT_EQ(calibration.nanoseconds_per_unit, 0.0);
  EXPECT_EQ(to_json(calibration).at("intcost"), defaults.intcost);
  EXPECT_EQ(calibration.vertcost, defaults.vertcost);
  EXPECT_EQ(calibration.detail.at("unidentified").size(), 5u);
}

TEST(Calibrate, NoisyRowsGiveStandardErrors) {
  // Alternating +-2% on the times: the fit still finds every term, with finite errors.
  std::vector<WorkSample> rows = exact_rows(KnownCosts{});
  for (size_t i = 0; i < rows.size(); ++i) rows[i].seconds *= i % 2 ? 1.02 : 0.98;
  const CostFit fit = fit_costs(rows);
  EXPECT_NEAR(fit.rms_relative_residual, 0.02, 0.02);
  for (int t = 0; t < kFitTerms; ++t) {
    EXPECT_TRUE(std::isfinite(fit.standard_error[t])) << t;
    EXPECT_GT(fit.standard_error[t], 0.0) << t;
  }
}

TEST(Calibrate, JsonRoundTrip) {
  Calibration calibration =
      calibration_from_measurements(exact_rows(KnownCosts{}), kBuilds, kShares);
  calibration.vertcost = 7.25;
  const Calibration back = calibration_from_json(to_json(calibration), "memory");
  EXPECT_EQ(to_json(back), to_json(calibration));

  const std::string path = test::temp_path("calibration.json");
  write_json(path, to_json(calibration));
  const Calibration read = read_calibration(path);
  EXPECT_EQ(read.vertcost, 7.25);
  EXPECT_EQ(read.subcost, calibration.subcost);
  EXPECT_EQ(read.nanoseconds_per_unit, calibration.nanoseconds_per_unit);
  std::remove(path.c_str());
}

TEST(Calibrate, WithCalibrationSetsExactlyTheFiveConstants) {
  AccelParams params;
  params.max_granularity = 7;
  params.axis = AxisRule::cost;
  params.sample_every = 3;
  params.max_depth = 9;
  Calibration calibration;
  calibration.intcost = 1.0, calibration.repcost = 0.5, calibration.travcost = 0.25;
  calibration.vertcost = 3.5, calibration.subcost = 11.0;
  json expected = params.to_json();
  for (const char* key : {"intcost", "repcost", "travcost", "vertcost", "subcost"})
    expected[key] = to_json(calibration)[key];
  EXPECT_EQ(with_calibration(params, calibration).to_json(), expected);
}

std::string error_of(const json& in) {
  return test::input_error([&] { calibration_from_json(in, "costs.json"); });
}

TEST(Calibrate, BadCalibrationIsInputErrorNamingTheFile) {
  const json good = {
      {"intcost", 1.0}, {"repcost", 0.2}, {"travcost", 1.0}, {"vertcost", 6.0}, {"subcost", 2.0}};
  EXPECT_EQ(error_of(good), "");
  json missing = good;
  missing.erase("travcost");
  EXPECT_EQ(error_of(missing), "costs.json: \"travcost\" is missing");
  json negative = good;
  negative["repcost"] = -0.5;
  EXPECT_EQ(error_of(negative), "costs.json: \"repcost\" must be a finite number >= 0, not -0.5");
  json nan = good;
  nan["vertcost"] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(error_of(nan), "costs.json: \"vertcost\" must be a finite number >= 0, not NaN");
  json text = good;
  text["subcost"] = "2";
  EXPECT_EQ(error_of(text), "costs.json: \"subcost\" must be a finite number >= 0, not \"2\"");
  json bad_unit = good;
  bad_unit["nanoseconds_per_unit"] = -1;
  EXPECT_EQ(error_of(bad_unit),
            "costs.json: \"nanoseconds_per_unit\" must be a finite number >= 0, not -1");
  EXPECT_EQ(error_of(json::array()), "costs.json: a calibration is a JSON object");

  // Files: NaN is not JSON; a missing file.
  const std::string path = test::temp_path("bad-calibration.json");
  std::ofstream(path) << R"({"intcost": 1, "repcost": NaN})";
  EXPECT_EQ(test::input_error([&] { read_calibration(path); }), path + ": is not valid JSON");
  std::remove(path.c_str());
  EXPECT_EQ(test::input_error([&] { read_calibration(path); }).rfind(path + ": ", 0), 0u);
}

TEST(Calibrate, ShortRealRunMeasuresEveryConstant) {
  CalibrateOptions options;
  // Eighteen timed scenes and seven fitted terms: under the sanitizers, with other tests
  // running beside it, half a second left one run in CI without a unit (a box test's 0.2 ns
  // lost in the noise).
  options.budget_seconds = 1.0;
  const Calibration calibration = calibrate(options);
  const json out = to_json(calibration);
  for (const char* key : {"intcost", "repcost", "travcost", "vertcost", "subcost"}) {
    EXPECT_TRUE(std::isfinite(out[key].get<double>())) << key;
    EXPECT_GT(out[key].get<double>(), 0.0) << key;
  }
  EXPECT_EQ(calibration.intcost, 1.0);
  // The unit is a timing fit: under the sanitizers, beside other tests, a 0.2 ns box test can
  // drown in the noise (twice in CI). Then every constant keeps its default and says why.
  if (calibration.nanoseconds_per_unit == 0.0) {
    EXPECT_EQ(calibration.detail.at("unidentified").size(), 5u);
  }
  // Each synthetic scene made the work it was built for, as the traversal counted it.
  for (const json& design : calibration.detail.at("designs"))
    EXPECT_TRUE(design.at("as_designed").get<bool>()) << design.dump();
  EXPECT_EQ(calibration.detail.at("validation").size(), 2u);
  // Real rays test a share of a searched leaf's triangles for real: more than none, fewer
  // than all (most triangle boxes are missed).
  const double share = calibration.detail.at("tested_share").get<double>();
  EXPECT_GT(share, 0.0);
  EXPECT_LT(share, 1.0);
  // And search some of the cells they cross (the rest are passed by).
  const double searched = calibration.detail.at("searched_per_cell").get<double>();
  EXPECT_GT(searched, 0.0);
  EXPECT_LT(searched, 1.0);
}

TEST(Calibrate, BudgetMustBePositive) {
  CalibrateOptions options;
  options.budget_seconds = 0.0;
  EXPECT_THROW(calibrate(options), UsageError);
  options.budget_seconds = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(calibrate(options), UsageError);
}

}  // namespace
}  // namespace gs
