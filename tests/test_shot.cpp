// `gridscope shot` (docs/design.md §3) driven as a user would, checked by its pixels: without
// overlays it is `render`'s image exactly; each overlay changes the pixels where what it
// draws projects and leaves the others alone; bad input gives the promised exit status.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

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
