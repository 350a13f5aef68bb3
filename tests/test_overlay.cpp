// Overlays and per-pixel render records, each checked against an answer worked out here
// another way: voxels counted by id rather than walked from the root, walls recomputed
// from the parent's box, depths from the plane equation, totals from the run's counters.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <set>

#include "core/accel/brute.h"
#include "core/accel/grid1d/grid1d.h"
#include "core/base/error.h"
#include "core/render/overlay.h"
#include "core/render/render.h"
#include "tests/test_util.h"

namespace gs {
namespace {

Scene sphere_and_soup() {
  return test::merge(test::make_sphere({0.0f, 0.0f, 0.0f}, 1.0f, 12, 24),
                     test::make_soup(5, 300, glm::vec3(-2.0f), glm::vec3(2.0f), 0.1f));
}

// Eagerly built with small arrays, the paper's axis alternation and tests dear against steps
// and set-ups: many levels, few cells.
std::unique_ptr<Grid1D> eager_grid(const Scene& scene) {
  AccelParams params;
  params.max_granularity = 4;
  params.intcost = 4.0;
  params.axis = AxisRule::alternate;
  auto grid = std::make_unique<Grid1D>(params);
  grid->build(scene);
  grid->build_all();
  return grid;
}

bool is_split(const Grid1D& grid, uint32_t id) {
  return grid.voxel(id).status.load(std::memory_order_acquire) == Grid1D::kSplit;
}

// Depth and parent of every voxel, by id order: children are always appended after their
// parent, so one pass in id order sees each parent before its children.
struct Family {
  std::vector<uint32_t> depth, parent;
};
Family family(const Grid1D& grid) {
  Family f{std::vector<uint32_t>(grid.voxel_count(), 0),
           std::vector<uint32_t>(grid.voxel_count(), Grid1D::kNone)};
  for (uint32_t id = 0; id < grid.voxel_count(); ++id) {
    if (!is_split(grid, id)) continue;
    const Grid1D::Voxel& v = grid.voxel(id);
    for (uint32_t k = 0; k < v.granularity; ++k) {
      f.depth[v.first_child + k] = f.depth[id] + 1;
      f.parent[v.first_child + k] = id;
    }
  }
  return f;
}

glm::vec4 legend_color(const LineSet& lines, const std::string& label) {
  for (const LegendEntry& e : lines.legend)
    if (e.label == label) return e.color;
  ADD_FAILURE() << "no legend entry " << label;
  return glm::vec4(0.0f);
}

class Overlay : public testing::Test {
 protected:
  static void SetUpTestSuite() {
    scene_ = new Scene(sphere_and_soup());
    grid_ = eager_grid(*scene_).release();
  }
  static void TearDownTestSuite() {
    delete grid_;
    delete scene_;
  }
  static Scene* scene_;
  static Grid1D* grid_;
};
Scene* Overlay::scene_ = nullptr;
Grid1D* Overlay::grid_ = nullptr;

TEST_F(Overlay, CellLinesHaveTheRootBoxAndFourEdgesPerInnerWall) {
  const Grid1D& grid = *grid_;
  size_t expected = 12, splits = 0;
  for (uint32_t id = 0; id < grid.voxel_count(); ++id)
    if (is_split(grid, id)) expected += 4 * (grid.voxel(id).granularity - 1), ++splits;
  ASSERT_GT(splits, 10u) << "the scene should be cut at several levels";
  ASSERT_LT(2 * expected, kMaxOverlaySegments) << "the default cap would cut this grid short";
  for (CellColoring coloring : {CellColoring::depth, CellColoring::axis}) {
    const LineSet lines = cell_lines(grid, coloring);
    EXPECT_EQ(lines.vertices.size(), 2 * expected);
    EXPECT_EQ(lines.coverage.shown(), (expected - 12) / 4);
    EXPECT_EQ(lines.coverage.total(), (expected - 12) / 4);
  }
  // The first 12 segments are the root box's edges.
  double lo[3], hi[3];
  grid.voxel_box(0, lo, hi);
  const LineSet lines = cell_lines(grid, CellColoring::axis);
  for (int i = 0; i < 24; ++i)
    for (int a = 0; a < 3; ++a) {
      const float c = lines.vertices[i].position[a];
      EXPECT_TRUE(c == float(lo[a]) || c == float(hi[a])) << "vertex " << i << " axis " << a;
    }
}

TEST_F(Overlay, AxisColouredWallsLieOnTheirCutsPlanes) {
  const Grid1D& grid = *grid_;
  // Walls per axis, recomputed from each voxel's box (to float, as drawn).
  std::set<float> walls[3];
  for (uint32_t id = 0; id < grid.voxel_count(); ++id) {
    if (!is_split(grid, id)) continue;
    const Grid1D::Voxel& v = grid.voxel(id);
    double lo[3], hi[3];
    grid.voxel_box(id, lo, hi);
    for (uint32_t k = 1; k < v.granularity; ++k) {
      double clo[3], chi[3];
      grid.voxel_box(v.first_child + k, clo, chi);
      // The exact wall agrees with the even split to rounding.
      const double even = lo[v.axis] + k * (hi[v.axis] - lo[v.axis]) / v.granularity;
      EXPECT_NEAR(clo[v.axis], even, 1e-12 * (1.0 + std::abs(even)));
      walls[v.axis].insert(float(clo[v.axis]));
    }
  }
  const LineSet lines = cell_lines(grid, CellColoring::axis);
  const glm::vec3 colors[3] = {legend_color(lines, "x"), legend_color(lines, "y"),
                               legend_color(lines, "z")};
  size_t walls_seen[3] = {0, 0, 0};
  for (size_t i = 24; i < lines.vertices.size(); ++i) {
    const LineVertex& v = lines.vertices[i];
    int axis = -1;
    for (int a = 0; a < 3; ++a)
      if (glm::vec3(v.color) == colors[a]) axis = a;  // alpha fades with depth
    if (axis < 0) {
      ADD_FAILURE() << "vertex " << i << " has no axis colour";
      continue;
    }
    EXPECT_TRUE(walls[axis].count(v.position[axis])) << "vertex " << i << " off every wall";
    ++walls_seen[axis];
  }
  for (int a = 0; a < 3; ++a) EXPECT_GT(walls_seen[a], 0u) << "axis " << a;
}

TEST_F(Overlay, DepthColouringCountsWallsPerDepth) {
  const Grid1D& grid = *grid_;
  const Family f = family(grid);
  uint32_t max_depth = 0;
  std::map<uint32_t, size_t> segments_by_depth;  // by depth label
  for (uint32_t id = 0; id < grid.voxel_count(); ++id)
    if (is_split(grid, id)) {
      max_depth = std::max(max_depth, f.depth[id]);
      segments_by_depth[f.depth[id]] += 4 * (grid.voxel(id).granularity - 1);
    }
  const LineSet lines = cell_lines(grid, CellColoring::depth);
  // "scene box" then "depth 0" .. "depth max".
  ASSERT_EQ(lines.legend.size(), size_t(max_depth) + 2);
  for (uint32_t d = 0; d <= max_depth; ++d)
    EXPECT_EQ(lines.legend[d + 1].label, "depth " + std::to_string(d));
  // The palette cycles, so count per distinct colour: every depth sharing it.
  std::map<std::array<float, 3>, size_t> expected, seen;  // alpha fades with depth
  auto key = [](glm::vec4 c) { return std::array<float, 3>{c.r, c.g, c.b}; };
  for (const auto& [depth, segments] : segments_by_depth)
    expected[key(lines.legend[depth + 1].color)] += segments;
  for (size_t i = 24; i < lines.vertices.size(); i += 2) ++seen[key(lines.vertices[i].color)];
  EXPECT_EQ(seen, expected);
}

TEST_F(Overlay, StateTableCountsEverySubdividedVoxelOnce) {
  const Grid1D& grid = *grid_;
  const Family f = family(grid);
  std::map<uint32_t, uint64_t> per_state;
  uint64_t splits = 0;
  for (uint32_t id = 0; id < grid.voxel_count(); ++id) {
    if (!is_split(grid, id)) continue;
    const Grid1D::Voxel& v = grid.voxel(id);
    ++per_state[v.state], ++splits;
    // G: the product of the array sizes of the ancestors cut on the same axis, and its own.
    uint64_t g = v.granularity;
    for (uint32_t up = f.parent[id]; up != Grid1D::kNone; up = f.parent[up])
      if (grid.voxel(up).axis == v.axis) g *= grid.voxel(up).granularity;
    EXPECT_EQ(grid.state_info(v.state).granularity, g) << "voxel " << id;
  }
  const std::vector<StateRow> rows = state_table(grid);
  ASSERT_EQ(rows.size(), per_state.size());
  // Eager and within budget: every state but the scene box's three (0, 1, 2) has a voxel.
  EXPECT_EQ(rows.size(), grid.state_count() - 3);
  uint64_t total = 0;
  for (size_t i = 0; i < rows.size(); ++i) {
    const StateRow& row = rows[i];
    EXPECT_GE(row.state, 3u);
    EXPECT_EQ(row.voxels, per_state[row.state]);
    EXPECT_EQ(uint32_t(row.axis), grid.state_info(row.state).axis);
    EXPECT_EQ(row.absolute_granularity, grid.state_info(row.state).granularity);
    if (i > 0) {
      const StateRow& prev = rows[i - 1];
      EXPECT_TRUE(prev.axis < row.axis ||
                  (prev.axis == row.axis && prev.absolute_granularity < row.absolute_granularity));
    }
    total += row.voxels;
  }
  EXPECT_EQ(total, splits);

  const LineSet lines = state_lines(grid);
  EXPECT_EQ(lines.vertices.size(), 24 * splits);
  ASSERT_EQ(lines.legend.size(), rows.size());
  const char* names[3] = {"x", "y", "z"};
  for (size_t i = 0; i < rows.size(); ++i)
    EXPECT_EQ(lines.legend[i].label, std::string(names[rows[i].axis]) +
                                         " G=" + std::to_string(rows[i].absolute_granularity));
  // Deterministic colours: the same grid gives the same lines.
  const LineSet again = state_lines(grid);
  for (size_t i = 0; i < lines.vertices.size(); ++i)
    EXPECT_EQ(lines.vertices[i].color, again.vertices[i].color);
}

TEST(OverlayEmpty, UnexaminedGridHasOnlyTheSceneBox) {
  AccelParams params;
  Grid1D grid(params);
  EXPECT_TRUE(cell_lines(grid, CellColoring::depth).vertices.empty());  // not built
  EXPECT_TRUE(state_table(grid).empty());
  grid.build(sphere_and_soup());
  EXPECT_EQ(cell_lines(grid, CellColoring::axis).vertices.size(), 24u);
  EXPECT_TRUE(state_lines(grid).vertices.empty());
}

void expect_near(glm::vec3 a, glm::dvec3 b, double tolerance) {
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], tolerance) << "component " << k;
}

