// `gridscope view` (DESIGN.md §3) driven by its script flags under Xvfb, as CI would: it
// exits by itself, the screenshot is the window, and the walk a scripted click records is
// the one `trace --walk` records for the same pixel's ray (same sampling pass, same cuts).
// Skips with a message when xvfb-run is not installed.
#include <gtest/gtest.h>

#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string>

#include "core/camera.h"
#include "tests/test_util.h"

namespace {

using gs::test::temp_path;

using gs::test::slurp;
using Outcome = gs::test::CommandOutcome;

// Runs `prefix gridscope args` (a time limit keeps a hung window from stalling the suite).
Outcome run(const std::string& args, const std::string& prefix = "") {
  return gs::test::run_gridscope(args, prefix);
}

bool have_xvfb() { return std::system("command -v xvfb-run >/dev/null 2>&1") == 0; }

const std::string kXvfb = "xvfb-run -a -s '-screen 0 1280x800x24'";

nlohmann::json read_json(const std::string& path) {
  const std::string text = slurp(path);
  return text.empty() ? nlohmann::json() : nlohmann::json::parse(text);
}

// The PNG's size and whether all its pixels are equal.
struct PngFacts {
  int width = 0, height = 0;
  bool uniform = true;
};

PngFacts png_facts(const std::string& path) {
  const gs::test::Png png = gs::test::load_png(path);
  PngFacts facts{png.width, png.height, true};
  for (size_t i = 4; i < png.rgba.size() && facts.uniform; ++i)
    facts.uniform = png.rgba[i] == png.rgba[i % 4];
  return facts;
}

void expect_same_cells(const nlohmann::json& viewer, const nlohmann::json& traced) {
  ASSERT_FALSE(viewer.at("cells").empty());
  EXPECT_GE(viewer.at("hit").at("id").get<int>(), 0);  // the centre of the view is on the pyramid
  ASSERT_EQ(viewer.at("cells").size(), traced.at("cells").size());
  for (size_t i = 0; i < viewer["cells"].size(); ++i) {
    const nlohmann::json& a = viewer["cells"][i];
    const nlohmann::json& b = traced["cells"][i];
    EXPECT_EQ(a.at("lo"), b.at("lo")) << "cell " << i;
    EXPECT_EQ(a.at("hi"), b.at("hi")) << "cell " << i;
    EXPECT_EQ(a.at("hit"), b.at("hit")) << "cell " << i;
    EXPECT_EQ(a.at("depth"), b.at("depth")) << "cell " << i;
  }
  EXPECT_EQ(viewer.at("hit"), traced.at("hit"));
}

TEST(View, ScriptedClickRecordsTheWalkTraceRecords) {
  if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed: the viewer needs a display";
  const std::string walk_path = temp_path("view_walk.json"), shot = temp_path("view_shot.png");
  const Outcome view =
      run("view builtin:pyramid --size 800x600 --frames 10 --click 0.5,0.5 --walk-out '" +
              walk_path + "' --screenshot '" + shot + "'",
          kXvfb);
  ASSERT_EQ(view.status, 0) << view.err;

  const PngFacts png = png_facts(shot);
  EXPECT_EQ(png.width, 800);
  EXPECT_EQ(png.height, 600);
  EXPECT_FALSE(png.uniform);

  const nlohmann::json walk = read_json(walk_path);
  ASSERT_TRUE(walk.contains("view")) << walk_path;
  const int width = walk["view"]["width"], height = walk["view"]["height"];
  const int x = walk["view"]["pixel"][0], y = walk["view"]["pixel"][1];
  const std::string camera = walk["view"]["camera"];
  EXPECT_EQ(x, int(0.5 * width));
  EXPECT_EQ(y, int(0.5 * height));

  // The walk's ray is the primary ray of the clicked pixel.
  const gs::Ray ray = gs::parse_camera(camera).primary_ray(x, y, width, height);
  for (int a = 0; a < 3; ++a) {
    EXPECT_EQ(float(walk["ray"]["origin"][a].get<double>()), ray.origin[a]);
    EXPECT_EQ(float(walk["ray"]["dir"][a].get<double>()), ray.dir[a]);
  }

  // The same pixel's ray traced from a ray file of the viewport, with the same sampling pass.
  const std::string size = std::to_string(width) + "x" + std::to_string(height);
  const std::string rays = temp_path("view.rays"), hits = temp_path("view.hits"),
                    traced_path = temp_path("view_trace_walk.json");
  const Outcome made = run("rays builtin:pyramid --size " + size + " --camera '" + camera +
                           "' --out '" + rays + "'");
  ASSERT_EQ(made.status, 0) << made.err;
  const Outcome traced =
      run("trace builtin:pyramid --rays '" + rays + "' --out '" + hits + "' --sample-image " +
          size + " --walk " + std::to_string(y * width + x) + " --walk-out '" + traced_path + "'");
  ASSERT_EQ(traced.status, 0) << traced.err;
  expect_same_cells(walk, read_json(traced_path));
}

TEST(View, MissingSceneExitsOneNamingIt) {
  const Outcome result = run("view /nonexistent.obj");
  EXPECT_EQ(result.status, 1);
  EXPECT_NE(result.err.find("/nonexistent.obj"), std::string::npos) << result.err;
}

TEST(View, ClickOutsideTheViewportIsAUsageError) {
  const Outcome result = run("view --click 2,2");
  EXPECT_EQ(result.status, 2);
  EXPECT_NE(result.err.find("--click"), std::string::npos) << result.err;
}

}  // namespace
