// The nested 3D grid (grid3d) and the SAH BVH (bvh) must give exactly brute's answers
// (same id, t, u, v) on every ray, for several parameter settings, lazy or eager, with one
// thread or two; and survive degenerate and numerically hard input.
#include <gtest/gtest.h>

#include <cstdio>
#include <set>
#include <span>

#include "core/accel/bvh.h"
#include "core/accel/grid3d.h"
#include "tests/cases.h"

namespace gs {
namespace {

// A structure setting: which structure, its depth (grid3d levels; 0: default) and leaf size,
// lazy or eager, traced by one thread or two.
test::StructureRun config(const std::string& accel, int depth, int leaf, bool eager, int threads) {
  AccelParams params;
  params.max_depth = depth;
  params.leaf_size = leaf;
  return {accel, params, false, eager, threads};
}

std::string config_name(const testing::TestParamInfo<test::StructureRun>& info) {
  const test::StructureRun& c = info.param;
  std::string name = c.accel;
  name += "_d" + std::to_string(c.params.max_depth);
  name += "_leaf" + std::to_string(c.params.leaf_size);
  name += c.eager ? "_eager" : "_lazy";
  name += "_t" + std::to_string(c.threads);
  return name;
}

using Case = test::BruteCase;

// Camera rays, chords (a fifth with -0.0 or 1e-30 components), axis-parallel rays and
// rays aimed exactly at edges and vertices.
std::vector<Ray> mixed_rays(const Scene& scene, int scale) {
  const test::RayMix mix{.camera_width = 12 * scale,
                         .camera_height = 10 * scale,
                         .chords = 800 * scale,
                         .axis_parallel = 500 * scale,
                         .edges_and_vertices = 500 * scale};
  std::vector<Ray> rays = test::mixed_rays(scene, mix);
  const std::span<Ray> chords = std::span(rays).subspan(mix.camera_count(), size_t(mix.chords));
  test::set_negative_zero_or_tiny_components(chords, 5);
  return rays;
}

const std::vector<Case>& cases() {
  static const std::vector<Case> all =
      test::brute_cases(test::comparison_scenes(2000, test::wall_planes_scene()),
                        [](const test::NamedScene& s) { return mixed_rays(s.scene, 6); });
  return all;
}

class MatchesBrute : public testing::TestWithParam<test::StructureRun> {};

TEST_P(MatchesBrute, SameHitOnEveryRay) {
  const int depth = GetParam().params.max_depth;
  const size_t checked =
      test::expect_brute_answers(cases(), GetParam(), test::Answers::nearest,
                                 [depth](const Case& c, const Accelerator& accel) {
                                   if (c.name == "stadium" && depth != 1) {
                                     EXPECT_GT(*accel.stats().voxels_subdivided, 0u) << c.name;
                                   }
                                 });
  RecordProperty("rays_checked", int(checked));
}

TEST_P(MatchesBrute, AnyHitFoundIffBruteFound) {
  test::expect_brute_answers(cases(), GetParam(), test::Answers::any_hit);
}

std::vector<test::StructureRun> configs() {
  return {config("grid3d", 3, 16, false, 1), config("grid3d", 3, 16, false, 2),
          config("grid3d", 3, 16, true, 2),  config("grid3d", 1, 16, false, 1),
          config("grid3d", 2, 4, false, 2),  config("grid3d", 2, 64, true, 1),
          config("grid3d", 3, 4, true, 1),   config("grid3d", 3, 64, false, 2),
          config("bvh", 0, 1, false, 1),     config("bvh", 0, 4, false, 2),
          config("bvh", 0, 16, false, 1)};
}

INSTANTIATE_TEST_SUITE_P(Settings, MatchesBrute, testing::ValuesIn(configs()), config_name);

// The grids a structure has built, by box and resolution.
std::multiset<std::vector<double>> grids_of(const NestedGrid& grid) {
  std::multiset<std::vector<double>> out;
  for (uint32_t id = 0; id < grid.grid_count(); ++id) {
    const NestedGrid::GridNode& g = grid.grid(id);
    out.insert({g.lo[0], g.lo[1], g.lo[2], g.hi[0], g.hi[1], g.hi[2], double(g.res[0]),
                double(g.res[1]), double(g.res[2]), double(g.depth)});
  }
  return out;
}

// Two threads reaching unbuilt cells at once build only grids the eager build has, and
// after build_all exactly its grids (each sub-grid is a function of its cell). Run under
// ThreadSanitizer by scripts/test.sh.
TEST(Grid3DBuild, LazyTwoThreadsBuildTheSameGridsAsEager) {
  for (const Case& c : cases()) {
    AccelParams params;
    NestedGrid lazy(params), eager(params);
    lazy.build(c.scene);
    eager.build(c.scene);
    eager.build_all();
    const std::vector<Hit> hits = test::trace_all(lazy, c.rays, 2);
    EXPECT_EQ(test::count_mismatches(c.name, hits, c.expected), 0u);
    const auto lazy_grids = grids_of(lazy), eager_grids = grids_of(eager);
    EXPECT_TRUE(
        std::includes(eager_grids.begin(), eager_grids.end(), lazy_grids.begin(), lazy_grids.end()))
        << c.name;
    lazy.build_all();
    EXPECT_EQ(grids_of(lazy), eager_grids) << c.name;
    if (c.name == "stadium") {
      EXPECT_GT(eager.grid_count(), 1u) << c.name;
    }
  }
}

// Rays that see one corner of a large scene build a small part of what --eager does.
TEST(Grid3DBuild, PartialViewBuildsFewerGrids) {
  const Scene scene = test::make_soup(17, 30000, glm::vec3(-10.0f), glm::vec3(10.0f), 0.3f);
  const std::vector<Ray> rays = test::corner_view_rays(50);
  AccelParams params;
  params.leaf_size = 2;
  NestedGrid lazy(params), eager(params);
  lazy.build(scene);
  eager.build(scene);
  eager.build_all();
  test::trace_all(lazy, rays, 2);
  std::printf("grid3d laziness: %zu grids lazy, %zu eager\n", lazy.grid_count(),
              eager.grid_count());
  EXPECT_LT(lazy.grid_count() * 5, eager.grid_count());
}

// Brute against each structure (grid3d lazy and eager, 1 and 2 threads; bvh 1 and 2
// threads): the (structure, ray) pairs whose answers differ.
size_t disagreements(const Scene& scene, const std::vector<Ray>& rays) {
  return test::disagreements(scene, rays,
                             {config("grid3d", 0, 0, false, 1), config("grid3d", 0, 0, false, 2),
                              config("grid3d", 0, 4, true, 2), config("bvh", 0, 0, false, 1),
                              config("bvh", 0, 1, false, 2)});
}

TEST(Stress, MovedAndScaledScenes) {
  for (const test::NamedScene& moved : test::moved_and_scaled(test::small_sphere_in_soup()))
    EXPECT_EQ(disagreements(moved.scene, mixed_rays(moved.scene, 3)), 0u) << moved.name;
}

TEST(Stress, ThousandsOfCoincidentTriangles) {
  const Scene scene = test::coincident_scene();
  EXPECT_EQ(disagreements(scene, mixed_rays(scene, 1)), 0u);
  for (int leaf : {1, 16}) {
    AccelParams params;
    params.leaf_size = leaf;
    NestedGrid grid(params);
    grid.build(scene);
    grid.build_all();
    // Bounded: each grid holds at most 8 references per triangle it sorts.
    EXPECT_LT(grid.stats().memory_bytes, uint64_t{64} << 20) << "leaf " << leaf;
    std::printf("coincident, leaf %d: %zu grids, %llu bytes\n", leaf, grid.grid_count(),
                (unsigned long long)grid.stats().memory_bytes);
  }
}

TEST(Stress, FlatSceneEmptySceneOneTriangleNoRays) {
  const Scene flat = test::flat_scene();
  const std::vector<Ray> rays = test::flat_scene_rays(flat, 3000, 2000);
  EXPECT_EQ(disagreements(flat, rays), 0u);
  for (const std::string name : {"grid3d", "bvh"})
    test::expect_empty_and_one_triangle_answers(name, rays);
}

// A closed sphere far from the origin, shot from points inside it: no ray escapes
// (watertight kernel, and no structure loses a triangle near a wall).
TEST(Stress, ClosedSphereFarFromOriginNoEscapes) {
  const glm::vec3 centre(3e4f, -2e4f, 1e4f);
  const Scene sphere = test::make_sphere(centre, 10.0f, 40, 80);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::vector<Ray> rays;
  for (int i = 0; i < 6000; ++i) {
    Ray ray;
    ray.origin = centre + 5.0f * glm::vec3(unit(rng), unit(rng), unit(rng));
    ray.dir = {unit(rng), unit(rng), unit(rng)};
    if (i % 4 == 0) ray.dir[i % 3] = 0.0f;
    rays.push_back(ray);
  }
  EXPECT_EQ(disagreements(sphere, rays), 0u);
  for (const std::string name : {"grid3d", "bvh"}) {
    const auto accel = test::build_structure({.accel = name}, sphere);
    size_t escaped = 0;
    for (const Hit& hit : test::trace_all(*accel, rays, 2)) escaped += !hit.found();
    EXPECT_EQ(escaped, 0u) << name;
  }
}

}  // namespace
}  // namespace gs
