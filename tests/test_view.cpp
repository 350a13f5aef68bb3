// `gridscope view` (docs/design.md §3) driven by its script flags under Xvfb, as CI would: it
// exits by itself, the screenshot is the window, and the walk a scripted click records is
// the one `trace --walk` records for the same pixel's ray (same sampling pass, same cuts).
// Scripted abuse: no display, no GL 3.3 context, minimising and restoring, a bad
// file opened from the UI, parameters changed and the window closed during a build; the
// viewport shown at the end is compared with `render` of the view --stats reports.
// Skips with a message when xvfb-run is not installed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/scene/camera.h"
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

// Runs `env ENV gridscope args` in a fresh Xvfb display of `screen` (WxHxDEPTH, at least the
// window's size). The status is the program's, kept in a file by a shell inside the display:
// xvfb-run's own is 5 when its clean-up trips over a program that exits at once.
Outcome run_in_xvfb(const std::string& args, const std::string& env = "",
                    const std::string& screen = "1280x800x24") {
  const std::string status_path = temp_path("xvfb_status.txt");
  std::remove(status_path.c_str());
  Outcome outcome = run(args, "env " + env + " xvfb-run -a -s '-screen 0 " + screen +
                                  "' sh -c '\"$0\" \"$@\"; echo $? >" + status_path + "'");
  const std::string status = slurp(status_path);
  outcome.status = status.empty() ? -1 : std::stoi(status);
  return outcome;
}

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
      run_in_xvfb("view builtin:pyramid --size 800x600 --frames 10 --click 0.5,0.5 --walk-out '" +
                  walk_path + "' --screenshot '" + shot + "'");
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
  const Outcome traced = run("trace builtin:pyramid --rays '" + rays + "' --out '" + hits +
                             "' --sample-image " + size + " --camera '" + camera + "' --walk " +
                             std::to_string(y * width + x) + " --walk-out '" + traced_path + "'");
  ASSERT_EQ(traced.status, 0) << traced.err;
  expect_same_cells(walk, read_json(traced_path));
}

// A script file holding `text`.
std::string script_file(const std::string& name, const std::string& text) {
  const std::string path = temp_path(name);
  std::ofstream(path) << text;
  return path;
}

// The viewport (the top-left WxH of the window, W and H from --stats) holds exactly the image
// `render` gives for the view --stats reports (its camera and samples per pixel).
void expect_viewport_is_render(const std::string& window_png, const nlohmann::json& stats,
                               const std::string& structure_flags = "") {
  ASSERT_TRUE(stats.contains("view")) << stats.dump();
  const nlohmann::json& view = stats["view"];
  ASSERT_TRUE(view.at("current").get<bool>()) << "the last frame is not of the current view";
  const int width = view.at("width"), height = view.at("height");
  const std::string expected_png = temp_path("view_expected.png");
  const Outcome rendered =
      run("render '" + stats.at("scene").get<std::string>() + "' --size " + std::to_string(width) +
          "x" + std::to_string(height) + " --camera '" + view.at("camera").get<std::string>() +
          "' --spp " + std::to_string(std::max(view.at("spp").get<int>(), 1)) + " --out '" +
          expected_png + "' " + structure_flags);
  ASSERT_EQ(rendered.status, 0) << rendered.err;
  const gs::test::Png window = gs::test::load_png(window_png);
  const gs::test::Png expected = gs::test::load_png(expected_png);
  ASSERT_GE(window.width, width);
  ASSERT_GE(window.height, height);
  ASSERT_EQ(expected.width, width);
  int differing = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c) differing += window.at(x, y)[c] != expected.at(x, y)[c];
  EXPECT_EQ(differing, 0) << "of " << width << "x" << height << " pixels' channels";
}

