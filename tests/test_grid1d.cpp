// grid1d must give exactly brute's answers (same id, same t, same u, v) on every ray, for
// every preset of its parameters, lazy or eager, with one thread or two.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <glm/vec2.hpp>
#include <limits>
#include <memory>
#include <random>
#include <set>
#include <span>

#include "core/accel/grid1d/grid1d.h"
#include "core/accel/grid1d/packet_lanes.h"
#include "core/accel/walk.h"
#include "core/scene/camera.h"
#include "core/scene/lighting.h"
#include "core/trace/sampling.h"
#include "tests/cases.h"
#include "tests/test_util.h"

namespace gs {
namespace {

using Case = test::BruteCase;

const std::vector<Case>& cases() {
  static const std::vector<Case> all = test::brute_cases(
      test::comparison_scenes(2500, test::wall_planes_scene()), [](const test::NamedScene& s) {
        return test::mixed_rays(s.scene, {.camera_width = 110,
                                          .camera_height = 100,
                                          .chords = 10000,
                                          .axis_parallel = 6000,
                                          .edges_and_vertices = 6000});
      });
  return all;
}

// A preset: grid1d with one maximum granularity (the root's too: the paper's structure, and
// roots cut into 64 cells) and axis rule, lazy or eager, traced by one thread or two, one
// ray at a time or in packets of consecutive rays; the two-thread presets run the sampling
// pass first, as the command line does. The default root cap has its own test below.
test::StructureRun preset(int max_granularity, AxisRule axis, bool eager, int threads,
                          size_t packet = 0) {
  AccelParams params;
  params.max_granularity = params.max_root_granularity = max_granularity;
  params.axis = axis;
  return {"grid1d", params, threads == 2, eager, threads, packet};
}

std::string preset_name(const testing::TestParamInfo<test::StructureRun>& info) {
  const test::StructureRun& p = info.param;
  std::string name = "g";  // built by appending: GCC 12 warns falsely on "literal" + string
  name += std::to_string(p.params.max_granularity);
  name += p.params.axis == AxisRule::alternate ? "_alternate" : "_cost";
  name += p.eager ? "_eager" : "_lazy";
  name += "_t" + std::to_string(p.threads);
  if (p.packet > 0) name += "_packets" + std::to_string(p.packet);
  return name;
}

// Brute force's answers to `rays`, of which more than `hits` must find a triangle: fewer
// would leave a test checking mostly misses.
std::vector<Hit> brute_answers_hitting(const Scene& scene, const std::vector<Ray>& rays,
                                       size_t hits) {
  std::vector<Hit> expected = test::brute_answers(scene, rays);
  size_t found = 0;
  for (const Hit& hit : expected) found += hit.found();
  EXPECT_GT(found, hits);
  return expected;
}

// `scene` built whole with `params`, by a grid whose root must come out cut along x.
std::unique_ptr<Grid1D> built_cut_along_x(const Scene& scene, const AccelParams& params) {
  auto grid = std::make_unique<Grid1D>(params);
  grid->build(scene);
  grid->build_all();
  EXPECT_EQ(grid->voxel(0).status.load(), Grid1D::kSplit);
  EXPECT_EQ(grid->voxel(0).axis, 0);
  return grid;
}

// `scene` built whole by a grid whose cuts cost nothing but triangle tests (so each voxel
// takes the most cells it may, `granularity`), down to `depth`, its root cut along x.
std::unique_ptr<Grid1D> built_with_free_cuts(const Scene& scene, int granularity, int depth) {
  AccelParams params;
  params.repcost = params.travcost = params.vertcost = params.subcost = 0.0;
  params.max_granularity = params.max_root_granularity = granularity;
  params.max_depth = depth;
  return built_cut_along_x(scene, params);
}

// Builds `lazy` and `eager` (build_all) on `scene` and expects brute's answers `expected` to
// `rays` from both: the lazy one one ray at a time and in packets of 64, the eager one on two
// threads.
void expect_lazy_and_eager_match(const Scene& scene, const std::vector<Ray>& rays,
                                 const std::vector<Hit>& expected, Grid1D& lazy, Grid1D& eager) {
  lazy.build(scene);
  EXPECT_EQ(test::count_mismatches("one at a time", test::trace_all(lazy, rays, 1), expected), 0u);
  EXPECT_EQ(
      test::count_mismatches("packets of 64", test::trace_all(lazy, rays, 1, false, 64), expected),
      0u);
  eager.build(scene);
  eager.build_all();
  EXPECT_EQ(test::count_mismatches("eager", test::trace_all(eager, rays, 2), expected), 0u);
}

class Grid1DMatchesBrute : public testing::TestWithParam<test::StructureRun> {};

TEST_P(Grid1DMatchesBrute, SameIdAndTOnEveryRay) {
  const size_t checked = test::expect_brute_answers(
      cases(), GetParam(), test::Answers::nearest, [](const Case& c, const Accelerator& grid) {
        EXPECT_GT(*grid.stats().voxels_subdivided, 0u) << c.name << ": the grid never subdivided";
      });
  RecordProperty("rays_checked", int(checked));
}

TEST_P(Grid1DMatchesBrute, AnyHitAgreesWithNearestHit) {
  test::expect_brute_answers(cases(), GetParam(), test::Answers::any_hit);
}

std::vector<test::StructureRun> presets() {
  std::vector<test::StructureRun> out;
  for (int g : {2, 20, 64})
    for (AxisRule axis : {AxisRule::alternate, AxisRule::cost})
      for (bool eager : {false, true})
        for (int threads : {1, 2}) out.push_back(preset(g, axis, eager, threads));
  // Packets: the camera rays go together; chords, axis-parallel and edge rays mostly diverge
  // and fall back to single rays, within the same packets.
  out.push_back(preset(20, AxisRule::alternate, false, 1, 64));
  out.push_back(preset(20, AxisRule::cost, true, 2, 64));
  out.push_back(preset(64, AxisRule::alternate, false, 2, 16));
  out.push_back(preset(2, AxisRule::cost, false, 1, 8));
  return out;
}

INSTANTIATE_TEST_SUITE_P(Presets, Grid1DMatchesBrute, testing::ValuesIn(presets()), preset_name);

// One lazily built structure traced by two threads at once builds the same voxels as one
// thread and as the eager build (cuts depend on the voxel and the sample, not on timing).
TEST(Grid1DBuild, LazyTwoThreadsBuildTheSameVoxelsAsEager) {
  const Case& c = cases()[1];
  AccelParams params;
  Grid1D lazy(params), eager(params);
  lazy.build(c.scene);
  eager.build(c.scene);
  sample_run(lazy, sample_subset(c.rays, 64), c.rays.size(), 2);
  sample_run(eager, sample_subset(c.rays, 64), c.rays.size(), 1);
  eager.build_all();
  test::trace_all(lazy, c.rays, 2);
  lazy.build_all();
  ASSERT_EQ(lazy.voxel_count(), eager.voxel_count());
  ASSERT_EQ(lazy.state_count(), eager.state_count());
  // Same set of cut voxels, identified by their boxes.
  std::multiset<std::vector<double>> lazy_cuts, eager_cuts;
  for (const auto* grid : {&lazy, &eager})
    for (uint32_t id = 0; id < grid->voxel_count(); ++id) {
      if (grid->voxel(id).status.load() != Grid1D::kSplit) continue;
      double lo[3], hi[3];
      grid->voxel_box(id, lo, hi);
      (grid == &lazy ? lazy_cuts : eager_cuts)
          .insert({lo[0], lo[1], lo[2], hi[0], hi[1], hi[2], double(grid->voxel(id).axis),
                   double(grid->voxel(id).granularity)});
    }
  EXPECT_EQ(lazy_cuts, eager_cuts);
}

// The sampling pass's scout traces its sample, and the shadow rays the sample's hits cast, on
// any number of threads: the segments, and so every cut, are one thread's.
TEST(Grid1DSampling, TheScoutsThreadsCutWhatOneThreadCuts) {
  const Scene& scene = cases()[1].scene;
  const Camera camera = frame_box(scene.bounds());
  const Lighting lighting = make_lighting(scene.bounds(), camera, std::nullopt);
  constexpr int kSide = 40;
  std::vector<Ray> primaries;
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x) primaries.push_back(camera.primary_ray(x, y, kSide, kSide));
  const auto cuts = [&](int threads) {
    Grid1D grid{AccelParams{}};
    grid.build(scene);
    sample_image_rays(grid, scene, lighting, primaries, 64 * primaries.size(), threads);
    EXPECT_EQ(grid.build_progress()->figures().sample_rays_traced, primaries.size());
    grid.build_all();
    std::vector<std::array<uint32_t, 3>> out;
    for (uint32_t v = 0; v < grid.voxel_count(); ++v)
      out.push_back({grid.voxel(v).status.load(), grid.voxel(v).axis, grid.voxel(v).granularity});
    return out;
  };
  const auto one = cuts(1);
  EXPECT_GT(std::count_if(one.begin(), one.end(),
                          [](const auto& cut) { return cut[0] == Grid1D::kSplit; }),
            20);
  for (const int threads : {2, 3, 8}) EXPECT_EQ(cuts(threads), one) << threads << " threads";
}

// The sampling pass cuts with segments that already end at their hits (§1.5): a sample whose
// rays are given unclipped builds exactly what the same sample clipped at brute force's hits
// builds. The scene makes the difference show: one sample ray reaches a dense cluster, 99
// stop on a wall in front of it, so counting them through the wall would make cutting the
// cluster's voxels pay where one ray's worth does not.
TEST(Grid1DSampling, CutsSeeSegmentsEndingAtTheirHits) {
  Scene wall;
  wall.vertices = {{-2, 0.1f, 1}, {2, 0.1f, 1}, {2, 2, 1},    {-2, 2, 1},
                   {1.9f, -1, 3}, {2, -1, 3},   {2, -0.9f, 3}};  // and a speck above, aside
  wall.triangles = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}};
  const Scene scene = test::merge(wall, test::make_soup(7, 400, {-1, -1, -21}, {1, 1, -19}, 0.05f));
  std::vector<Ray> rays;
  for (int i = 0; i < 100; ++i) {
    Ray ray;
    ray.origin = i == 0 ? glm::vec3(0.0f, -0.5f, 5.0f)
                        : glm::vec3(-0.9f + 0.018f * float(i), 0.2f + 0.017f * float(i), 5.0f);
    ray.dir = {0.0f, 0.0f, -1.0f};
    rays.push_back(ray);
  }
  const std::vector<Hit> hits = test::brute_answers(scene, rays);
  std::vector<Ray> clipped = rays;
  for (size_t i = 0; i < rays.size(); ++i) {
    if (i > 0) {
      ASSERT_TRUE(hits[i].found() && hits[i].id < 2) << "ray " << i << " stops on the wall";
    }
    if (hits[i].found()) clipped[i].tmax = hits[i].t;
  }
  const auto structure = [&](const std::vector<Ray>& sample) {
    AccelParams params;
    params.axis = AxisRule::cost;  // the z cut that puts the wall and the cluster apart
    auto grid = std::make_unique<Grid1D>(params);
    grid->build(scene);
    sample_run(*grid, sample, sample.size(), 1);
    grid->build_all();
    std::vector<std::array<uint32_t, 3>> cuts;
    for (uint32_t v = 0; v < grid->voxel_count(); ++v)
      cuts.push_back(
          {grid->voxel(v).status.load(), grid->voxel(v).axis, grid->voxel(v).granularity});
    return cuts;
  };
  const auto unclipped_cuts = structure(rays), clipped_cuts = structure(clipped);
  EXPECT_GT(clipped_cuts.size(), 1u);
  EXPECT_EQ(unclipped_cuts, clipped_cuts);
}