TEST_F(Overlay, WalkLinesEndAtTheHitAndDrawEveryCellAsABox) {
  const Grid1D* grid = grid_;
  auto context = grid->make_context();
  Ray ray;
  ray.origin = {-5.0f, 0.1f, 0.2f};
  ray.dir = {2.0f, 0.01f, -0.02f};  // not normalised: t is in units of dir
  const std::optional<Walk> walk = grid->record_walk(ray, *context);
  ASSERT_TRUE(walk && walk->hit.found());
  ASSERT_GT(walk->cells.size(), 1u);
  const int current = int(walk->cells.size()) / 2;
  const LineSet lines = walk_lines(*walk, current);
  ASSERT_EQ(lines.vertices.size(), 2 + 24 * walk->cells.size());
  const glm::dvec3 o(ray.origin), d(ray.dir);
  expect_near(lines.vertices[0].position, o, 0.0);
  expect_near(lines.vertices[1].position, o + double(walk->hit.t) * d, 1e-5);
  EXPECT_EQ(lines.vertices[0].color, legend_color(lines, "ray"));
  // Exactly one cell (the last 24 vertices) in the current colour; its corners are its box.
  const glm::vec4 current_color = legend_color(lines, "current cell");
  size_t highlighted = 0;
  for (const LineVertex& v : lines.vertices) highlighted += v.color == current_color;
  EXPECT_EQ(highlighted, 24u);
  const WalkCell& cell = walk->cells[current];
  for (size_t i = lines.vertices.size() - 24; i < lines.vertices.size(); ++i) {
    EXPECT_EQ(lines.vertices[i].color, current_color);
    for (int a = 0; a < 3; ++a) {
      const float c = lines.vertices[i].position[a];
      EXPECT_TRUE(c == float(cell.lo[a]) || c == float(cell.hi[a]));
    }
  }
  // No highlight: every cell in the visited colour.
  const LineSet plain = walk_lines(*walk);
  const glm::vec4 visited = legend_color(plain, "visited cell");
  for (size_t i = 2; i < plain.vertices.size(); ++i) EXPECT_EQ(plain.vertices[i].color, visited);
}