TEST(View, NoDisplayExitsOneNamingTheProblem) {
  const Outcome result =
      run("view builtin:pyramid --frames 1", "env -u DISPLAY -u WAYLAND_DISPLAY");
  EXPECT_EQ(result.status, 1);
  EXPECT_NE(result.err.find("OpenGL: could not open a window"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("DISPLAY"), std::string::npos) << result.err;
}

TEST(View, NoOpenGL33ContextExitsOne) {
  if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed: the viewer needs a display";
  // Mesa then offers at most OpenGL 3.0: GLX cannot make the 3.3 core context asked for.
  const Outcome result =
      run_in_xvfb("view builtin:pyramid --frames 1", "MESA_GL_VERSION_OVERRIDE=3.0");
  EXPECT_EQ(result.status, 1);
  // One line of ours (xvfb-run may add its own).
  const size_t line = result.err.find("gridscope: OpenGL: could not open a window (");
  EXPECT_NE(line, std::string::npos) << result.err;
  EXPECT_EQ(result.err.find("gridscope", line + 1), std::string::npos) << result.err;
}

TEST(View, MinimisedThenRestoredAtAnotherSizeShowsThatView) {
  if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed: the viewer needs a display";
  const std::string script = script_file("resize.txt",
                                         "# minimised for a while, then back at another size\n"
                                         "frame 3: resize 0x0\nframe 9: resize 900x640\n");
  const std::string shot = temp_path("resized.png"), stats = temp_path("resized.json");
  const Outcome view =
      run_in_xvfb("view builtin:pyramid --size 800x600 --frames 15 --script '" + script +
                  "' --screenshot '" + shot + "' --stats '" + stats + "'");
  ASSERT_EQ(view.status, 0) << view.err;
  const PngFacts png = png_facts(shot);
  EXPECT_EQ(png.width, 900);
  EXPECT_EQ(png.height, 640);
  const nlohmann::json figures = read_json(stats);
  expect_viewport_is_render(shot, figures);
  // The viewport followed the window: an 800-wide window's is 500 wide (the panel takes 300).
  EXPECT_GT(figures["view"]["width"].get<int>(), 500);
}

TEST(View, ABadFileOpenedFromTheUiIsReportedAndTheSceneKept) {
  if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed: the viewer needs a display";
  const std::string missing = "/nonexistent/missing.obj";
  const std::string script = script_file("open_bad.txt", "frame 2: open " + missing + "\n");
  const std::string shot = temp_path("open_bad.png"), stats = temp_path("open_bad.json");
  const Outcome view =
      run_in_xvfb("view builtin:pyramid --size 640x480 --frames 5 --script '" + script +
                  "' --screenshot '" + shot + "' --stats '" + stats + "'");
  ASSERT_EQ(view.status, 0) << view.err;
  EXPECT_NE(view.err.find(missing), std::string::npos) << view.err;
  const nlohmann::json figures = read_json(stats);
  EXPECT_NE(figures.at("status").get<std::string>().find(missing), std::string::npos);
  EXPECT_EQ(figures.at("scene"), "builtin:pyramid");
  expect_viewport_is_render(shot, figures);
}

TEST(View, ASecondOpenSupersedesTheFirst) {
  if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed: the viewer needs a display";
  const std::string script = script_file(
      "open_twice.txt", "frame 2: open /nonexistent/first.obj\nframe 2: open builtin:lumpy\n");
  const std::string shot = temp_path("open_twice.png"), stats = temp_path("open_twice.json");
  const Outcome view =
      run_in_xvfb("view builtin:pyramid --size 640x480 --frames 3 --script '" + script +
                  "' --screenshot '" + shot + "' --stats '" + stats + "'");
  ASSERT_EQ(view.status, 0) << view.err;
  EXPECT_EQ(view.err.find("first.obj"), std::string::npos) << view.err;
  const nlohmann::json figures = read_json(stats);
  EXPECT_EQ(figures.at("scene"), "builtin:lumpy");
  EXPECT_EQ(figures.at("status"), "");
  expect_viewport_is_render(shot, figures);
}

TEST(View, ParametersChangedDuringTheBuildAreTheFinalFramesOnes) {
  if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed: the viewer needs a display";
  // Frame 1 starts building sphereflake's structure; frame 2 changes it while it is built.
  const std::string script =
      script_file("set.txt", "frame 2: set max-granularity 8\nframe 2: set memory-budget 8M\n");
  const std::string shot = temp_path("set.png"), stats = temp_path("set.json");
  const Outcome view =
      run_in_xvfb("view builtin:sphereflake --size 640x480 --frames 4 --script '" + script +
                  "' --screenshot '" + shot + "' --stats '" + stats + "'");
  ASSERT_EQ(view.status, 0) << view.err;
  const nlohmann::json figures = read_json(stats);
  EXPECT_EQ(figures.at("parameters").at("max_granularity"), 8);
  EXPECT_EQ(figures.at("parameters").at("memory_budget"), 8u << 20);
  EXPECT_GT(figures.at("voxels_over_budget").get<uint64_t>(), 0u);  // the budget bit
  expect_viewport_is_render(shot, figures, "--max-granularity 8 --memory-budget 8M");
}

TEST(View, PacketsSwitchedOffMidwayRenderTheSameImageOneRayAtATime) {
  if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed: the viewer needs a display";
  std::vector<nlohmann::json> runs;
  for (const std::string script_text : {"", "frame 2: set packets off\n"}) {
    const std::string script = script_file("packets.txt", "# packets\n" + script_text);
    const std::string shot = temp_path("packets.png"), stats = temp_path("packets.json");
    const Outcome view =
        run_in_xvfb("view builtin:lumpy --size 640x480 --frames 4 --script '" + script +
                    "' --screenshot '" + shot + "' --stats '" + stats + "'");
    ASSERT_EQ(view.status, 0) << view.err;
    runs.push_back(read_json(stats));
    expect_viewport_is_render(shot, runs.back());
  }
  EXPECT_EQ(runs[0].at("packets"), true);
  EXPECT_GT(runs[0].at("packet_rays").get<uint64_t>(), 0u);
  EXPECT_GT(runs[0].at("packet_active_fraction").get<double>(), 0.0);
  EXPECT_EQ(runs[1].at("packets"), false);
  EXPECT_EQ(runs[1].at("packet_rays").get<uint64_t>(), 0u);
  for (const nlohmann::json& run : runs) EXPECT_GT(run.at("seconds").get<double>(), 0.0);
}

// `wait` holds the script until the view's full-resolution pass is shown; `orbit` turns the
// camera about the pivot (at first the target) keeping the eye's distance, as a drag does.
TEST(View, OrbitAfterEachFullPassRecordsEachPassTime) {
  if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed: the viewer needs a display";
  const std::string script = script_file(
      "orbit.txt", "frame 1: wait\nframe 1: orbit 30\nframe 1: wait\nframe 1: orbit -90\n");
  const std::string shot = temp_path("orbit.png"), stats = temp_path("orbit.json");
  const Outcome view = run_in_xvfb("view --size 640x480 --frames 1 --script '" + script +
                                   "' --screenshot '" + shot + "' --stats '" + stats + "'");
  ASSERT_EQ(view.status, 0) << view.err;
  const nlohmann::json figures = read_json(stats);
  // The default view, the view turned by 30 degrees, then by -60 in all.
  const auto seconds = figures.at("full_pass_seconds").get<std::vector<double>>();
  ASSERT_EQ(seconds.size(), 3u) << figures.dump();
  for (const double s : seconds) EXPECT_GT(s, 0.0);
  const gs::Camera start = gs::parse_camera("eye=3.2,-4.2,2.2;target=0,0,0.35;up=0,0,1;fov=40");
  const gs::Camera end = gs::parse_camera(figures.at("view").at("camera").get<std::string>());
  const glm::vec3 from = start.eye - start.target, to = end.eye - end.target;
  EXPECT_NEAR(glm::length(to), glm::length(from), 1e-4f);
  EXPECT_NEAR(to.z, from.z, 1e-4f);  // a turn about the up axis (z)
  const float turned = std::atan2(to.y, to.x) - std::atan2(from.y, from.x);
  EXPECT_NEAR(std::abs(std::remainder(turned, 2.0f * 3.14159265f)), glm::radians(60.0f), 1e-3f);
  expect_viewport_is_render(shot, figures);
}

TEST(View, ClosingDuringABigBuildExitsZero) {
  if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed: the viewer needs a display";
  // Cutting voxels into up to 4096 cells makes sphereflake's build take seconds; the window
  // closes a frame after it starts, long before the first full-resolution pass.
  const std::string script = script_file("close.txt", "frame 2: close\n");
  const std::string stats = temp_path("close.json");
  const Outcome view = run_in_xvfb("view builtin:sphereflake --max-granularity 4096 --script '" +
                                   script + "' --stats '" + stats + "'");
  ASSERT_EQ(view.status, 0) << view.err;
  EXPECT_LT(read_json(stats).at("view").at("pass").get<int>(), 2);
}

TEST(View, BadScriptsExitOneNamingTheLine) {
  const Outcome missing = run("view builtin:pyramid --script /nonexistent/script.txt");
  EXPECT_EQ(missing.status, 1);
  EXPECT_NE(missing.err.find("/nonexistent/script.txt"), std::string::npos) << missing.err;
  for (const std::string line :
       {"frame 0: close", "frame 2 close", "frame 2: jump", "frame 2: resize 0x5",
        "frame 2: resize 10x99999", "frame 2: set max-granularity 0", "frame 2: set colour red",
        "frame 2: set accel nothing", "frame 2: set packets maybe", "frame 2: orbit left",
        "frame 2: orbit 400", "frame 2: wait now", "frame 2: open", "frame two: close",
        "frame 2: set compare accel=nothing", "frame 2: set compare vertcost",
        "frame 2: set compare-view sideways"}) {
    const std::string script = script_file("bad_script.txt", "# fine\n\n" + line + "\n");
    const Outcome bad = run("view builtin:pyramid --script '" + script + "'");
    EXPECT_EQ(bad.status, 1) << line;
    EXPECT_NE(bad.err.find(script + ":3: "), std::string::npos) << line << ": " << bad.err;
  }
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

// The window's pixels of the viewport at (x, y) equal frame `index` of a --compare shot.
int differing_channels(const gs::test::Png& window, const gs::test::Png& shot, int width, int index,
                       int x0, int x1, int y0, int y1) {
  int differing = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x)
      for (int c = 0; c < 3; ++c)
        differing += window.at(x, y)[c] != shot.at(index * width + x, y)[c];
  return differing;
}

// Once the view has reached its last pass, later UI frames would look as the window does and
// are not drawn (Mesa's CPU renderer would spend the cores the renderer traces on); the
// window still shows the view: a screenshot taken after 60 such frames is the frame `shot`
// draws for the same view.
TEST(View, FramesThatWouldLookTheSameAreNotDrawnAndTheWindowStillShowsTheView) {
  if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed: the viewer needs a display";
  const std::string png = temp_path("view_idle.png"), stats_path = temp_path("view_idle.json");
  const std::string flags = "builtin:pyramid --accel bvh";
  const Outcome view = run_in_xvfb("view " + flags + " --size 800x600 --max-spp 1 --frames 60 " +
                                   "--screenshot '" + png + "' --stats '" + stats_path + "'");
  ASSERT_EQ(view.status, 0) << view.err;
  const nlohmann::json stats = read_json(stats_path);
  const nlohmann::json& frames = stats.at("window_frames");
  EXPECT_EQ(frames.at("built"), 60);
  EXPECT_GE(frames.at("drawn").get<int>(), 2) << "the coarse and the full-resolution pass";
  EXPECT_LT(frames.at("drawn").get<int>(), 20) << frames.dump();
  const int width = stats.at("view").at("width"), height = stats.at("view").at("height");
  const std::string shot_png = temp_path("view_idle_shot.png");
  const Outcome shot =
      run("shot " + flags + " --size " + std::to_string(width) + "x" + std::to_string(height) +
          " --camera '" + stats.at("view").at("camera").get<std::string>() + "' --out '" +
          shot_png + "'");
  ASSERT_EQ(shot.status, 0) << shot.err;
  const gs::test::Png window = gs::test::load_png(png), frame = gs::test::load_png(shot_png);
  ASSERT_EQ(frame.width, width);
  EXPECT_EQ(differing_channels(window, frame, width, 0, 0, width, 0, height), 0);
}

// A/B of two structures built up front (their per-pixel counts are the same every run), one
// sample per pixel: the viewer's split viewport shows A's heatmap left of the divider and B's
// right of it, on the scale `shot --compare` uses for the same view; difference mode is
// shot's third frame.
void expect_viewer_compare_is_shot(const std::string& mode) {
  const std::string png = temp_path("view_ab.png"), stats_path = temp_path("view_ab.json");
  const std::string script =
      script_file("view_ab.txt", "frame 1: set compare-view " + mode + "\nframe 2: wait\n");
  const std::string side_a = "builtin:pyramid --accel bvh --packets off --overlay heat:tests";
  const Outcome view =
      run_in_xvfb("view " + side_a +
                  " --size 800x600 --max-spp 1 --compare accel=uniform "
                  "--frames 3 --script '" +
                  script + "' --screenshot '" + png + "' --stats '" + stats_path + "'");
  ASSERT_EQ(view.status, 0) << view.err;
  const nlohmann::json stats = read_json(stats_path);
  const nlohmann::json& a = stats.at("view");
  const nlohmann::json& b = stats.at("compare").at("view");
  ASSERT_TRUE(stats.at("compare").at("shown").get<bool>()) << stats.dump();
  EXPECT_EQ(stats.at("compare").at("mode"), mode);
  EXPECT_EQ(a.at("spp"), 1);
  EXPECT_EQ(b.at("spp"), 1);
  EXPECT_EQ(a.at("camera"), b.at("camera"));
  const int width = a.at("width"), height = a.at("height");
  const std::string shot_png = temp_path("view_ab_shot.png");
  const Outcome shot = run("shot " + side_a + " --compare accel=uniform --size " +
                           std::to_string(width) + "x" + std::to_string(height) + " --camera '" +
                           a.at("camera").get<std::string>() + "' --out '" + shot_png + "'");
  ASSERT_EQ(shot.status, 0) << shot.err;
  const gs::test::Png window = gs::test::load_png(png), frames = gs::test::load_png(shot_png);
  ASSERT_EQ(frames.width, 3 * width);
  constexpr int kLabels = 30;  // rows under the labels at the viewport's top
  if (mode == "split") {
    const int divider = width / 2;
    EXPECT_EQ(differing_channels(window, frames, width, 0, 0, divider - 3, kLabels, height), 0);
    EXPECT_EQ(differing_channels(window, frames, width, 1, divider + 3, width, kLabels, height), 0);
    // A and B differ in places, so the halves test what each side drew.
    int a_differs_from_b = 0;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x)
        a_differs_from_b += frames.at(x, y)[0] != frames.at(width + x, y)[0];
    EXPECT_GT(a_differs_from_b, 0);
  } else {
    EXPECT_EQ(differing_channels(window, frames, width, 2, 0, width, kLabels, height), 0);
  }
}