// Where the sampling pass's scout made a cut the same way (same voxel, axis and g), the
// structure takes the scout's cells as they stand instead of sorting its triangles again.
// Every cut, taken or sorted, must hold what its geometry says: each cell lists, in the
// voxel's order, the triangles whose extent (clipped to the voxel) along the cut axis meets
// the cell, except those that meet every cell (kept at the node: in no cell's list). Checked
// against the voxels' walls, with a margin for triangles that touch a wall.
TEST(Grid1DSampling, CutsTakenFromTheScoutHoldWhatTheirGeometrySays) {
  size_t checked = 0;
  for (const size_t scene_index : {size_t{0}, size_t{1}, size_t{2}}) {
    const Scene& scene = cases()[scene_index].scene;
    const Camera camera = frame_box(scene.bounds());
    const Lighting lighting = make_lighting(scene.bounds(), camera, std::nullopt);
    std::vector<Ray> primaries;
    // A sample of 8x8 rays standing for 4096 each: the final structure cuts most voxels as the
    // scout did, some otherwise, and build_all cuts voxels the scout never reached.
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x) primaries.push_back(camera.primary_ray(x, y, 8, 8));
    Grid1D grid{AccelParams{}};
    grid.build(scene);
    sample_image_rays(grid, scene, lighting, primaries, 4096 * primaries.size(), 1);
    grid.build_all();
    // Both ways occur: cuts taken from the scout, and cuts of voxels the scout never reached
    // (or cut otherwise), sorted here.
    const BuildFigures figures = grid.build_progress()->figures();
    EXPECT_GT(figures.triangles_from_scout, 0u) << cases()[scene_index].name;
    EXPECT_LT(figures.triangles_from_scout, figures.triangles_sorted) << cases()[scene_index].name;
    std::printf("%s: %llu of %llu triangles sorted in cuts taken from the scout\n",
                cases()[scene_index].name.c_str(), (unsigned long long)figures.triangles_from_scout,
                (unsigned long long)figures.triangles_sorted);
    const BuildInput input(scene);
    for (uint32_t id = 0; id < grid.voxel_count(); ++id) {
      const Grid1D::Voxel& voxel = grid.voxel(id);
      if (voxel.status.load() != Grid1D::kSplit) continue;
      const int a = voxel.axis;
      double lo[3], hi[3];
      grid.voxel_box(id, lo, hi);
      const double margin = 1e-9 * (hi[a] - lo[a]);
      const std::span<const uint32_t> tris = grid.voxel_triangles(id);
      std::vector<std::vector<uint32_t>> expected(voxel.granularity);
      for (const uint32_t tri : tris) {
        const double t_lo = std::max(input.box_lo(tri, a), lo[a]);
        const double t_hi = std::min(input.box_hi(tri, a), hi[a]);
        std::vector<int> surely, maybe;
        for (uint32_t i = 0; i < voxel.granularity; ++i) {
          double cell_lo[3], cell_hi[3];
          grid.voxel_box(voxel.first_child + i, cell_lo, cell_hi);
          if (t_lo < cell_hi[a] - margin && t_hi > cell_lo[a] + margin) surely.push_back(int(i));
          if (t_lo <= cell_hi[a] + margin && t_hi >= cell_lo[a] - margin) maybe.push_back(int(i));
        }
        const bool listed_anywhere = std::any_of(maybe.begin(), maybe.end(), [&](int i) {
          const auto cell = grid.voxel_triangles(voxel.first_child + uint32_t(i));
          return std::find(cell.begin(), cell.end(), tri) != cell.end();
        });
        if (!listed_anywhere) {  // kept at the node: it must meet every cell
          EXPECT_EQ(maybe.size(), voxel.granularity) << "triangle " << tri << " voxel " << id;
          continue;
        }
        for (const int i : maybe) {
          const auto cell = grid.voxel_triangles(voxel.first_child + uint32_t(i));
          const bool listed = std::find(cell.begin(), cell.end(), tri) != cell.end();
          if (std::find(surely.begin(), surely.end(), i) != surely.end()) {
            EXPECT_TRUE(listed) << "triangle " << tri << " cell " << i << " of voxel " << id;
          }
          if (listed) expected[size_t(i)].push_back(tri);
        }
      }
      // Nothing else is listed, in the voxel's order.
      for (uint32_t i = 0; i < voxel.granularity; ++i) {
        const auto cell = grid.voxel_triangles(voxel.first_child + i);
        EXPECT_EQ(std::vector<uint32_t>(cell.begin(), cell.end()), expected[i])
            << "cell " << i << " of voxel " << id;
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 100u);
}

// The recorded walk lists the cells the walk looked at (leaves whose contents the ray
// meets; cells crossed without a look are not listed), in the order the ray enters them:
// each holds triangles, the ray is inside it where the walk says it entered, through the
// face of the axis it names, and the nearest hit lies in one of them. Its tests,
// rejections and cells are the counters' own.
TEST(Grid1DWalk, RecordsTheCellsTheWalkLooksAt) {
  const Case& c = cases()[1];
  Grid1D grid(AccelParams{});
  grid.build(c.scene);
  sample_run(grid, sample_subset(c.rays, 64), c.rays.size(), 1);
  auto context = grid.make_context();
  size_t cells = 0, multi_cell = 0, hits = 0;
  const auto inside = [](const Ray& ray, double t, const WalkCell& cell, int a, double bound) {
    const double p = double(ray.origin[a]) + t * double(ray.dir[a]);
    const double slack = 1e-9 * (1.0 + std::fabs(p));
    return bound == 0 ? p >= cell.lo[a] - slack && p <= cell.hi[a] + slack
                      : std::fabs(p - bound) <= slack;
  };
  for (size_t i = 0; i < c.rays.size(); i += 7) {
    const Ray& ray = c.rays[i];
    const TraceCounters before = context->counters;
    const std::optional<Walk> walk = grid.record_walk(ray, *context);
    ASSERT_TRUE(walk);
    ASSERT_EQ(walk->hit, c.expected[i]) << "ray " << i;
    const TraceCounters& after = context->counters;
    uint64_t tests = 0, rejections = 0;
    for (const WalkCell& cell : walk->cells) tests += cell.tests, rejections += cell.rejections;
    EXPECT_EQ(tests, after.intersection_tests - before.intersection_tests);
    EXPECT_EQ(rejections, after.mailbox_rejections - before.mailbox_rejections);
    EXPECT_EQ(walk->cells.size(), after.traversal_steps - before.traversal_steps);
    if (walk->hit.found()) {
      ++hits;
      ASSERT_FALSE(walk->cells.empty()) << "ray " << i;
      EXPECT_EQ(walk->cells.back().hit, walk->hit.id);
      bool hit_in_a_cell = false;
      for (const WalkCell& cell : walk->cells) {
        bool in = true;
        for (int a = 0; a < 3; ++a) in &= inside(ray, walk->hit.t, cell, a, 0);
        hit_in_a_cell |= in;
      }
      EXPECT_TRUE(hit_in_a_cell) << "ray " << i;
    }
    cells += walk->cells.size();
    multi_cell += walk->cells.size() > 1;
    for (size_t k = 0; k < walk->cells.size(); ++k) {
      const WalkCell& cell = walk->cells[k];
      // A subdivided voxel's spanning triangles, or a leaf holding triangles.
      EXPECT_EQ(grid.voxel(cell.voxel).status.load(),
                cell.spanning ? Grid1D::kSplit : Grid1D::kLeaf)
          << "ray " << i;
      EXPECT_GT(grid.voxel(cell.voxel).tri_count, 0u) << "ray " << i << " cell " << k;
      if (k > 0) {
        ASSERT_LE(walk->cells[k - 1].t_enter, cell.t_enter) << "ray " << i;
      }
      for (int a = 0; a < 3; ++a)
        EXPECT_TRUE(inside(ray, cell.t_enter, cell, a, 0)) << "ray " << i << " cell " << k;
      const int a = cell.entered_axis;
      if (a < 0) continue;
      EXPECT_TRUE(inside(ray, cell.t_enter, cell, a, cell.lo[a]) ||
                  inside(ray, cell.t_enter, cell, a, cell.hi[a]))
          << "ray " << i << " cell " << k;
    }
  }
  EXPECT_GT(hits, 100u);
  EXPECT_GT(multi_cell, 20u);
  RecordProperty("cells_recorded", int(cells));
}

// The stadium's cluster lies in a chain of voxels that each hold it whole in one cell (the
// paper's teapot in a stadium). The chain's top cell refers to the chain's bottom, so the
// walk goes from there straight into the cluster. Rays from an eye inside the stadium toward
// the cluster, one at a time and in packets, lazily and eagerly built, get brute force's
// answers; the chain is there (voxels cut with exactly one cell holding triangles, counted
// from the voxel records), and no recorded walk goes down into one of its voxels, although
// the walks that hit go down below them; every cell a walk records is a leaf. (Rays leaving
// the cluster through the chain: RaysLeavingAClusterInsideACellOfAnotherAxisReachTheWalls.)
TEST(Grid1DWalk, RaysGoFromTheStadiumsChainStraightIntoTheCluster) {
  const Scene scene = test::stadium_scene(2500);
  std::vector<Ray> rays;
  const glm::vec3 eye(4.0f, 3.0f, 6.0f);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      Ray ray;
      ray.origin = eye;
      ray.dir =
          glm::vec3(1.5f * (float(x) - 31.5f) / 32.0f, 1.5f * (float(y) - 31.5f) / 32.0f, 0.0f) -
          eye;
      rays.push_back(ray);
    }
  const std::vector<Hit> expected = brute_answers_hitting(scene, rays, rays.size() / 4);
  Grid1D grid{AccelParams{}}, eager{AccelParams{}};
  expect_lazy_and_eager_match(scene, rays, expected, grid, eager);
  std::vector<bool> chain(grid.voxel_count(), false);
  uint32_t chain_depth = 0;
  for (uint32_t id = 0; id < grid.voxel_count(); ++id) {
    const Grid1D::Voxel& voxel = grid.voxel(id);
    if (voxel.status.load() != Grid1D::kSplit) continue;
    int holding = 0;
    for (uint32_t i = 0; i < voxel.granularity; ++i)
      holding += grid.voxel(voxel.first_child + i).tri_count > 0;
    chain[id] = holding == 1;
    if (chain[id]) chain_depth = std::max(chain_depth, grid.voxel_depth(id));
  }
  EXPECT_GE(std::count(chain.begin(), chain.end(), true), 3);
  const auto context = grid.make_context();
  uint64_t descents = 0, below_chain = 0;
  for (size_t i = 0; i < rays.size(); i += 7) {
    const std::optional<Walk> walk = grid.record_walk(rays[i], *context);
    ASSERT_TRUE(walk.has_value());
    EXPECT_EQ(walk->hit.id, expected[i].id) << "ray " << i;
    for (const WalkCell& cell : walk->cells) {
      EXPECT_TRUE(cell.spanning || grid.voxel(cell.voxel).status.load() != Grid1D::kSplit)
          << "ray " << i << " searched subdivided voxel " << cell.voxel;
      for (const WalkDescent& descent : cell.descents) {
        ++descents;
        EXPECT_FALSE(chain[descent.voxel])
            << "ray " << i << " went down into chain voxel " << descent.voxel;
        below_chain += descent.depth > chain_depth;
      }
    }
  }
  EXPECT_GT(descents, 0u);
  EXPECT_GT(below_chain, 0u);
}

