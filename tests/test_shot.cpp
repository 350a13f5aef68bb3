// `gridscope shot` (docs/design.md §3) driven as a user would, checked by its pixels: without
// overlays it is `render`'s image exactly; each overlay changes the pixels where what it
// draws projects and leaves the others alone; bad input gives the promised exit status.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/render/compare.h"
#include "tests/test_util.h"

namespace {

using gs::test::temp_path;

using gs::test::load_png;
using gs::test::Png;
using gs::test::slurp;
using Outcome = gs::test::CommandOutcome;

Outcome run(const std::string& args) { return gs::test::run_gridscope(args); }

bool same_at(const Png& a, const Png& b, int x, int y) {
  return std::equal(a.at(x, y), a.at(x, y) + 4, b.at(x, y));
}

Png image_of(const std::string& command, const std::string& name, const std::string& args) {
  const std::string path = temp_path(name);
  const Outcome result = run(command + " " + args + " --out '" + path + "'");
  EXPECT_EQ(result.status, 0) << result.err;
  return load_png(path);
}

// The pyramid's box is [-1, 1]^3; this camera looks straight down -z at its centre.
constexpr int kSide = 201;
constexpr double kEyeZ = 5.0, kFov = 40.0;
const std::string kTopView =
    "builtin:pyramid --size 201x201 --camera "
    "'eye=0,0,5;target=0,0,0;up=0,1,0;fov=40'";

// Where the top view puts world point (x, y, z): image column and row (pixel centres at
// integers), as Camera::primary_ray shoots them.
std::pair<double, double> project(double x, double y, double z) {
  const double half = std::tan(kFov * M_PI / 360.0) * (kEyeZ - z);
  return {(x / half + 1.0) / 2.0 * kSide - 0.5, (1.0 - y / half) / 2.0 * kSide - 0.5};
}

// Does any pixel within `radius` of (x, y) differ between the two images?
bool changed_near(const Png& a, const Png& b, double x, double y, int radius) {
  for (int py = int(std::lround(y)) - radius; py <= int(std::lround(y)) + radius; ++py)
    for (int px = int(std::lround(x)) - radius; px <= int(std::lround(x)) + radius; ++px)
      if (px >= 0 && py >= 0 && px < a.width && py < a.height && !same_at(a, b, px, py))
        return true;
  return false;
}

TEST(Shot, WithoutOverlaysEqualsRender) {
  const std::string args = "builtin:lumpy --size 160x120 --spp 2";
  const Png shot = image_of("shot", "plain_shot.png", args);
  const Png render = image_of("render", "plain_render.png", args);
  ASSERT_EQ(shot.width, 160);
  ASSERT_EQ(shot.height, 120);
  EXPECT_EQ(shot.rgba, render.rgba);
}

TEST(Shot, CellsOverlayDrawsTheRootWall) {
  // Granularity 2 with depth cap 1 and alternating axes: one cut, the root at x = 0 (the
  // render's stats confirm one subdivided voxel), so the only inner wall is the plane x = 0.
  const std::string structure = " --max-granularity 2 --max-depth 1 --axis alternate";
  const std::string stats = temp_path("cells_stats.json");
  image_of("render", "cells_render.png", kTopView + structure + " --stats '" + stats + "'");
  ASSERT_EQ(nlohmann::json::parse(slurp(stats)).at("voxels_subdivided"), 1) << slurp(stats);

  const Png plain = image_of("shot", "cells_plain.png", kTopView + structure);
  const Png cells = image_of("shot", "cells.png", kTopView + structure + " --overlay cells");
  ASSERT_EQ(cells.width, kSide);
  // The wall's top edge (x = 0, z = 1) lies on or above every surface: visible along its
  // whole projection, the image's middle column.
  for (const double y : {-0.6, 0.0, 0.5}) {
    const auto [px, py] = project(0.0, y, 1.0);
    EXPECT_TRUE(changed_near(cells, plain, px, py, 1)) << "wall at y = " << y;
  }
  // Away from the wall and from the scene box's edges (which the overlay also outlines).
  for (const double x : {-0.4, 0.4}) {
    const auto [px, py] = project(x, 0.3, 1.0);
    EXPECT_FALSE(changed_near(cells, plain, px, py, 2)) << "x = " << x;
  }
}

TEST(Shot, WalkIsDrawnAtItsPixel) {
  const Png plain = image_of("shot", "walk_plain.png", kTopView);
  const Png walk = image_of("shot", "walk.png", kTopView + " --overlay walk --pixel 120,80");
  ASSERT_EQ(walk.width, kSide);
  EXPECT_TRUE(changed_near(walk, plain, 120, 80, 3));
  // Outside the scene box's projection nothing of the walk can appear.
  EXPECT_FALSE(changed_near(walk, plain, 5, 5, 4));
  EXPECT_FALSE(changed_near(walk, plain, 195, 195, 4));
}

TEST(Shot, HeatReplacesTheShadedImage) {
  const Png plain = image_of("shot", "heat_plain.png", kTopView);
  const Png heat = image_of("shot", "heat.png", kTopView + " --overlay heat:steps");
  ASSERT_EQ(heat.width, kSide);
  // Background pixels take turbo's colour for their count, not the background colour, and
  // shaded grey (r = g = b) pixels become coloured ones.
  EXPECT_FALSE(same_at(heat, plain, 2, 2));
  int grey = 0;
  for (size_t i = 0; i < heat.rgba.size(); i += 4)
    grey += heat.rgba[i] == heat.rgba[i + 1] && heat.rgba[i + 1] == heat.rgba[i + 2];
  EXPECT_LT(grey, int(heat.rgba.size() / 4) / 100);
}

TEST(Shot, HeatOfALazyBuildIsTheSameEveryRun) {
  // Rendered on one thread, the lazy build's order and so every pixel's count is fixed.
  const std::string args = "builtin:lumpy --size 96x72 --overlay heat:tests";
  const Png first = image_of("shot", "heat_run1.png", args);
  for (int run = 2; run <= 3; ++run)
    EXPECT_EQ(image_of("shot", "heat_run" + std::to_string(run) + ".png", args).rgba, first.rgba)
        << "run " << run;
}

TEST(Shot, UiChangesOnlyThePanel) {
  const std::string args = "builtin:pyramid --size 640x480";
  const Png plain = image_of("shot", "ui_plain.png", args);
  const Png ui = image_of("shot", "ui.png", args + " --ui");
  ASSERT_EQ(ui.width, 640);
  int x0 = ui.width, y0 = ui.height, x1 = -1, y1 = -1, changed = 0;
  for (int y = 0; y < ui.height; ++y)
    for (int x = 0; x < ui.width; ++x)
      if (!same_at(ui, plain, x, y)) {
        x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
        ++changed;
      }
  ASSERT_GT(changed, 0);
  // One panel at the top-left corner: the changes form a nearly solid rectangle there,
  // and the rest of the frame is the plain shot.
  EXPECT_LE(x0, 12);
  EXPECT_LE(y0, 12);
  EXPECT_LT(x1, ui.width / 2);
  EXPECT_LT(y1, ui.height - 10);
  EXPECT_GT(changed, (x1 - x0 + 1) * (y1 - y0 + 1) * 9 / 10);
}

TEST(Shot, BadInput) {
  const std::string out = " --out '" + temp_path("bad.png") + "'";
  Outcome r = run("shot builtin:pyramid --overlay cells,bogus" + out);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("bogus"), std::string::npos) << r.err;
  r = run("shot builtin:pyramid --size 40x30 --overlay walk --pixel 40,0" + out);
  EXPECT_EQ(r.status, 2) << r.err;
  r = run("shot builtin:pyramid --pixel 3" + out);
  EXPECT_EQ(r.status, 2) << r.err;
  r = run("shot builtin:pyramid --accel brute --overlay states" + out);
  EXPECT_EQ(r.status, 2) << r.err;
  r = run("shot '" + temp_path("no_such_scene.obj") + "'" + out);
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

// Frame `index` (each `width` wide) of a --compare PNG.
Png frame_of(const Png& wide, int width, int index) {
  Png frame;
  frame.width = width;
  frame.height = wide.height;
  for (int y = 0; y < wide.height; ++y)
    frame.rgba.insert(frame.rgba.end(), wide.at(index * width, y),
                      wide.at(index * width, y) + 4 * width);
  return frame;
}

// The figure in the totals table's row `name`, column 0 (A) or 1 (B).
double table_figure(const std::string& out, const std::string& name, int column) {
  const size_t at = out.find("\n" + name + " ");
  EXPECT_NE(at, std::string::npos) << out;
  if (at == std::string::npos) return -1.0;
  std::istringstream line(out.substr(at + 1 + name.size()));
  double a = 0.0, b = 0.0;
  line >> a >> b;
  return column == 0 ? a : b;
}

TEST(ShotCompare, EachSideIsItsStructuresImage) {
  // Every structure answers as brute force does: A (grid1d) and B (bvh) are render's image.
  const Outcome r =
      run("shot " + kTopView + " --compare accel=bvh --out '" + temp_path("cmp.png") + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  const Png wide = load_png(temp_path("cmp.png"));
  ASSERT_EQ(wide.width, 2 * kSide);
  ASSERT_EQ(wide.height, kSide);
  const Png render = image_of("render", "cmp_render.png", kTopView);
  EXPECT_EQ(frame_of(wide, kSide, 0).rgba, render.rgba);
  EXPECT_EQ(frame_of(wide, kSide, 1).rgba, render.rgba);
  EXPECT_NE(r.out.find("A: grid1d\nB: bvh\n"), std::string::npos) << r.out;
}

TEST(ShotCompare, TotalsAreEachRunsOwn) {
  // Built up front, bvh and uniform count the same tests and nodes every run: the table's
  // figures are those `render --stats` reports for each alone.
  const std::string args = "builtin:pyramid --size 96x64 --packets off";
  const Outcome r = run("shot " + args + " --accel bvh --compare accel=uniform --out '" +
                        temp_path("cmp_totals.png") + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  for (const auto& [column, accel] : {std::pair{0, "bvh"}, std::pair{1, "uniform"}}) {
    const std::string stats_path = temp_path(std::string("cmp_") + accel + ".json");
    const Outcome alone = run("render " + args + " --accel " + accel + " --stats '" + stats_path +
                              "' --out '" + temp_path("cmp_alone.png") + "'");
    ASSERT_EQ(alone.status, 0) << alone.err;
    const nlohmann::json stats = nlohmann::json::parse(slurp(stats_path));
    const double rays = stats.at("rays").get<double>();
    EXPECT_EQ(table_figure(r.out, "nodes", column), stats.at("nodes").get<double>()) << accel;
    EXPECT_NEAR(table_figure(r.out, "tests per ray", column),
                stats.at("intersection_tests").get<double>() / rays, 0.0005)
        << accel;
    EXPECT_NEAR(table_figure(r.out, "steps per ray", column),
                stats.at("traversal_steps").get<double>() / rays, 0.0005)
        << accel;
  }
}

TEST(ShotCompare, SameRunsGiveEqualHeatmapsAndANeutralDifference) {
  const std::string args = kTopView + " --accel bvh --overlay heat:tests";
  const Outcome r =
      run("shot " + args + " --compare accel=bvh --out '" + temp_path("cmp_same.png") + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  const Png wide = load_png(temp_path("cmp_same.png"));
  ASSERT_EQ(wide.width, 3 * kSide);
  // One scale for both, which for equal runs is each one's own: the shot of A alone.
  const Png alone = image_of("shot", "cmp_same_alone.png", args);
  EXPECT_EQ(frame_of(wide, kSide, 0).rgba, alone.rgba);
  EXPECT_EQ(frame_of(wide, kSide, 1).rgba, alone.rgba);
  const Png difference = frame_of(wide, kSide, 2);
  EXPECT_EQ(difference.rgba, std::vector<unsigned char>(difference.rgba.size(), 255));
}

TEST(ShotCompare, TheDifferenceIsWhiteExactlyWhereTheHeatmapsAgree) {
  const Outcome r =
      run("shot " + kTopView + " --accel bvh --overlay heat:tests --compare accel=uniform --out '" +
          temp_path("cmp_diff.png") + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  // With spp 1 the counts are whole numbers: a difference of 1 shows as not white while the
  // range is at most 255 / (2 * 0.55) (the map's smallest channel step).
  const size_t at = r.out.find("B - A from -");
  ASSERT_NE(at, std::string::npos) << r.out;
  const double range = std::stod(r.out.substr(at + 12));
  ASSERT_LE(range, 231.0) << r.out;
  const Png wide = load_png(temp_path("cmp_diff.png"));
  const Png a = frame_of(wide, kSide, 0), b = frame_of(wide, kSide, 1),
            difference = frame_of(wide, kSide, 2);
  int agree = 0, differ = 0;
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x) {
      const unsigned char* d = difference.at(x, y);
      const bool white = d[0] == 255 && d[1] == 255 && d[2] == 255;
      EXPECT_EQ(white, same_at(a, b, x, y)) << x << "," << y;
      (white ? agree : differ) += 1;
    }
  EXPECT_GT(agree, 0);
  EXPECT_GT(differ, 0);
}

TEST(ShotCompare, BadSpecsAreUsageErrors) {
  const std::string out = " --out '" + temp_path("cmp_bad.png") + "'";
  for (const char* spec : {"", "accel", "accel=nosuch", "bogus=1", "packets=maybe",
                           "max-granularity=0", "density=3", "accel=zero"}) {
    const Outcome r = run("shot builtin:pyramid --compare '" + std::string(spec) + "'" + out);
    EXPECT_EQ(r.status, 2) << spec << ": " << r.err;
    EXPECT_NE(r.err.find("--compare"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
  // The grid1d overlays need a 1D grid on both sides.
  const Outcome r = run("shot builtin:pyramid --overlay cells --compare accel=bvh" + out);
  EXPECT_EQ(r.status, 2) << r.err;
}

TEST(Compare, DivergingIsWhiteAtZeroAndSymmetric) {
  EXPECT_EQ(gs::diverging(0.0f), (std::array<uint8_t, 3>{255, 255, 255}));
  EXPECT_EQ(gs::diverging(NAN), gs::diverging(0.0f));
  EXPECT_EQ(gs::diverging(2.0f), gs::diverging(1.0f));  // clamped
  for (const float x : {0.1f, 0.5f, 1.0f}) {
    const std::array<uint8_t, 3> more = gs::diverging(x), less = gs::diverging(-x);
    // B more: red stays full; B less: blue stays full; the same distance from white.
    EXPECT_EQ(more[0], 255);
    EXPECT_EQ(less[2], 255);
    EXPECT_EQ(more[1], less[1]);
    EXPECT_EQ(more[2], less[0]);
    EXPECT_LT(more[2], 255);
  }
  EXPECT_LT(gs::diverging(1.0f)[2], gs::diverging(0.5f)[2]);  // stronger further out
}

TEST(Compare, ScalesAndDifference) {
  const std::vector<float> a = {0.0f, 2.0f, 5.0f, NAN}, b = {1.0f, 2.0f, 3.0f, 0.0f};
  EXPECT_EQ(gs::shared_heat_max(a, b), 5.0f);
  EXPECT_EQ(gs::shared_heat_max({}, {0.5f}), 1.0f);  // at least 1
  const std::vector<float> c = {0.0f, 0.0f, 8.0f}, d = {4.0f, 0.0f, 0.0f};
  EXPECT_EQ(gs::difference_range(c, d), 4.0f);  // the 99th percentile of {4, 8}: 4
  EXPECT_EQ(gs::difference_range(c, c), 1.0f);  // no difference: still a range
  std::vector<float> many(200, 0.0f), shifted(200, 0.0f);
  for (int i = 0; i < 200; ++i) shifted[size_t(i)] = float(i + 1);  // |d| = 1..200
  EXPECT_EQ(gs::difference_range(many, shifted), 198.0f);           // index 199 * 99 / 100 = 197
  const std::vector<uint8_t> rgba = gs::difference_image(c, d);
  ASSERT_EQ(rgba.size(), 12u);
  // Range 4: +4 is full red; -8 saturates at full blue.
  const std::array<uint8_t, 3> full_more = gs::diverging(1.0f), all_less = gs::diverging(-1.0f);
  EXPECT_TRUE(std::equal(full_more.begin(), full_more.end(), rgba.begin()));
  EXPECT_EQ(rgba[4], 255);
  EXPECT_EQ(rgba[5], 255);
  EXPECT_EQ(rgba[6], 255);
  EXPECT_TRUE(std::equal(all_less.begin(), all_less.end(), rgba.begin() + 8));
  EXPECT_THROW(gs::difference_range(c, a), std::invalid_argument);
}

TEST(Compare, TotalsReadRunStatsAndLeaveUnmeasuredFiguresOut) {
  const nlohmann::json measured = {{"rays", 200},
                                   {"intersection_tests", 500},
                                   {"traversal_steps", 100},
                                   {"nodes", 7},
                                   {"memory_bytes", 2000000},
                                   {"build_seconds", 0.5},
                                   {"rays_per_second", 1e6}};
  nlohmann::json unmeasured = measured;
  unmeasured["intersection_tests"] = nullptr;
  unmeasured["traversal_steps"] = nullptr;
  unmeasured["nodes"] = nullptr;
  unmeasured["rays_per_second"] = 2e6;
  const gs::CompareTotals a = gs::compare_totals("A: x", measured);
  const gs::CompareTotals b = gs::compare_totals("B: y", unmeasured);
  EXPECT_EQ(a.tests_per_ray, 2.5);
  EXPECT_EQ(a.steps_per_ray, 0.5);
  EXPECT_EQ(a.nodes, 7u);
  EXPECT_FALSE(b.tests_per_ray);
  EXPECT_FALSE(b.nodes);
  const std::string table = gs::totals_table(a, b);
  EXPECT_EQ(table.find("A: x\nB: y\n"), 0u) << table;
  EXPECT_NE(table.find("rays/s                    1e+06          2e+06     2.00"),
            std::string::npos)
      << table;
  EXPECT_NE(table.find("tests per ray             2.500            n/a"), std::string::npos)
      << table;
  EXPECT_NE(table.find("memory MB                 2.000          2.000     1.00"),
            std::string::npos)
      << table;
}

// Lumpy's close-up, as the viewer starts: the centre pixel's ray hits the teapot.
const std::string kLumpyCloseUp =
    "builtin:lumpy --size 400x250 --camera 'eye=3.2,-4.2,2.2;target=0,0,0.35;up=0,0,1;fov=40'";

// 3x3 blocks wholly in the walk's colour: a line one pixel wide never fills one.
int solid_walk_blocks(const Png& png) {
  int blocks = 0;
  for (int y = 1; y + 1 < png.height; ++y)
    for (int x = 1; x + 1 < png.width; ++x) {
      bool solid = true;
      for (int dy = -1; dy <= 1 && solid; ++dy)
        for (int dx = -1; dx <= 1 && solid; ++dx)
          solid = gs::test::walk_coloured(png.at(x + dx, y + dy));
      blocks += solid;
    }
  return blocks;
}

TEST(Shot, WalkIsDrawnThickInItsOwnColourOverTheCellsItCrossed) {
  const Png cells = image_of("shot", "lumpy_cells.png", kLumpyCloseUp + " --overlay cells");
  const Png walk =
      image_of("shot", "lumpy_walk.png", kLumpyCloseUp + " --overlay cells,walk,near-walk");
  ASSERT_EQ(walk.width, 400);
  EXPECT_EQ(gs::test::walk_pixels(cells), 0);
  EXPECT_GT(gs::test::walk_pixels(walk), 100);
  EXPECT_GT(solid_walk_blocks(walk), 0);
  // Near the walk, only what it crossed: far fewer pixels changed than with every wall.
  const Png plain = image_of("shot", "lumpy_plain.png", kLumpyCloseUp);
  int changed_by_cells = 0, changed_near_walk = 0;
  for (int y = 0; y < plain.height; ++y)
    for (int x = 0; x < plain.width; ++x) {
      changed_by_cells += !same_at(cells, plain, x, y);
      changed_near_walk += !same_at(walk, plain, x, y) && !gs::test::walk_coloured(walk.at(x, y));
    }
  EXPECT_LT(changed_near_walk * 3, changed_by_cells);
}

TEST(Shot, CellsNoteSaysWhatTheCapLeftOutAndTheDepthRangeNarrowsIt) {
  const std::string out = " --out '" + temp_path("note.png") + "'";
  const Outcome all = run("shot " + kLumpyCloseUp + " --overlay cells" + out);
  ASSERT_EQ(all.status, 0) << all.err;
  // Lumpy has far more walls than the cap: the shallow levels are kept.
  EXPECT_NE(all.err.find("gridscope shot: cells: showing "), std::string::npos) << all.err;
  EXPECT_NE(all.err.find(" walls: levels 0-"), std::string::npos) << all.err;
  EXPECT_NE(all.err.find("left out; narrow the depth range or use near-walk"), std::string::npos)
      << all.err;
  const Outcome shallow = run("shot " + kLumpyCloseUp + " --overlay cells,depth:0-1" + out);
  ASSERT_EQ(shallow.status, 0) << shallow.err;
  EXPECT_NE(shallow.err.find("walls, levels 0-1\n"), std::string::npos) << shallow.err;
  EXPECT_EQ(shallow.err.find("showing"), std::string::npos) << shallow.err;
  const Outcome reversed = run("shot " + kLumpyCloseUp + " --overlay cells,depth:3-1" + out);
  EXPECT_EQ(reversed.status, 2) << reversed.err;
  EXPECT_NE(reversed.err.find("depth:3-1"), std::string::npos) << reversed.err;
  EXPECT_EQ(std::count(reversed.err.begin(), reversed.err.end(), '\n'), 1) << reversed.err;
}

}  // namespace