TEST(View, CompareSplitShowsEachSidesHeatmapOnOneScale) {
  if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed: the viewer needs a display";
  expect_viewer_compare_is_shot("split");
}

TEST(View, CompareDifferenceIsShotsDifferenceFrame) {
  if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed: the viewer needs a display";
  expect_viewer_compare_is_shot("difference");
}

TEST(View, CompareFlagsBForAnotherStructureAreUsageErrors) {
  // grid1d reads no --density: B's flags must suit B's structure.
  for (const char* spec : {"density=3", "accel=nothing", "vertcost", "accel=zero"}) {
    const Outcome result = run("view --compare '" + std::string(spec) + "'");
    EXPECT_EQ(result.status, 2) << spec;
    EXPECT_NE(result.err.find("--compare"), std::string::npos) << result.err;
  }
}

// The layout (app/view/layout.h) as --stats's "layout" describes the last frame: the
// viewport's rectangle and every ImGui window's rectangle, content and visible sizes.

struct Box {
  double x, y, w, h;
};

Box box(const nlohmann::json& rect) {
  return {rect.at("x"), rect.at("y"), rect.at("w"), rect.at("h")};
}

double overlap(const Box& a, const Box& b) {
  const double w = std::min(a.x + a.w, b.x + b.w) - std::max(a.x, b.x);
  const double h = std::min(a.y + a.h, b.y + b.h) - std::max(a.y, b.y);
  return w > 0 && h > 0 ? w * h : 0.0;
}