// Rays that start on the scene's surfaces, as shadow rays and bounces do: from each
// triangle's centre (and from its first corner) toward a point light above the stadium, and
// back the way a reflection would go. They start deep in the structure, in cells whose
// contents hold the start point, and the walk goes straight down to them. Nearest and any
// hit get brute force's answers one at a time, in packets and on two threads; a recorded
// walk tests its first triangles before any step across a wall, every descent to that cell
// goes into a voxel holding the start point, and that cell holds it too.
TEST(Grid1DWalk, RaysStartingOnSurfacesGoStraightDownToTheirStart) {
  const Scene scene = test::stadium_scene(2500);
  const glm::vec3 light(4.0f, 30.0f, 6.0f);
  std::vector<Ray> rays;
  for (uint32_t t = 0; t < scene.triangle_count(); t += 3) {
    const glm::vec3 centre = (scene.vertex(t, 0) + scene.vertex(t, 1) + scene.vertex(t, 2)) / 3.0f;
    for (const glm::vec3& start : {centre, scene.vertex(t, 0)}) {
      Ray shadow;
      shadow.origin = start;
      shadow.dir = light - start;
      shadow.tmax = 1.0f;
      Ray back = shadow;
      back.dir = -shadow.dir;
      back.tmax = std::numeric_limits<float>::infinity();
      rays.insert(rays.end(), {shadow, back});
    }
  }
  const std::vector<Hit> expected = brute_answers_hitting(scene, rays, rays.size() / 4);
  Grid1D grid{AccelParams{}};
  grid.build(scene);
  EXPECT_EQ(test::count_mismatches("one at a time", test::trace_all(grid, rays, 1), expected), 0u);
  EXPECT_EQ(test::count_any_hit_mismatches(rays, test::trace_all(grid, rays, 2, true), expected),
            0u);
  EXPECT_EQ(
      test::count_mismatches("packets of 64", test::trace_all(grid, rays, 1, false, 64), expected),
      0u);
  EXPECT_EQ(
      test::count_any_hit_mismatches(rays, test::trace_all(grid, rays, 1, true, 64), expected), 0u);
  const auto holds = [&](uint32_t voxel, const glm::vec3& point) {
    double lo[3], hi[3];
    grid.voxel_box(voxel, lo, hi);
    bool in = true;
    for (int a = 0; a < 3; ++a) in &= lo[a] <= point[a] && point[a] <= hi[a];
    return in;
  };
  const auto context = grid.make_context();
  size_t walks = 0, deep_starts = 0;
  for (size_t i = 0; i < rays.size(); i += 4 * 5, ++walks) {  // centres' shadow rays
    const std::optional<Walk> walk = grid.record_walk(rays[i], *context);
    ASSERT_TRUE(walk.has_value());
    // The first cell that tests anything: the start's leaf, or a node on the way down to it
    // that keeps the start's triangle as a spanning one (the leaf then may hold nothing).
    const auto first =
        std::ranges::find_if(walk->cells, [](const WalkCell& c) { return c.tests > 0; });
    ASSERT_NE(first, walk->cells.end()) << "ray " << i;
    EXPECT_EQ(first->entered_axis, -1) << "ray " << i;
    EXPECT_TRUE(holds(first->voxel, rays[i].origin)) << "ray " << i;
    size_t descents = 0;
    for (auto cell = walk->cells.begin(); cell <= first; ++cell)
      for (const WalkDescent& descent : cell->descents) {
        ++descents;
        EXPECT_TRUE(holds(descent.voxel, rays[i].origin))
            << "ray " << i << " went down into voxel " << descent.voxel;
      }
    deep_starts += descents >= 3;
  }
  EXPECT_GT(deep_starts, walks / 2);
  RecordProperty("walks", int(walks));
  RecordProperty("deep_starts", int(deep_starts));
}