TEST(WalkLines, MissEndsWhereTheRayLeavesTheSceneBox) {
  const Scene scene = test::make_sphere({0.0f, 0.0f, 0.0f}, 1.0f, 16, 32);
  auto grid = eager_grid(scene);
  auto context = grid->make_context();
  // Inside the sphere's box but outside the sphere (0.9^2 + 0.9^2 > 1), along +x.
  Ray ray;
  ray.origin = {-5.0f, 0.9f, 0.9f};
  ray.dir = {0.5f, 0.0f, 0.0f};
  const std::optional<Walk> walk = grid->record_walk(ray, *context);
  ASSERT_TRUE(walk && !walk->hit.found());
  const LineSet lines = walk_lines(*walk);
  ASSERT_EQ(lines.vertices.size(), 2 + 24 * walk->cells.size());
  double lo[3], hi[3];
  grid->voxel_box(0, lo, hi);  // the ray leaves through the root box's +x face
  expect_near(lines.vertices[1].position, glm::dvec3(hi[0], 0.9, 0.9), 1e-6);

  // A ray that never enters the box: nothing to draw.
  ray.origin = {-5.0f, 5.0f, 5.0f};
  const std::optional<Walk> outside = grid->record_walk(ray, *context);
  ASSERT_TRUE(outside);
  EXPECT_TRUE(walk_lines(*outside).vertices.empty());
}