// The window named `name` in the layout, or null.
const nlohmann::json* find_window(const nlohmann::json& layout, const std::string& name) {
  for (const nlohmann::json& window : layout.at("windows"))
    if (window.at("name") == name) return &window;
  return nullptr;
}

// No window's content is cut off, and every top-level window lies inside the display (child
// windows may be scrolled out of their parent's view).
void expect_nothing_clipped(const nlohmann::json& layout) {
  const double width = layout.at("display").at("w"), height = layout.at("display").at("h");
  ASSERT_FALSE(layout.at("windows").empty());
  for (const nlohmann::json& window : layout.at("windows")) {
    EXPECT_FALSE(window.at("clipped").get<bool>()) << window.dump();
    if (window.at("parent") != "") continue;
    const Box r = box(window.at("rect"));
    EXPECT_GE(r.x, 0.0) << window.dump();
    EXPECT_GE(r.y, 0.0) << window.dump();
    EXPECT_LE(r.x + r.w, width) << window.dump();
    EXPECT_LE(r.y + r.h, height) << window.dump();
  }
}

// The viewport, the two splitter bars and the two panels cover the display without
// overlapping.
void expect_tiled(const nlohmann::json& layout) {
  std::vector<Box> parts = {box(layout.at("viewport"))};
  for (const std::string name :
       {"controls", "statistics and inspector", "##right splitter", "##bottom splitter"}) {
    const nlohmann::json* window = find_window(layout, name);
    ASSERT_NE(window, nullptr) << name;
    parts.push_back(box(window->at("rect")));
  }
  double area = 0;
  for (size_t i = 0; i < parts.size(); ++i) {
    area += parts[i].w * parts[i].h;
    for (size_t j = i + 1; j < parts.size(); ++j)
      EXPECT_EQ(overlap(parts[i], parts[j]), 0.0) << i << " and " << j;
  }
  const double width = layout.at("display").at("w"), height = layout.at("display").at("h");
  EXPECT_NEAR(area, width * height, 1.0);
}