// A chain of one-cell cuts that the depth cap ends in a leaf: the chain's top refers to that
// leaf, rays get brute force's answers, and a recorded walk names the leaf it searched (the
// chain's last cell), not the chain's top voxel.
TEST(Grid1DWalk, AChainEndingInALeafIsSearchedAsThatLeaf) {
  const Scene scene = test::stadium_scene(2500);
  std::vector<Ray> rays;
  for (int i = 0; i < 400; ++i) {
    Ray ray;
    ray.origin = {4.0f, 3.0f, 6.0f};
    ray.dir =
        glm::vec3(0.02f * float(i % 20) - 0.2f, 0.02f * float(i / 20) - 0.2f, 0.0f) - ray.origin;
    rays.push_back(ray);
  }
  const std::vector<Hit> expected = brute_answers_hitting(scene, rays, rays.size() / 2);
  AccelParams params;
  params.max_depth = 6;
  Grid1D grid{params};
  grid.build(scene);
  EXPECT_EQ(test::count_mismatches("depth cap 6", test::trace_all(grid, rays, 1), expected), 0u);
  const auto context = grid.make_context();
  uint32_t searched = 0;
  for (size_t i = 0; i < rays.size(); i += 5) {
    const std::optional<Walk> walk = grid.record_walk(rays[i], *context);
    ASSERT_TRUE(walk.has_value());
    for (const WalkCell& cell : walk->cells) {
      if (cell.spanning) continue;  // the stadium's ground, at the root
      ASSERT_NE(grid.voxel(cell.voxel).status.load(), Grid1D::kSplit) << "ray " << i;
      searched += grid.voxel(cell.voxel).tri_count > 0;
    }
  }
  EXPECT_GT(searched, 0u);
}

// Triangles that lie in every cell of a cut (the stadium's ground and back wall span the
// whole box along the root's axis) are kept once at the cut voxel's node, in none of its
// cells, and tested as the walk goes down into it: no voxel below the root lists them, the
// walks of rays toward the ground beside the cluster search the root's spanning triangles
// first and find their answer there, and every answer is brute force's, one at a time, in
// packets, any-hit, eagerly built and on two threads.
TEST(Grid1DWalk, TrianglesSpanningACutAreTestedAtItsNode) {
  const Scene scene = test::stadium_scene(2500);
  const uint32_t first_ground = uint32_t(scene.triangle_count()) - 4;  // merged last
  std::vector<Ray> rays;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 48; ++x) {
      Ray ray;
      ray.origin = {4.0f, 3.0f, 6.0f};
      ray.dir = glm::vec3(-6.0f + 0.25f * float(x), -2.0f, -6.0f + 0.25f * float(y)) - ray.origin;
      rays.push_back(ray);
    }
  const std::vector<Hit> expected = brute_answers_hitting(scene, rays, rays.size() / 2);
  Grid1D grid{AccelParams{}}, eager{AccelParams{}};
  expect_lazy_and_eager_match(scene, rays, expected, grid, eager);
  EXPECT_EQ(test::count_any_hit_mismatches(rays, test::trace_all(grid, rays, 2, true), expected),
            0u);
  ASSERT_EQ(eager.voxel(0).status.load(), Grid1D::kSplit);
  EXPECT_EQ(std::ranges::count_if(eager.voxel_triangles(0),
                                  [&](uint32_t tri) { return tri >= first_ground; }),
            4);
  for (uint32_t id = 1; id < eager.voxel_count(); ++id)
    for (const uint32_t tri : eager.voxel_triangles(id))
      ASSERT_LT(tri, first_ground) << "voxel " << id << " lists spanning triangle " << tri;
  const auto context = grid.make_context();
  size_t ground_hits = 0;
  for (size_t i = 0; i < rays.size(); i += 5) {
    const std::optional<Walk> walk = grid.record_walk(rays[i], *context);
    ASSERT_TRUE(walk.has_value());
    EXPECT_EQ(walk->hit, expected[i]) << "ray " << i;
    if (expected[i].id < int32_t(first_ground)) continue;
    ++ground_hits;
    ASSERT_FALSE(walk->cells.empty()) << "ray " << i;
    const WalkCell& first = walk->cells.front();
    EXPECT_TRUE(first.spanning) << "ray " << i;
    EXPECT_EQ(first.voxel, 0u) << "ray " << i;
    EXPECT_GT(first.tests, 0u) << "ray " << i;
    EXPECT_EQ(first.hit, expected[i].id) << "ray " << i;
  }
  EXPECT_GT(ground_hits, 100u);
}