// Walls (inner walls of subdivided voxels) per depth, counted by id order through family().
std::vector<uint64_t> walls_by_depth(const Grid1D& grid) {
  const Family f = family(grid);
  std::vector<uint64_t> walls;
  for (uint32_t id = 0; id < grid.voxel_count(); ++id) {
    if (!is_split(grid, id)) continue;
    walls.resize(std::max<size_t>(walls.size(), f.depth[id] + 1), 0);
    walls[f.depth[id]] += grid.voxel(id).granularity - 1;
  }
  return walls;
}

constexpr size_t kNoCap = std::numeric_limits<size_t>::max();

TEST_F(Overlay, DepthRangeKeepsOnlyItsLevels) {
  const Grid1D& grid = *grid_;
  const Family f = family(grid);
  const std::vector<uint64_t> walls = walls_by_depth(grid);
  ASSERT_GE(walls.size(), 4u) << "the grid should have several levels";
  const uint32_t deepest = uint32_t(walls.size() - 1);
  for (const DepthRange range : {DepthRange{0, 0}, DepthRange{1, 2}, DepthRange{2, deepest}}) {
    SCOPED_TRACE(std::to_string(range.first) + "-" + std::to_string(range.last));
    uint64_t expected_walls = 0, expected_voxels = 0;
    for (uint32_t id = 0; id < grid.voxel_count(); ++id)
      if (is_split(grid, id) && range.contains(f.depth[id]))
        expected_walls += grid.voxel(id).granularity - 1, ++expected_voxels;
    const VoxelFilter filter{.depths = range, .max_segments = kNoCap};
    const LineSet cells = cell_lines(grid, CellColoring::depth, filter);
    EXPECT_EQ(cells.coverage.total(), expected_walls);
    EXPECT_EQ(cells.vertices.size(), 2 * (12 + 4 * expected_walls));
    // The legend names the range's levels only (after the scene box).
    ASSERT_EQ(cells.legend.size(), 1 + range.last - range.first + 1);
    EXPECT_EQ(cells.legend[1].label, "depth " + std::to_string(range.first));
    const LineSet states = state_lines(grid, filter);
    EXPECT_EQ(states.coverage.total(), expected_voxels);
    EXPECT_EQ(states.vertices.size(), 24 * expected_voxels);
  }
}

TEST_F(Overlay, NearWalkDrawsOnlyTheVoxelsTheWalkCrossed) {
  const Grid1D& grid = *grid_;
  const Family f = family(grid);
  auto context = grid.make_context();
  Ray ray;
  ray.origin = {-5.0f, 0.3f, -0.2f};
  ray.dir = {1.0f, 0.05f, 0.02f};
  const std::optional<Walk> walk = grid.record_walk(ray, *context);
  ASSERT_TRUE(walk && walk->cells.size() > 1);
  // The walk's voxels: its cells' ancestors, climbed through the parent links.
  std::set<uint32_t> crossed;
  for (const WalkCell& cell : walk->cells)
    for (uint32_t up = f.parent[cell.voxel]; up != Grid1D::kNone; up = f.parent[up])
      crossed.insert(up);
  uint64_t splits = 0, expected_walls = 0;
  for (uint32_t id = 0; id < grid.voxel_count(); ++id) splits += is_split(grid, id);
  for (uint32_t id : crossed) expected_walls += grid.voxel(id).granularity - 1;
  ASSERT_GT(crossed.size(), 1u);
  ASSERT_LT(crossed.size() * 4, splits) << "the walk should cross few of the voxels";

  const VoxelFilter filter{.near_walk = true, .walk = &*walk, .max_segments = kNoCap};
  const LineSet cells = cell_lines(grid, CellColoring::axis, filter);
  EXPECT_EQ(cells.coverage.total(), expected_walls);
  ASSERT_EQ(cells.vertices.size(), 2 * (12 + 4 * expected_walls));
  // Every wall segment lies in (on the boundary of or inside) a crossed voxel's box.
  const auto inside = [&](uint32_t id, glm::vec3 p) {
    double lo[3], hi[3];
    grid.voxel_box(id, lo, hi);
    for (int a = 0; a < 3; ++a)
      if (p[a] < float(lo[a]) || p[a] > float(hi[a])) return false;
    return true;
  };
  for (size_t i = 24; i < cells.vertices.size(); i += 2) {
    const glm::vec3 a = cells.vertices[i].position, b = cells.vertices[i + 1].position;
    EXPECT_TRUE(std::any_of(crossed.begin(), crossed.end(),
                            [&](uint32_t id) { return inside(id, a) && inside(id, b); }))
        << "segment " << i / 2 << " outside every crossed voxel";
  }
  // States: exactly the crossed voxels' boxes, each corner a corner of one of them; the
  // legend names their states only.
  const LineSet states = state_lines(grid, filter);
  ASSERT_EQ(states.vertices.size(), 24 * crossed.size());
  std::set<uint32_t> crossed_states;
  for (uint32_t id : crossed) crossed_states.insert(grid.voxel(id).state);
  EXPECT_EQ(states.legend.size(), crossed_states.size());
  for (size_t box = 0; box < crossed.size(); ++box) {
    const glm::vec3 corner = states.vertices[24 * box].position;
    EXPECT_TRUE(std::any_of(crossed.begin(), crossed.end(),
                            [&](uint32_t id) {
                              double lo[3], hi[3];
                              grid.voxel_box(id, lo, hi);
                              return corner == glm::vec3(float(lo[0]), float(lo[1]), float(lo[2]));
                            }))
        << "box " << box;
  }
  // No walk picked: nothing at all, not even the scene box.
  const LineSet none = cell_lines(grid, CellColoring::axis, {.near_walk = true});
  EXPECT_TRUE(none.vertices.empty());
  EXPECT_EQ(none.coverage.total(), 0u);
  EXPECT_EQ(none.coverage.describe(), "cells: no walls");
}