// A click's run of lumpy at WIDTHxHEIGHT with `script` (if any) and `flags`: the stats.
nlohmann::json clicked_run(int width, int height, const std::string& script_text = "",
                           const std::string& flags = "") {
  const std::string size = std::to_string(width) + "x" + std::to_string(height);
  const std::string stats = temp_path("layout_" + size + ".json");
  std::string args = "view builtin:lumpy --size " + size +
                     " --frames 10 --click 0.5,0.5 --stats '" + stats + "' " + flags;
  if (!script_text.empty()) args += " --script '" + script_file("layout.txt", script_text) + "'";
  const Outcome view = run_in_xvfb(args, "", "1920x1080x24");
  EXPECT_EQ(view.status, 0) << view.err;
  return read_json(stats);
}

TEST(View, LayoutFitsEachWindowSizeWithNothingClipped) {
  if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed: the viewer needs a display";
  for (const auto& [width, height] : {std::pair{1024, 640}, {1280, 800}, {1920, 1080}}) {
    SCOPED_TRACE(std::to_string(width) + "x" + std::to_string(height));
    const nlohmann::json figures = clicked_run(width, height);
    ASSERT_TRUE(figures.contains("layout")) << figures.dump();
    const nlohmann::json& layout = figures["layout"];
    EXPECT_EQ(layout.at("display").at("w"), width);
    EXPECT_EQ(layout.at("display").at("h"), height);
    expect_nothing_clipped(layout);
    expect_tiled(layout);
    // The render is the viewport's size, and the inspector shows the clicked walk.
    EXPECT_EQ(figures.at("view").at("width"), int(layout.at("viewport").at("w").get<double>()));
    EXPECT_EQ(figures.at("view").at("height"), int(layout.at("viewport").at("h").get<double>()));
    const std::string dump = layout.dump();  // the cost chart's child window (ImGui names it
    EXPECT_NE(dump.find("statistics and inspector/cost_"), std::string::npos);  // NAME_ID)
    EXPECT_EQ(find_window(layout, "mouse and keyboard"), nullptr);              // help closed
  }
}