// Beads on a string: small clusters far apart along x, so that the root's cells are mostly
// empty, in runs on both sides of cell 63 (where a node's bits of occupied cells end: bit 63
// stands for every cell from 63 on). Rays along the string both ways, camera rays and
// chords across it, and rays from far away (those test no content box) find brute force's answers
// one at a time, in packets, any-hit, and eagerly built on two threads: a cell the walk
// passes over by its bits holds no triangle.
// Lumpy's cluster sits in a stadium whose walls are 1,000 units away. The cost function
// isolates the cluster by chains of one-cell cuts, some of them inside a cell of a node cut
// along another axis (the root's x cell holding the cluster is cut along y). A ray leaving
// the cluster toward a wall must step along that node's cells, which hold the wall's
// triangles; when the walk passed such a chain by, stepping in the node above it instead, it
// lost the node in between and left the scene box missing the wall. Rays from inside the
// cluster outward, the first eight ones the lazy and the eager structure once missed (from a
// walk built by a sampling pass over 200,000 such rays), and 3,000 random ones: brute's
// answers, lazy (sampled on the random ones) and eager.
TEST(Grid1DWalk, RaysLeavingAClusterInsideACellOfAnotherAxisReachTheWalls) {
  const Scene scene = load_scene("builtin:lumpy");
  std::vector<Ray> rays;
  const float missed[][2][3] = {
      {{0.34660521149635315f, 0.27795326709747314f, 0.8435225486755371f},
       {0.18672218918800354f, 0.9824012517929077f, 0.00475903507322073f}},
      {{-1.2661857604980469f, 0.6264313459396362f, 0.8316223621368408f},
       {-0.1653517335653305f, -0.9834770560264587f, 0.0737004429101944f}},
      {{-1.149144172668457f, 0.8268856406211853f, 0.792421817779541f},
       {-0.19317087531089783f, -0.980881929397583f, 0.02357413060963154f}},
      {{-0.986055850982666f, -2.226151704788208f, 0.7068450450897217f},
       {-0.1506010890007019f, 0.9870226979255676f, 0.05572749674320221f}},
      {{-0.7456555962562561f, -0.8013631105422974f, 0.9181519746780396f},
       {-0.14243483543395996f, -0.9897902607917786f, 0.005253075622022152f}},
      {{-0.3782624304294586f, 1.2905540466308594f, 0.021184459328651428f},
       {-0.17370633780956268f, 0.9807555079460144f, 0.08913359045982361f}},
      {{1.178339958190918f, -1.9825446605682373f, 0.7148137092590332f},
       {0.09956800192594528f, 0.9885209798812866f, 0.1136331707239151f}},
      {{0.8718082904815674f, -0.09274973720312119f, 0.9974645972251892f},
       {0.1394025832414627f, 0.9900315403938293f, 0.0201102327555418f}},
  };
  for (const auto& [origin, dir] : missed) {
    Ray ray;
    ray.origin = {origin[0], origin[1], origin[2]};
    ray.dir = {dir[0], dir[1], dir[2]};
    rays.push_back(ray);
  }
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> inside(-3.2f, 3.2f);
  std::normal_distribution<float> normal;
  for (int i = 0; i < 3000; ++i) {
    Ray ray;
    ray.origin = {inside(rng), inside(rng), inside(rng) * 0.5f + 1.6f};
    ray.dir = glm::normalize(glm::vec3(normal(rng), normal(rng), normal(rng)));
    rays.push_back(ray);
  }
  const std::vector<Hit> expected = brute_answers_hitting(scene, rays, rays.size() / 2);
  for (size_t i = 0; i < std::size(missed); ++i)
    EXPECT_GT(expected[i].t, 1000.0f) << "ray " << i << " reaches a wall";
  Grid1D lazy{AccelParams{}}, eager{AccelParams{}};
  lazy.build(scene);
  sample_run(lazy, std::span(rays).subspan(std::size(missed)), rays.size(), 1);
  EXPECT_EQ(test::count_mismatches("lazy", test::trace_all(lazy, rays, 1), expected), 0u);
  eager.build(scene);
  sample_run(eager, std::span(rays).subspan(std::size(missed)), rays.size(), 1);
  eager.build_all();
  EXPECT_EQ(test::count_mismatches("eager", test::trace_all(eager, rays, 2), expected), 0u);
}

TEST(Grid1DWalk, RunsOfEmptyCellsArePassedOverWithoutLosingAHit) {
  Scene scene;
  for (const float x : {0.0f, 30.2f, 62.6f, 63.6f, 71.4f, 99.6f})
    scene = test::merge(scene, test::make_soup(uint32_t(10 * x), 40, glm::vec3(x, 0.0f, 0.0f),
                                               glm::vec3(x + 0.3f, 1.0f, 1.0f), 0.05f));
  std::vector<Ray> rays;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int i = 0; i < 4000; ++i) {
    Ray ray;
    const bool forward = i % 2 == 0;
    ray.origin = {forward ? -5.0f : 105.0f, unit(rng), unit(rng)};
    ray.dir = {forward ? 1.0f : -1.0f, 0.002f * (unit(rng) - 0.5f), 0.002f * (unit(rng) - 0.5f)};
    rays.push_back(ray);
  }
  const Box box = scene.bounds();
  for (const std::vector<Ray>& more :
       {test::camera_rays(box, 40, 40), test::random_chords(box, 3, 3000),
        test::edge_and_vertex_rays(scene, 5, 3000)})
    rays.insert(rays.end(), more.begin(), more.end());
  const std::vector<Hit> expected = brute_answers_hitting(scene, rays, rays.size() / 8);

  AccelParams params;
  params.max_granularity = params.max_root_granularity = 128;
  params.intcost = 16.0;  // tests dear against steps: the root takes fine cells
  Grid1D grid(params), eager(params);
  expect_lazy_and_eager_match(scene, rays, expected, grid, eager);
  EXPECT_EQ(test::count_any_hit_mismatches(rays, test::trace_all(grid, rays, 2, true), expected),
            0u);
  const Grid1D::Voxel& root = eager.voxel(0);
  ASSERT_EQ(root.status.load(), Grid1D::kSplit);
  ASSERT_EQ(root.axis, 0);
  ASSERT_GT(root.granularity, 70);
  std::vector<uint32_t> occupied;
  for (uint32_t i = 0; i < root.granularity; ++i)
    if (eager.voxel(root.first_child + i).tri_count > 0) occupied.push_back(i);
  ASSERT_GE(occupied.size(), 6u);
  EXPECT_LE(occupied.size(), 12u);
  // Past cell 63, an empty run and then a cell with triangles: bit 63 stands for both.
  EXPECT_TRUE(std::ranges::any_of(occupied, [](uint32_t i) { return i > 65; }));
  EXPECT_TRUE(std::ranges::any_of(occupied, [](uint32_t i) { return i < 63 && i > 1; }));
}

// A packet whose rays all go one way walks together: a 64x64 view straight down onto the
// sphere in its soup, in 8x8 tiles (the image's centre lines fall between tiles, so each
// tile's rays share their direction signs, and z dominates every direction), gives brute's
// answers with no ray falling back, and the packet steps carry several rays each; any-hit
// answers keep the any-hit rule.
TEST(Grid1DPackets, CoherentTilesWalkTogetherAndMatchBrute) {
  const Scene scene = test::sphere_in_soup();
  const Box box = scene.bounds();
  const glm::vec3 centre = 0.5f * (box.lo + box.hi);
  const float height = 2.0f * (box.hi.z - box.lo.z);
  std::vector<Ray> tiled;  // 8x8 tiles, one after another
  for (int ty = 0; ty < 64; ty += 8)
    for (int tx = 0; tx < 64; tx += 8)
      for (int y = ty; y < ty + 8; ++y)
        for (int x = tx; x < tx + 8; ++x) {
          Ray ray;
          ray.origin = centre + glm::vec3(0.0f, 0.0f, height);
          ray.dir = {0.25f * (float(x) + 0.5f - 32.0f) / 32.0f,
                     0.25f * (float(y) + 0.5f - 32.0f) / 32.0f, -1.0f};
          tiled.push_back(ray);
        }
  const std::vector<Hit> expected = brute_answers_hitting(scene, tiled, tiled.size() / 8);
  Grid1D grid{AccelParams{}};
  grid.build(scene);
  const auto context = grid.make_context();
  std::vector<Hit> hits(tiled.size()), any(tiled.size());
  std::vector<uint64_t> keys(64);
  for (size_t first = 0; first < tiled.size(); first += 64) {
    const std::span<const Ray> packet(tiled.data() + first, 64);
    grid.trace_packet(packet, keys, {hits.data() + first, 64}, false, *context);
    grid.trace_packet(packet, keys, {any.data() + first, 64}, true, *context);
  }
  EXPECT_EQ(test::count_mismatches("packets of 64", hits, expected), 0u);
  EXPECT_EQ(test::count_any_hit_mismatches(tiled, any, expected), 0u);
  const TraceCounters& counters = context->counters;
  EXPECT_EQ(counters.packet_fallback_rays, 0u);
  EXPECT_GT(counters.packets, 0u);
  EXPECT_GT(counters.packet_steps, 0u);
  // More than one ray per step on average: the rays really went together.
  EXPECT_GT(counters.packet_step_rays, 2 * counters.packet_steps);
}