// "12,345": written here independently of the overlay's own formatting.
std::string grouped(uint64_t n) {
  if (n < 1000) return std::to_string(n);
  char rest[8];
  std::snprintf(rest, sizeof rest, ",%03u", unsigned(n % 1000));
  return grouped(n / 1000) + rest;
}

TEST_F(Overlay, CapKeepsShallowLevelsWholeAndSaysWhatWasLeftOut) {
  const Grid1D& grid = *grid_;
  const std::vector<uint64_t> walls = walls_by_depth(grid);
  ASSERT_GE(walls.size(), 5u);
  ASSERT_GE(walls[2], 2u);
  // Room for the scene box, levels 0 and 1 and half of level 2.
  const uint64_t half = walls[2] / 2, shown = walls[0] + walls[1] + half;
  const size_t cap = 12 + 4 * shown;
  const LineSet lines = cell_lines(grid, CellColoring::depth, {.max_segments = cap + 3});
  EXPECT_LE(lines.vertices.size() / 2, cap + 3);
  EXPECT_EQ(lines.vertices.size() / 2, cap);
  const Coverage& c = lines.coverage;
  uint64_t total = 0;
  for (const uint64_t w : walls) total += w;
  EXPECT_EQ(c.shown(), shown);
  EXPECT_EQ(c.total(), total);
  ASSERT_EQ(c.shown_by_depth.size(), walls.size());
  EXPECT_EQ(c.shown_by_depth[2], half);
  EXPECT_EQ(c.shown_by_depth[3], 0u);
  const std::string deepest = std::to_string(walls.size() - 1);
  EXPECT_EQ(c.describe(), "cells: showing " + grouped(shown) + " of " + grouped(total) +
                              " walls: levels 0-1 complete, level 2 partly, levels 3-" + deepest +
                              " left out; narrow the depth range or use near-walk");
  // Uncapped: every wall, and the note only counts them.
  const LineSet all = cell_lines(grid, CellColoring::depth, {.max_segments = kNoCap});
  EXPECT_EQ(all.coverage.describe(), "cells: " + grouped(total) + " walls, levels 0-" + deepest);
  // States are capped by whole boxes (12 lines).
  const LineSet states = state_lines(grid, {.max_segments = 12 * 5 + 11});
  EXPECT_EQ(states.vertices.size(), 24u * 5);
  EXPECT_EQ(states.coverage.shown(), 5u);
}