TEST(View, LayoutOtherTabsFitTheSmallestWindow) {
  if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed: the viewer needs a display";
  for (const std::string tab : {"statistics", "states"}) {
    SCOPED_TRACE(tab);
    const nlohmann::json figures = clicked_run(1024, 640, "frame 2: tab " + tab + "\n");
    expect_nothing_clipped(figures.at("layout"));
    expect_tiled(figures.at("layout"));
  }
}

TEST(View, LayoutSplitterDragsResizeTheViewportAndTheRender) {
  if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed: the viewer needs a display";
  // At 1280x800 the panels take 30%: 384 on the right, 240 below, each beyond a 6-unit bar.
  const nlohmann::json figures = clicked_run(
      1280, 800, "frame 3: drag-splitter right 100\nframe 3: drag-splitter bottom -50\n");
  const nlohmann::json& layout = figures.at("layout");
  EXPECT_EQ(layout.at("viewport").at("w"), 1280 - 384 - 6 + 100);
  EXPECT_EQ(layout.at("viewport").at("h"), 800 - 240 - 6 - 50);
  EXPECT_EQ(figures.at("view").at("width"), 990);
  EXPECT_EQ(figures.at("view").at("height"), 504);
  EXPECT_TRUE(figures.at("view").at("current").get<bool>());
  expect_nothing_clipped(layout);
  expect_tiled(layout);
}

TEST(View, LayoutSplittersDraggedPastTheLimitsLeaveThePanelsTheirMinimums) {
  if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed: the viewer needs a display";
  // The heatmap's controls are the controls panel's widest.
  const nlohmann::json figures = clicked_run(
      1024, 640, "frame 2: drag-splitter right 1000\nframe 2: drag-splitter bottom 1000\n",
      "--overlay heat:tests,walk");
  const nlohmann::json& layout = figures.at("layout");
  EXPECT_EQ(find_window(layout, "controls")->at("rect").at("w"), 280);
  EXPECT_EQ(find_window(layout, "statistics and inspector")->at("rect").at("h"), 180);
  EXPECT_EQ(figures.at("view").at("width"), 1024 - 280 - 6);
  EXPECT_EQ(figures.at("view").at("height"), 640 - 180 - 6);
  expect_nothing_clipped(layout);
  expect_tiled(layout);
}