// A few rays of a packet spread over its lane groups search a dense leaf one at a time
// (searches_alone): a soup of 64 small triangles in [0, 1]^3 and a wall at x = 9..10 make a
// root cut along x into leaves; of 64 rays along +z, rays 0, 8, ..., 56 (one per group of 8,
// and of 4; two per group of 16) cross the soup and the others the wall, so the packet's
// bounds leave every soup box to test. On every instruction set this CPU has, each ray's
// nearest and any-hit answers are brute force's.
TEST(Grid1DPackets, ScatteredRaysSearchADenseLeafAloneAndMatchBrute) {
  Scene scene = test::make_soup(11, 64, glm::vec3(0.0f), glm::vec3(1.0f), 0.3f);
  const auto wall = uint32_t(scene.vertices.size());
  scene.vertices.insert(scene.vertices.end(),
                        {{8.5f, -0.5f, 0.5f}, {11.0f, -0.5f, 0.5f}, {9.5f, 2.0f, 0.5f}});
  scene.triangles.push_back({wall, wall + 1, wall + 2});
  std::vector<Ray> rays(64);
  uint64_t soup_rays = 0;
  for (uint32_t i = 0; i < 64; ++i) {
    const bool soup = i % 8 == 0;
    soup_rays |= uint64_t(soup) << i;
    const float x = soup ? 0.05f + 0.9f * float(i / 8) / 7.0f : 9.3f + 0.005f * float(i % 8);
    rays[i].origin = {x, 0.1f + 0.8f * float(i % 8) / 7.0f + 0.01f * float(i / 8), -1.0f};
    rays[i].dir = {0.0f, 0.0f, 1.0f};
  }
  const std::vector<Hit> expected = brute_answers_hitting(scene, rays, 60);
  // Every soup box left by the bounds: alone at every lane width.
  for (const uint32_t width : {4u, 8u, 16u})
    EXPECT_TRUE(searches_alone(soup_rays, ~uint64_t{0}, 64, width)) << width;
  // The wall's leaf, searched by the 56 other rays filling their groups: together.
  EXPECT_FALSE(searches_alone(~soup_rays, 1, 1, 8));
  const Isa before = kernel_isa();
  for (const Isa isa : {Isa::scalar, Isa::avx2, Isa::avx512}) {
    if (!isa_supported(isa)) continue;
    force_kernel_isa(isa);
    AccelParams params;
    params.max_depth = 1;
    const std::unique_ptr<Grid1D> grid = built_cut_along_x(scene, params);
    const auto context = grid->make_context();
    std::vector<Hit> hits(64), any(64);
    const std::vector<uint64_t> keys(64);
    grid->trace_packet(rays, keys, hits, false, *context);
    grid->trace_packet(rays, keys, any, true, *context);
    EXPECT_EQ(test::count_mismatches("packets of 64", hits, expected), 0u) << isa_name(isa);
    EXPECT_EQ(test::count_any_hit_mismatches(rays, any, expected), 0u) << isa_name(isa);
    EXPECT_EQ(context->counters.packet_fallback_rays, 0u);
  }
  force_kernel_isa(before);
}

// A recorded walk counts the walls it crosses along the nodes' axes, cells it looks at and
// cells it passes by alike (Travcost's work, §6.2): a row [0, 8] x [0, 1] x [0, 1] cut into
// eight unit cells along x, whose triangles lie in the cells' corners off the rays, crossed
// end to end (7 walls), from inside cell 2 (5), stopped in cell 4 (4), the other way (7),
// and across one cell (none).
TEST(Grid1DWalk, CountsTheCellsARayCrosses) {
  Scene scene;
  for (int i = 0; i < 8; ++i) {
    const float x = float(i) + 0.4f;
    test::add_triangle(scene, {x, 0.0f, 0.0f}, {x + 0.2f, 0.0f, 0.0f}, {x + 0.1f, 0.1f, 0.1f});
  }
  test::add_triangle(scene, {0.0f, 0.9f, 0.9f}, {0.1f, 1.0f, 1.0f},
                     {0.0f, 1.0f, 0.9f});  // the box's corners
  test::add_triangle(scene, {7.9f, 0.9f, 0.9f}, {8.0f, 1.0f, 1.0f}, {8.0f, 0.9f, 1.0f});
  const std::unique_ptr<Grid1D> grid = built_with_free_cuts(scene, 8, 1);
  ASSERT_EQ(grid->voxel(0).granularity, 8u);

  const auto crossed = [&](glm::vec3 origin, glm::vec3 dir, float tmax) {
    Ray ray;
    ray.origin = origin, ray.dir = dir, ray.tmax = tmax;
    const auto context = grid->make_context();
    const std::optional<Walk> walk = grid->record_walk(ray, *context);
    EXPECT_TRUE(walk && !walk->hit.found());
    return walk ? walk->cells_crossed : ~uint64_t{0};
  };
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(crossed({-1.0f, 0.45f, 0.45f}, {1.0f, 0.01f, 0.02f}, inf), 7u);
  EXPECT_EQ(crossed({2.5f, 0.45f, 0.45f}, {1.0f, 0.01f, 0.02f}, inf), 5u);
  EXPECT_EQ(crossed({-1.0f, 0.45f, 0.45f}, {1.0f, 0.01f, 0.02f}, 5.2f), 4u);
  EXPECT_EQ(crossed({9.0f, 0.55f, 0.55f}, {-1.0f, -0.01f, -0.02f}, inf), 7u);
  EXPECT_EQ(crossed({3.5f, -1.0f, 0.5f}, {0.0f, 1.0f, 0.01f}, inf), 0u);
}

// A ray up z from below the scene at `at`: its answer, which must be brute force's, and the
// descents its walk made.
std::pair<Hit, uint64_t> traced_up_z(const Grid1D& grid, const Scene& scene, glm::vec2 at) {
  Ray ray;
  ray.origin = {at.x, at.y, -1.0f}, ray.dir = {0.0f, 0.0f, 1.0f};
  const auto context = grid.make_context();
  const Hit hit = grid.intersect(ray, *context);
  EXPECT_EQ(hit, test::brute_answers(scene, {ray})[0]) << at.x << " " << at.y;
  return {hit, context->counters.descents};
}

// Rays up z into a root whose cell holds a node, the node's triangles at z = 0.5: the one
// through `gap` meets the cell's box but no box of the node's summary, and goes down into the
// root alone; the one through `hit` goes down into the node too and hits triangle `id`.
void expect_node_passed_by(const Grid1D& grid, const Scene& scene, glm::vec2 gap, glm::vec2 hit,
                           int32_t id) {
  const auto [missed, gap_descents] = traced_up_z(grid, scene, gap);
  EXPECT_FALSE(missed.found());
  EXPECT_EQ(gap_descents, 1u);
  const auto [found, hit_descents] = traced_up_z(grid, scene, hit);
  EXPECT_EQ(found.id, id);
  EXPECT_EQ(found.t, 1.5f);
  EXPECT_EQ(hit_descents, 2u);
}