TEST_F(Overlay, LinesFadeWithDepth) {
  for (uint32_t first : {0u, 3u}) {
    EXPECT_EQ(alpha_for_depth(first, first), 1.0f);
    EXPECT_LT(alpha_for_depth(first + 1, first), 1.0f);
    for (uint32_t d = first; d < uint32_t(kMaxDepth); ++d) {
      EXPECT_LE(alpha_for_depth(d + 1, first), alpha_for_depth(d, first)) << d;
      EXPECT_GT(alpha_for_depth(d + 1, first), 0.0f) << d;
    }
  }
  // In the drawn lines: each level's walls carry that level's alpha (levels 0-5 have
  // distinct palette colours), and it falls level by level.
  const LineSet lines = cell_lines(*grid_, CellColoring::depth, {.max_segments = kNoCap});
  float previous = 2.0f;
  for (uint32_t d = 0; d < 6 && d + 1 < lines.legend.size(); ++d) {
    const glm::vec3 rgb = lines.legend[d + 1].color;
    std::set<float> alphas;
    for (size_t i = 24; i < lines.vertices.size(); ++i)
      if (glm::vec3(lines.vertices[i].color) == rgb) alphas.insert(lines.vertices[i].color.a);
    ASSERT_EQ(alphas.size(), 1u) << "depth " << d;
    EXPECT_EQ(*alphas.begin(), alpha_for_depth(d, 0));
    EXPECT_LE(*alphas.begin(), previous);
    previous = *alphas.begin();
  }
}

// `color` at opacity `alpha` over a grey of `grey` (0..255), as 8-bit RGB.
std::array<unsigned char, 3> over_grey(glm::vec4 color, float alpha, int grey) {
  std::array<unsigned char, 3> rgb;
  for (int c = 0; c < 3; ++c)
    rgb[c] = (unsigned char)std::lround(alpha * 255.0f * color[c] + (1.0f - alpha) * grey);
  return rgb;
}

// The pixel tests (test_shot, test_view) count walk-coloured pixels: the walk's colour must
// pass their test, and no structure colour, at any opacity over any grey shading.
TEST_F(Overlay, TheWalksColourIsNoStructureColour) {
  EXPECT_TRUE(test::walk_coloured(over_grey(kWalkColor, 1.0f, 0).data()));
  for (const LineSet& set : {cell_lines(*grid_, CellColoring::depth),
                             cell_lines(*grid_, CellColoring::axis), state_lines(*grid_)}) {
    EXPECT_FALSE(set.emphasised);
    for (const LegendEntry& e : set.legend)
      for (const float alpha : {0.1f, 0.3f, 0.6f, 1.0f})
        for (const int grey : {0, 60, 128, 200, 255})
          EXPECT_FALSE(test::walk_coloured(over_grey(e.color, alpha, grey).data()))
              << e.label << " alpha " << alpha << " over " << grey;
  }
}

TEST_F(Overlay, WalkIsEmphasisedWithItsCurrentCellFilled) {
  auto context = grid_->make_context();
  Ray ray;
  ray.origin = {-5.0f, 0.1f, 0.2f};
  ray.dir = {2.0f, 0.01f, -0.02f};
  const std::optional<Walk> walk = grid_->record_walk(ray, *context);
  ASSERT_TRUE(walk && walk->cells.size() > 1);
  const LineSet lines = walk_lines(*walk, 1);
  EXPECT_TRUE(lines.emphasised);
  EXPECT_EQ(glm::vec3(lines.vertices[0].color), glm::vec3(kWalkColor));
  ASSERT_EQ(lines.fill.size(), 36u);  // six faces, two triangles each
  const WalkCell& cell = walk->cells[1];
  for (const LineVertex& v : lines.fill) {
    EXPECT_EQ(glm::vec3(v.color), glm::vec3(kWalkColor));
    EXPECT_GT(v.color.a, 0.0f);
    EXPECT_LT(v.color.a, 1.0f);  // translucent
    for (int a = 0; a < 3; ++a)
      EXPECT_TRUE(v.position[a] == float(cell.lo[a]) || v.position[a] == float(cell.hi[a]));
  }
  EXPECT_TRUE(walk_lines(*walk).fill.empty());  // no current cell, nothing filled
}

TEST(ParseOverlays, AcceptsTheListWords) {
  const OverlaySelection s = parse_overlays("cells,walk,depth:1-3,near-walk");
  EXPECT_TRUE(s.cells && s.walk && s.near_walk && !s.states);
  EXPECT_EQ(s.depths.first, 1u);
  EXPECT_EQ(s.depths.last, 3u);
  EXPECT_EQ(s.heat, HeatKind::none);
  const OverlaySelection single = parse_overlays("depth:2,states,heat:tests");
  EXPECT_EQ(single.depths.first, 2u);
  EXPECT_EQ(single.depths.last, 2u);
  EXPECT_EQ(single.heat, HeatKind::tests);
  const OverlaySelection plain = parse_overlays("cells");
  EXPECT_TRUE(plain.depths.everything());
  EXPECT_FALSE(plain.near_walk);
  EXPECT_EQ(parse_overlays("cells,depth:0-64").depths.last, 64u);
  // format_overlays writes what parse_overlays reads back.
  for (const std::string list :
       {"cells,walk,near-walk,depth:1-3", "states,depth:2-2,heat:built", "walk", "cells,states"})
    EXPECT_EQ(format_overlays(parse_overlays(list)), list);
  // A filter left on with nothing to filter (the panel's cells unticked) is not written.
  OverlaySelection unticked = parse_overlays("cells,walk,near-walk,depth:2-4");
  unticked.cells = false;
  EXPECT_EQ(format_overlays(unticked), "walk");
}