TEST(View, LayoutHelpOverlayOpensOnItsKeyInsideTheWindow) {
  if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed: the viewer needs a display";
  const nlohmann::json figures = clicked_run(1024, 640, "frame 2: key F1\n");
  const nlohmann::json& layout = figures.at("layout");
  const nlohmann::json* help = find_window(layout, "mouse and keyboard");
  ASSERT_NE(help, nullptr) << layout.dump();
  EXPECT_GT(help->at("content").at("h").get<double>(), 200.0);  // the list of controls
  expect_nothing_clipped(layout);
}

TEST(View, LayoutWithAComparisonFitsTheSmallestWindow) {
  if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed: the viewer needs a display";
  // The A/B section (spec, views, the totals table) in the narrowest controls panel.
  const nlohmann::json figures =
      clicked_run(1024, 640, "", "--compare accel=bvh --overlay heat:tests --packets off");
  ASSERT_FALSE(figures.at("compare").is_null()) << figures.dump();
  EXPECT_TRUE(figures.at("compare").at("shown").get<bool>());
  expect_nothing_clipped(figures.at("layout"));
}

// The build progress bar (app/view/build_progress.h) over a build longer than half a second,
// and the build's figures --stats reports.
TEST(View, ALongBuildShowsTheProgressBarAndItsFiguresAreTheStructures) {
  if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed: the viewer needs a display";
  // Cuts that cost next to nothing against tests, into up to 4096 cells: the first image's
  // rays (at the default window size) build sphereflake's grid for seconds (2.8 s on this
  // project's 2-core machine, 50,000 voxels built, 600 MB).
  const std::string stats = temp_path("progress.json");
  const Outcome view = run_in_xvfb(
      "view builtin:sphereflake --max-granularity 4096 --subcost 0.001 --intcost 1000 "
      "--frames 2 --stats '" +
      stats + "'");
  ASSERT_EQ(view.status, 0) << view.err;
  const nlohmann::json figures = read_json(stats);
  const nlohmann::json& progress = figures.at("build_progress");
  const nlohmann::json& build = progress.at("build");
  const nlohmann::json& ended = build.at("figures");
  EXPECT_EQ(build.at("structure"), "grid1d");
  EXPECT_EQ(build.at("building"), false);  // ended with the first full-resolution pass
  // The sampling pass traces one ray per 8x8 block of the view.
  const int width = figures.at("view").at("width"), height = figures.at("view").at("height");
  const auto sample_rays = uint64_t((width + 7) / 8 * ((height + 7) / 8));
  EXPECT_EQ(ended.at("sample_rays"), sample_rays);
  EXPECT_EQ(ended.at("sample_rays_traced"), sample_rays);
  // The build ends as the full-resolution pass is published, so that pass's frame carries its
  // final figures, taken with the frame's statistics; a later pass only adds voxels.
  const nlohmann::json& at_frame = progress.at("frame");
  EXPECT_EQ(at_frame.at("voxels_subdivided"), figures.at("voxels_subdivided"));
  for (const char* figure : {"voxels_built", "voxels_subdivided", "triangles_sorted"}) {
    if (figures.at("view").at("pass") == 2)
      EXPECT_EQ(at_frame.at(figure), ended.at(figure)) << figure;
    else
      EXPECT_GE(at_frame.at(figure).get<uint64_t>(), ended.at(figure).get<uint64_t>()) << figure;
  }
  EXPECT_GT(ended.at("voxels_subdivided").get<uint64_t>(), 0u);
  EXPECT_GE(ended.at("voxels_built").get<uint64_t>(),
            ended.at("voxels_subdivided").get<uint64_t>());

  // The UI draws at least 30 frames a second: a build under half a second shows no bar, one
  // over a second shows it. How long this one takes depends on the machine's cores.
  const double seconds = build.at("seconds");
  if (seconds < 0.5) {
    EXPECT_EQ(progress.at("bar_shown"), false);
  }
  if (seconds < 1.0) GTEST_SKIP() << "built in " << seconds << " s: too quick to check the bar";
  ASSERT_EQ(progress.at("bar_shown"), true) << figures.dump();
  const nlohmann::json& shown = progress.at("bar_last").at("figures");
  EXPECT_GT(progress.at("bar_last").at("seconds").get<double>(), 0.5);
  EXPECT_EQ(shown.at("sample_rays"), sample_rays);
  // The bar showed the build under way: no more than it came to.
  for (const char* figure : {"sample_rays_traced", "voxels_built", "voxels_subdivided"})
    EXPECT_LE(shown.at(figure).get<uint64_t>(), ended.at(figure).get<uint64_t>()) << figure;
}