// A node whose cells' content boxes all lie off the ray, though the ray meets its own cell's
// box, is passed by with a test of its summary, without going down into it (Node::boxes): the
// root cut along x into four cells; cell 1 holds one small triangle near each end of its
// y extent and is cut along y, so its content box spans the gap between them. A ray up z
// through the gap goes down into the root alone; one through a triangle goes down into both
// and hits it, as brute force does.
TEST(Grid1DWalk, PassesByANodeWhoseSummaryTheRayMisses) {
  Scene scene;
  test::add_triangle(scene, {1.4f, 0.4f, 0.5f}, {1.6f, 0.4f, 0.5f},
                     {1.5f, 0.6f, 0.5f});  // cell 1, near y = 0.4
  test::add_triangle(scene, {1.4f, 3.4f, 0.5f}, {1.6f, 3.4f, 0.5f},
                     {1.5f, 3.6f, 0.5f});  // cell 1, near y = 3.6
  test::add_triangle(scene, {0.4f, 2.0f, 0.0f}, {0.6f, 2.0f, 1.0f}, {0.5f, 2.1f, 0.5f});  // cell 0
  test::add_triangle(scene, {3.4f, 2.0f, 0.0f}, {3.6f, 2.0f, 1.0f}, {3.5f, 2.1f, 0.5f});  // cell 3
  const std::unique_ptr<Grid1D> grid = built_with_free_cuts(scene, 4, 2);
  ASSERT_EQ(grid->voxel(0).granularity, 4u);
  const Grid1D::Voxel& cell = grid->voxel(grid->voxel(0).first_child + 1);
  ASSERT_EQ(cell.status.load(), Grid1D::kSplit);
  ASSERT_EQ(cell.axis, 1);

  expect_node_passed_by(*grid, scene, {1.5f, 1.7f}, {1.5f, 0.5f}, 0);
}

// A node's summary splits its cells into runs whose boxes are as small as they can be, not
// into fixed quarters (write_summary): the root cut along x into eight cells; cell 1 holds two
// flat triangles over the same x, one in each of the first two of its eight cells along y,
// which one quarter would have held together with the gap between them. A ray up z through
// the gap goes down into the root alone; one through a triangle goes down into both and hits
// it, as brute force does.
TEST(Grid1DWalk, PassesByANodeBetweenTwoClustersOfOneQuarter) {
  Scene scene;
  test::add_triangle(scene, {1.1f, 0.1f, 0.5f}, {1.9f, 0.1f, 0.5f}, {1.5f, 0.3f, 0.5f});  // cell 0
  test::add_triangle(scene, {1.1f, 0.6f, 0.5f}, {1.9f, 0.6f, 0.5f}, {1.5f, 0.9f, 0.5f});  // cell 1
  test::add_triangle(scene, {0.1f, 3.6f, 0.0f}, {0.3f, 3.6f, 1.0f},
                     {0.2f, 3.9f, 0.5f});  // x cell 0
  test::add_triangle(scene, {7.7f, 0.1f, 0.0f}, {7.9f, 0.1f, 1.0f},
                     {7.8f, 0.3f, 0.5f});  // x cell 7
  const std::unique_ptr<Grid1D> grid = built_with_free_cuts(scene, 8, 2);
  ASSERT_EQ(grid->voxel(0).granularity, 8u);
  const Grid1D::Voxel& cell = grid->voxel(grid->voxel(0).first_child + 1);
  ASSERT_EQ(cell.status.load(), Grid1D::kSplit);
  ASSERT_EQ(cell.axis, 1);
  ASSERT_EQ(cell.granularity, 8u);
  ASSERT_EQ(grid->voxel(cell.first_child).tri_count, 1u);
  ASSERT_EQ(grid->voxel(cell.first_child + 1).tri_count, 1u);

  expect_node_passed_by(*grid, scene, {1.5f, 0.45f}, {1.5f, 0.7f}, 1);
}

// The calibration's unit is a searched leaf's triangle (TraceCounters::leaf_triangles): with
// the root kept one leaf of 20 triangles, each of 64 rays crossing the scene box searches it
// once, alone or in a packet: 20 leaf triangles a ray, of which only those whose box the ray
// crosses get a real test.
TEST(Grid1DCounters, EachSearchedLeafCountsItsTrianglesOncePerRay) {
  AccelParams params;
  params.max_granularity = params.max_root_granularity = 1;
  Grid1D grid(params);
  grid.build(test::make_soup(3, 20, glm::vec3(0.0f), glm::vec3(1.0f), 0.2f));
  std::vector<Ray> rays(64);
  for (int i = 0; i < 64; ++i) {
    rays[size_t(i)].origin = {0.1f + 0.8f * float(i % 8) / 7.0f, 0.1f + 0.8f * float(i / 8) / 7.0f,
                              -1.0f};
    rays[size_t(i)].dir = {0.0f, 0.0f, 1.0f};
  }
  const auto single = grid.make_context();
  for (const Ray& ray : rays) grid.intersect(ray, *single);
  ASSERT_EQ(grid.voxel(0).status.load(), Grid1D::kLeaf);
  EXPECT_EQ(single->counters.leaf_triangles, 64u * 20u);
  EXPECT_GT(single->counters.intersection_tests, 0u);
  EXPECT_LT(single->counters.intersection_tests, 64u * 20u);

  const auto packet = grid.make_context();
  std::vector<Hit> hits(64);
  const std::vector<uint64_t> keys(64);
  grid.trace_packet(rays, keys, hits, false, *packet);
  EXPECT_EQ(packet->counters.packet_rays, 64u);
  EXPECT_EQ(packet->counters.leaf_triangles, 64u * 20u);
}

// Rays going different ways (octants) walk as one packet per way, and a way only one ray
// takes is traced as a single ray: of seven rays through the one triangle, three along +z,
// three along -z and one along +z but slightly toward -y, two packets of three walk and one
// ray falls back; each gets the single-ray answer (a hit at t 0.5 from either side).
TEST(Grid1DPackets, EachWayWalksAsItsOwnPacket) {
  Grid1D grid{AccelParams{}};
  grid.build(test::one_triangle());
  std::vector<Ray> rays(7);
  for (int i = 0; i < 7; ++i) {
    const bool down = i % 2 == 0 && i != 0;  // rays 2, 4 and 6
    rays[size_t(i)].origin = {0.1f + 0.04f * float(i), 0.2f, down ? 1.0f : -1.0f};
    rays[size_t(i)].dir = {0.0f, i == 5 ? -0.001f : 0.0f, down ? -2.0f : 2.0f};
  }
  const auto context = grid.make_context();
  std::vector<Hit> hits(7);
  const std::vector<uint64_t> keys(7);
  grid.trace_packet(rays, keys, hits, false, *context);
  for (int i = 0; i < 7; ++i) {
    EXPECT_EQ(hits[size_t(i)], grid.intersect(rays[size_t(i)], *context)) << "ray " << i;
    EXPECT_EQ(hits[size_t(i)].id, 0) << "ray " << i;
    EXPECT_FLOAT_EQ(hits[size_t(i)].t, 0.5f) << "ray " << i;
  }
  EXPECT_EQ(context->counters.packets, 2u);
  EXPECT_EQ(context->counters.packet_rays, 6u);
  EXPECT_EQ(context->counters.packet_fallback_rays, 1u);
}