TEST(ParseOverlays, RejectsBadListsNamingTheProblem) {
  const std::pair<std::string, std::string> cases[] = {{"cells,depth:3-1", "0 <= A <= B"},
                                                       {"cells,depth:-1-2", "0 <= A <= B"},
                                                       {"cells,depth:1-", "0 <= A <= B"},
                                                       {"cells,depth:a-b", "0 <= A <= B"},
                                                       {"cells,depth:", "0 <= A <= B"},
                                                       {"cells,depth:1-65", "0 <= A <= B"},
                                                       {"cells,depth:1-2,depth:3", "only one"},
                                                       {"near-walk", "add cells or states"},
                                                       {"walk,depth:1-2", "add cells or states"},
                                                       {"cells,bogus", "unknown overlay 'bogus'"},
                                                       {"cells,,walk", "unknown overlay ''"},
                                                       {"heat:steps,heat:built", "only one heat"},
                                                       {"", "unknown overlay ''"}};
  for (const auto& [list, problem] : cases) {
    try {
      parse_overlays(list);
      ADD_FAILURE() << "'" << list << "' accepted";
    } catch (const UsageError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("--overlay '" + list + "'"), std::string::npos) << message;
      EXPECT_NE(message.find(problem), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  }
}

void expect_rgb_near(std::array<uint8_t, 3> got, std::array<int, 3> want, int tolerance) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(int(got[c]), want[c], tolerance) << "channel " << c;
}

TEST(Turbo, FollowsThePublishedColourMap) {
  // The published table's ends are (48, 18, 59) and (122, 4, 3); the published polynomial
  // fit is up to 32 units off at the ends (its blue at 0 is 27), hence the tolerance.
  expect_rgb_near(turbo(0.0f), {48, 18, 59}, 33);
  expect_rgb_near(turbo(1.0f), {122, 4, 3}, 33);
  // Dark blue, then green in the middle, then dark red.
  const auto low = turbo(0.0f), mid = turbo(0.5f), high = turbo(1.0f);
  EXPECT_LT(low[0] + low[1] + low[2], 150);
  EXPECT_GT(mid[1], 200);
  EXPECT_GT(mid[1], mid[0]);
  EXPECT_GT(mid[1], mid[2]);
  EXPECT_GT(high[0], high[1] + 50);
  EXPECT_GT(high[0], high[2] + 50);
  // Clamped outside 0..1; NaN like 0.
  EXPECT_EQ(turbo(-3.0f), low);
  EXPECT_EQ(turbo(7.0f), high);
  EXPECT_EQ(turbo(std::nanf("")), low);
}

TEST(HeatImage, MapsTheRangeThroughTurbo) {
  const std::vector<float> values = {2.0f, 6.0f, 4.0f, std::nanf(""), -1.0f, 9.0f};
  const std::vector<uint8_t> rgba = heat_image(values, 2.0f, 6.0f);
  ASSERT_EQ(rgba.size(), values.size() * 4);
  auto rgb = [&](size_t i) {
    return std::array<uint8_t, 3>{rgba[4 * i], rgba[4 * i + 1], rgba[4 * i + 2]};
  };
  EXPECT_EQ(rgb(0), turbo(0.0f));
  EXPECT_EQ(rgb(1), turbo(1.0f));
  EXPECT_EQ(rgb(2), turbo(0.5f));
  EXPECT_EQ(rgb(3), (std::array<uint8_t, 3>{0, 0, 0}));
  EXPECT_EQ(rgb(4), turbo(0.0f));
  EXPECT_EQ(rgb(5), turbo(1.0f));
  for (size_t i = 0; i < values.size(); ++i) EXPECT_EQ(rgba[4 * i + 3], 255);
  // An empty or reversed range: everything at the low end, NaN still black.
  for (float hi : {2.0f, 1.0f}) {
    const std::vector<uint8_t> flat = heat_image(values, 2.0f, hi);
    for (size_t i = 0; i < values.size(); ++i) {
      const std::array<uint8_t, 3> want = i == 3 ? std::array<uint8_t, 3>{0, 0, 0} : turbo(0.0f);
      EXPECT_EQ((std::array<uint8_t, 3>{flat[4 * i], flat[4 * i + 1], flat[4 * i + 2]}), want);
    }
  }
  EXPECT_TRUE(heat_image({}, 0.0f, 1.0f).empty());
}