// Lumpy's close-up, the viewer's default, clicked in the middle: the walk shows in its own
// colour over the walls of the voxels it crossed (the default overlays), and the log says
// how many walls that is. A script's `set overlay` with a depth range replaces them and the
// log reports the range; without a click there is no walk to draw.
TEST(View, DefaultViewShowsTheClickedWalkAndScriptsSetOverlays) {
  if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed: the viewer needs a display";
  const std::string shot = temp_path("view_default_walk.png");
  const Outcome view =
      run_in_xvfb("view --size 960x640 --frames 10 --click 0.5,0.5 --screenshot '" + shot + "'");
  ASSERT_EQ(view.status, 0) << view.err;
  EXPECT_GT(gs::test::walk_pixels(gs::test::load_png(shot)), 100);
  EXPECT_NE(view.err.find("gridscope view: overlays: cells: "), std::string::npos) << view.err;
  EXPECT_EQ(view.err.find("showing"), std::string::npos) << "near the walk, nothing capped";

  const std::string script =
      script_file("overlay_depth.txt", "frame 1: set overlay cells,depth:1-2\n");
  const std::string ranged = temp_path("view_depth_walk.png");
  const Outcome set = run_in_xvfb("view --size 960x640 --frames 10 --click 0.5,0.5 --script '" +
                                  script + "' --screenshot '" + ranged + "'");
  ASSERT_EQ(set.status, 0) << set.err;
  EXPECT_NE(set.err.find("walls, levels 1-2"), std::string::npos) << set.err;
  EXPECT_GT(gs::test::walk_pixels(gs::test::load_png(ranged)), 100);  // a click shows the walk

  const std::string unclicked = temp_path("view_depth_nowalk.png");
  const Outcome no_click = run_in_xvfb("view --size 960x640 --frames 10 --script '" + script +
                                       "' --screenshot '" + unclicked + "'");
  ASSERT_EQ(no_click.status, 0) << no_click.err;
  EXPECT_EQ(gs::test::walk_pixels(gs::test::load_png(unclicked)), 0);
}

TEST(View, BadOverlayStepsExitOneNamingTheLine) {
  for (const std::string line :
       {"frame 2: set overlay cells,depth:3-1", "frame 2: set overlay near-walk",
        "frame 2: set overlay cells,bogus"}) {
    const std::string script = script_file("bad_overlay.txt", "# fine\n\n" + line + "\n");
    const Outcome bad = run("view builtin:pyramid --script '" + script + "'");
    EXPECT_EQ(bad.status, 1) << line;
    EXPECT_NE(bad.err.find(script + ":3: set overlay '"), std::string::npos)
        << line << ": " << bad.err;
  }
}

TEST(View, LayoutFollowsScriptedResizesWithNothingClipped) {
  if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed: the viewer needs a display";
  // From the default 1280x800 down to the smallest supported window, or up to full HD, as a
  // person dragging the window's corner would: the last frame's layout fits the new size.
  for (const auto& [width, height] : {std::pair{1024, 640}, {1920, 1080}}) {
    const std::string size = std::to_string(width) + "x" + std::to_string(height);
    SCOPED_TRACE(size);
    const std::string stats = temp_path("resized_layout.json");
    const std::string script =
        script_file("resize_layout.txt", "frame 3: resize " + size + "\nframe 4: wait\n");
    const Outcome view = run_in_xvfb(
        "view builtin:pyramid --frames 6 --script '" + script + "' --stats '" + stats + "'", "",
        "1920x1080x24");
    ASSERT_EQ(view.status, 0) << view.err;
    const nlohmann::json layout = read_json(stats).at("layout");
    EXPECT_EQ(layout.at("display").at("w"), width);
    EXPECT_EQ(layout.at("display").at("h"), height);
    expect_nothing_clipped(layout);
    expect_tiled(layout);
  }
}

}  // namespace