// A ray from far away (beyond WalkLine::kNearRange scene magnitudes) tests no content box,
// so it walks alone: in a packet of 64 rays one way (+x, +y, -z, z dominant), 32 from above
// the sphere in its soup and 32 from a million scene magnitudes away toward the same
// points, the near ones walk as one packet and the far ones are traced one by one, and
// every ray, nearest and any-hit, gets brute's answer.
TEST(Grid1DPackets, FarRaysWalkAlone) {
  const Scene scene = test::sphere_in_soup();
  const Box box = scene.bounds();
  const glm::vec3 size = box.hi - box.lo, centre = 0.5f * (box.lo + box.hi);
  float magnitude = 0.0f;
  for (int a = 0; a < 3; ++a)
    magnitude = std::max({magnitude, std::fabs(box.lo[a]), std::fabs(box.hi[a])});
  std::vector<Ray> rays(64);
  for (size_t i = 0; i < rays.size(); ++i) {
    const float fx = float(i % 8) / 7.0f, fy = float(i / 8) / 7.0f;
    const glm::vec3 target = box.lo + size * glm::vec3(0.3f + 0.4f * fx, 0.3f + 0.4f * fy, 0.5f);
    const glm::vec3 from = i % 2 == 0 ? centre + size * glm::vec3(-0.5f, -0.5f, 1.5f)
                                      : centre + glm::vec3(-1.0f, -1.0f, 3.0f) * (1e6f * magnitude);
    rays[i].origin = from;
    rays[i].dir = target - from;
  }
  const std::vector<Hit> expected = brute_answers_hitting(scene, rays, rays.size() / 4);
  Grid1D grid{AccelParams{}};
  grid.build(scene);
  const auto context = grid.make_context();
  std::vector<Hit> hits(rays.size()), any(rays.size());
  const std::vector<uint64_t> keys(rays.size());
  grid.trace_packet(rays, keys, hits, false, *context);
  grid.trace_packet(rays, keys, any, true, *context);
  EXPECT_EQ(test::count_mismatches("packet of 64", hits, expected), 0u);
  EXPECT_EQ(test::count_any_hit_mismatches(rays, any, expected), 0u);
  const TraceCounters& counters = context->counters;
  EXPECT_EQ(counters.packets, 2u);
  EXPECT_EQ(counters.packet_rays, 64u);
  EXPECT_EQ(counters.packet_fallback_rays, 64u);
}

// Every ray that enters the scene box goes down through the (cut) root once, so the root's
// traversal state is first used by exactly those rays: an independent count by clipping.
TEST(Grid1DStates, RaysPerStateCountFirstUses) {
  const Case& c = cases()[0];
  Grid1D grid(AccelParams{});
  grid.build(c.scene);
  grid.build_all();
  ASSERT_EQ(grid.voxel(0).status.load(), Grid1D::kSplit);
  test::trace_all(grid, c.rays, 2);  // contexts end with the threads
  const ClipBox box(c.scene.bounds());
  uint64_t entering = 0;
  for (const Ray& ray : c.rays) {
    double t0, t1;
    entering += box.clip(ray, t0, t1);
  }
  EXPECT_EQ(grid.state_rays(grid.voxel(0).state), entering);
}

// The cheapest g the cost report lists on `axis` (the first of equals, as the build takes it).
int cheapest_granularity(const VoxelCostReport& report, int axis) {
  double best = INFINITY;
  int best_g = 0;
  for (const auto& alt : report.alternatives)
    if (alt.axis == axis && alt.cost.total < best) best = alt.cost.total, best_g = alt.granularity;
  return best_g;
}

// The root is cut into at most --max-root-granularity cells, at the cost function's cheapest
// g within that cap, and the voxels below it keep the full range; answers stay brute force's
// for any root cap, 1 (the root is one leaf) included.
TEST(Grid1DBuild, TheRootCapBoundsTheRootAlone) {
  const Case& c = cases()[0];
  AccelParams paper;
  paper.max_root_granularity = paper.max_granularity;
  Grid1D uncapped(paper);
  uncapped.build(c.scene);
  uncapped.build_all();
  ASSERT_GT(int(uncapped.voxel(0).granularity), AccelParams{}.max_root_granularity)
      << c.name << ": the cost function must want more root cells than the cap for this test";

  Grid1D capped{AccelParams{}};
  capped.build(c.scene);
  capped.build_all();
  const Grid1D::Voxel& root = capped.voxel(0);
  ASSERT_EQ(root.status.load(), Grid1D::kSplit);
  const VoxelCostReport report = capped.cost_report(0);
  int widest = 0;
  for (const auto& alt : report.alternatives)
    if (alt.axis == root.axis) widest = std::max(widest, alt.granularity);
  EXPECT_EQ(widest, AccelParams{}.max_root_granularity);
  EXPECT_EQ(int(root.granularity), cheapest_granularity(report, root.axis));
  uint32_t widest_below = 0;
  for (uint32_t id = 1; id < capped.voxel_count(); ++id)
    if (capped.voxel(id).status.load() == Grid1D::kSplit)
      widest_below = std::max<uint32_t>(widest_below, capped.voxel(id).granularity);
  EXPECT_GT(int(widest_below), AccelParams{}.max_root_granularity);

  for (int root_cap : {1, 3}) {
    AccelParams params;
    params.max_root_granularity = root_cap;
    Grid1D lazy(params), eager(params);
    expect_lazy_and_eager_match(c.scene, c.rays, c.expected, lazy, eager);
    EXPECT_EQ(eager.voxel(0).status.load(), root_cap == 1 ? Grid1D::kLeaf : Grid1D::kSplit);
  }
}

// The inspector's cost report is the build's own decision, recomputed.
TEST(Grid1DStates, CostReportReproducesTheCut) {
  const Case& c = cases()[0];
  Grid1D grid(AccelParams{});
  grid.build(c.scene);
  grid.build_all();
  size_t checked = 0;
  for (uint32_t id = 0; id < grid.voxel_count() && checked < 200; ++id) {
    const Grid1D::Voxel& voxel = grid.voxel(id);
    if (voxel.status.load() != Grid1D::kSplit) continue;
    const VoxelCostReport report = grid.cost_report(id);
    EXPECT_EQ(report.axis, voxel.axis);
    EXPECT_EQ(report.granularity, voxel.granularity);
    EXPECT_EQ(report.figures.triangles, voxel.tri_count);
    EXPECT_EQ(report.depth, grid.voxel_depth(id));
    double lo[3], hi[3];
    grid.voxel_box(id, lo, hi);
    for (int a = 0; a < 3; ++a) EXPECT_EQ(report.figures.extent[a], hi[a] - lo[a]);
    // The alternation rule cut along depth % 3 at the cheapest g: the minimum over the
    // listed alternatives on that axis.
    EXPECT_EQ(int(voxel.axis), int(report.depth % 3));
    EXPECT_EQ(cheapest_granularity(report, voxel.axis), int(voxel.granularity));
    ++checked;
  }
  EXPECT_GT(checked, 10u);
}

// The cost function's mean triangle sizes (§6.3), which the build measures only along the
// axes it plans and the report along all three: at the root, over every usable triangle,
// each one's padded extent on the axis clipped to the scene's padded box, as a direct sum
// over the scene's own corners.
TEST(Grid1DStates, CostReportMeanSizesAreTheClippedExtents) {
  for (const Case& c : cases()) {
    Grid1D grid(AccelParams{});
    grid.build(c.scene);
    const VoxelCostReport report = grid.cost_report(0);
    const double padding = ClipBox(c.scene.bounds()).padding;
    double lo[3], hi[3];
    grid.voxel_box(0, lo, hi);
    for (int a = 0; a < 3; ++a) {
      double sum = 0.0;
      size_t usable = 0;
      for (uint32_t t = 0; t < c.scene.triangle_count(); ++t) {
        if (c.scene.is_degenerate(t)) continue;
        double low = INFINITY, high = -INFINITY;
        for (int k = 0; k < 3; ++k) {
          low = std::min(low, double(c.scene.vertex(t, k)[a]));
          high = std::max(high, double(c.scene.vertex(t, k)[a]));
        }
        sum += std::max(0.0, std::min(high + padding, hi[a]) - std::max(low - padding, lo[a]));
        ++usable;
      }
      ASSERT_GT(usable, 0u) << c.name;
      EXPECT_NEAR(report.figures.mean_size[a], sum / double(usable), 1e-12 * (hi[a] - lo[a]))
          << c.name << " axis " << a;
    }
  }
}

}  // namespace
}  // namespace gs