// A square in the tilted plane z = 0.3 x, |x|, |y| <= 1, seen from +z.
constexpr double kSlope = 0.3;
Scene tilted_quad() {
  Scene scene;
  scene.vertices = {{-1, -1, -kSlope}, {1, -1, kSlope}, {1, 1, kSlope}, {-1, 1, -kSlope}};
  scene.triangles = {{0, 1, 2}, {0, 2, 3}};
  return scene;
}

Camera quad_camera() {
  Camera camera;
  camera.eye = {0.2f, 0.1f, 4.0f};
  camera.target = {0.0f, 0.0f, 0.0f};
  camera.up = {0.0f, 1.0f, 0.0f};
  camera.fov = 40.0f;
  return camera;
}

struct PlaneHit {
  bool inside, outside;  // clearly on the square, clearly off it (edges excluded)
  double depth;          // distance along the view axis
};
PlaneHit plane_hit(const Camera& camera, int px, int py, int w, int h) {
  const Ray ray = camera.primary_ray(px, py, w, h);
  const glm::dvec3 o(ray.origin), d(ray.dir), f(camera.forward());
  const double t = (kSlope * o.x - o.z) / (d.z - kSlope * d.x);
  const glm::dvec3 p = o + t * d;
  const double margin = 0.05;
  const double reach = std::max(std::abs(p.x), std::abs(p.y));
  return {reach<1.0 - margin, reach> 1.0 + margin, glm::dot(p - o, f)};
}

TEST(PixelRecords, BruteDepthsAndCostsMatchThePlane) {
  const Scene scene = tilted_quad();
  BruteForce brute;
  brute.build(scene);
  const Camera camera = quad_camera();
  RenderSettings settings;
  settings.width = 48, settings.height = 40, settings.threads = 2;
  const RenderOutcome out = render_image(scene, brute, camera, settings);
  ASSERT_EQ(out.pixels.size(), size_t(48 * 40));
  size_t inside = 0, outside = 0;
  uint64_t tests = 0;
  for (int py = 0; py < settings.height; ++py)
    for (int px = 0; px < settings.width; ++px) {
      const PixelRecord& r = out.pixels[size_t(py) * settings.width + px];
      tests += r.tests;
      EXPECT_EQ(r.steps, 0u);  // brute steps through no cells
      EXPECT_EQ(r.built, 0u);
      const PlaneHit expected = plane_hit(camera, px, py, settings.width, settings.height);
      if (expected.outside) {
        ++outside;
        EXPECT_EQ(r.depth, kInf) << px << "," << py;
        // Both triangles or none (a ray that misses the scene box tests nothing); no shadow ray.
        EXPECT_TRUE(r.tests == 0 || r.tests == 2) << px << "," << py;
      } else if (expected.inside) {
        ++inside;
        EXPECT_NEAR(r.depth, expected.depth, 1e-4 * expected.depth) << px << "," << py;
        EXPECT_TRUE(r.tests == 2 || r.tests == 4) << "primary and perhaps a shadow ray";
      }
    }
  EXPECT_GT(inside, 200u);
  EXPECT_GT(outside, 200u);
  EXPECT_EQ(tests, out.counters.intersection_tests);
}

TEST(PixelRecords, Grid1DRecordsSumToTheRunsCounters) {
  const Scene scene = test::merge(tilted_quad(), sphere_and_soup());
  AccelParams params;
  Grid1D grid(params);
  grid.build(scene);
  const Camera camera = quad_camera();
  RenderSettings settings;
  settings.width = 40, settings.height = 30, settings.spp = 2, settings.threads = 2;
  sample_image(scene, grid, camera, settings);
  const RenderOutcome out = render_image(scene, grid, camera, settings);
  ASSERT_EQ(out.pixels.size(), size_t(40 * 30));
  uint64_t steps = 0, tests = 0, built = 0;
  size_t hits = 0;
  for (const PixelRecord& r : out.pixels) {
    steps += r.steps, tests += r.tests, built += r.built;
    if (r.depth == kInf) continue;
    ++hits;
    EXPECT_GT(r.depth, 0.0f);
  }
  EXPECT_GT(hits, 100u);
  EXPECT_GT(built, 0u);
  EXPECT_EQ(steps, out.counters.traversal_steps);
  EXPECT_EQ(tests, out.counters.intersection_tests);
  EXPECT_EQ(built, out.counters.voxels_built);

  // The first sample's hit t is brute's, so depths agree with brute's render exactly.
  BruteForce brute;
  brute.build(scene);
  const RenderOutcome reference = render_image(scene, brute, camera, settings);
  for (size_t i = 0; i < out.pixels.size(); ++i)
    EXPECT_EQ(out.pixels[i].depth, reference.pixels[i].depth) << "pixel " << i;
  EXPECT_EQ(out.image.rgba, reference.image.rgba);
}

}  // namespace
}  // namespace gs
