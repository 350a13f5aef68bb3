// The nested 3D grid (grid3d) and the SAH BVH (bvh) must give exactly brute's answers
// (same id, t, u, v) on every ray, for several parameter settings, lazy or eager, with one
// thread or two; and survive degenerate and numerically hard input.
#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <set>

#include "core/accel/brute.h"
#include "core/accel/bvh.h"
#include "core/accel/grid3d.h"
#include "tests/test_util.h"

namespace gs {
namespace {

// A structure setting: which structure, its parameters, how it is built and traced.
struct Config {
  std::string accel;
  int depth;  // grid3d levels (0: default)
  int leaf;
  bool eager;
  int threads;
};

std::string config_name(const testing::TestParamInfo<Config>& info) {
  const Config& c = info.param;
  std::string name = c.accel;
  name += "_d" + std::to_string(c.depth);
  name += "_leaf" + std::to_string(c.leaf);
  name += c.eager ? "_eager" : "_lazy";
  name += "_t" + std::to_string(c.threads);
  return name;
}

std::unique_ptr<Accelerator> make(const Config& config, const Scene& scene) {
  AccelParams params;
  params.max_depth = config.depth;
  params.leaf_size = config.leaf;
  auto accel = make_accelerator(config.accel, params);
  accel->build(scene);
  if (config.eager) accel->build_all();
  return accel;
}

using Case = test::BruteCase;

// Camera rays, chords (a fifth with -0.0 or 1e-30 components), axis-parallel rays and
// rays aimed exactly at edges and vertices.
std::vector<Ray> mixed_rays(const Scene& scene, int scale) {
  const Box box = scene.bounds();
  std::vector<Ray> rays = test::camera_rays(box, 12 * scale, 10 * scale);
  std::vector<Ray> chords = test::random_chords(box, 1, 800 * scale);
  for (size_t i = 0; i < chords.size(); i += 5) chords[i].dir[i % 3] = (i % 2) ? -0.0f : 1e-30f;
  for (const auto& set : {chords, test::axis_parallel_rays(box, 2, 500 * scale),
                          test::edge_and_vertex_rays(scene, 3, 500 * scale)})
    rays.insert(rays.end(), set.begin(), set.end());
  return rays;
}

std::vector<Case>& cases() {
  static std::vector<Case> all = [] {
    std::vector<std::pair<std::string, Scene>> scenes;
    scenes.emplace_back("pyramid", make_builtin_scene("pyramid"));
    scenes.emplace_back(
        "sphere+soup",
        test::merge(test::make_sphere({0.3f, -0.2f, 0.1f}, 1.0f, 24, 48),
                    test::make_soup(11, 1500, glm::vec3(-1.5f), glm::vec3(1.5f), 0.1f)));
    scenes.emplace_back("stadium", test::stadium_scene(2000));
    scenes.emplace_back("wall planes", test::wall_planes_scene());
    std::vector<Case> out;
    for (auto& [name, scene] : scenes) {
      Case c{name, scene, mixed_rays(scene, 6), {}};
      c.expected = test::brute_answers(c.scene, c.rays);
      out.push_back(std::move(c));
    }
    return out;
  }();
  return all;
}

// Rays whose answers differ from `expected`; the first few are reported.
size_t mismatches(const std::string& what, const std::vector<Hit>& hits,
                  const std::vector<Hit>& expected) {
  size_t bad = 0;
  for (size_t i = 0; i < hits.size(); ++i) {
    if (hits[i] == expected[i]) continue;
    if (++bad <= 5)
      ADD_FAILURE() << what << " ray " << i << ": id " << hits[i].id << " t " << hits[i].t << " u "
                    << hits[i].u << ", brute id " << expected[i].id << " t " << expected[i].t
                    << " u " << expected[i].u;
  }
  return bad;
}

class MatchesBrute : public testing::TestWithParam<Config> {};

TEST_P(MatchesBrute, SameHitOnEveryRay) {
  size_t checked = 0;
  for (const Case& c : cases()) {
    const auto accel = make(GetParam(), c.scene);
    const std::vector<Hit> hits = test::trace_all(*accel, c.rays, GetParam().threads);
    EXPECT_EQ(mismatches(c.name, hits, c.expected), 0u) << c.name;
    if (c.name == "stadium" && GetParam().depth != 1) {
      EXPECT_GT(*accel->stats().voxels_subdivided, 0u) << c.name;
    }
    checked += hits.size();
  }
  RecordProperty("rays_checked", int(checked));
}

TEST_P(MatchesBrute, AnyHitFoundIffBruteFound) {
  for (const Case& c : cases()) {
    const auto accel = make(GetParam(), c.scene);
    const std::vector<Hit> hits = test::trace_all(*accel, c.rays, GetParam().threads, true);
    size_t bad = 0;
    for (size_t i = 0; i < hits.size(); ++i)
      bad += hits[i].found() != c.expected[i].found() ||
             (hits[i].found() && !(hits[i].t > c.rays[i].tmin && hits[i].t <= c.rays[i].tmax &&
                                   hits[i].t >= c.expected[i].t));
    EXPECT_EQ(bad, 0u) << c.name;
  }
}

std::vector<Config> configs() {
  return {{"grid3d", 3, 16, false, 1}, {"grid3d", 3, 16, false, 2}, {"grid3d", 3, 16, true, 2},
          {"grid3d", 1, 16, false, 1}, {"grid3d", 2, 4, false, 2},  {"grid3d", 2, 64, true, 1},
          {"grid3d", 3, 4, true, 1},   {"grid3d", 3, 64, false, 2}, {"bvh", 0, 1, false, 1},
          {"bvh", 0, 4, false, 2},     {"bvh", 0, 16, false, 1}};
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
    EXPECT_EQ(mismatches(c.name, hits, c.expected), 0u);
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
  std::vector<Ray> rays;
  for (int y = 0; y < 50; ++y)
    for (int x = 0; x < 50; ++x) {
      Ray ray;
      ray.origin = {-9.0f + x * 0.01f, -9.0f + y * 0.01f, -11.0f};
      ray.dir = {0.0f, 0.0f, 1.0f};
      rays.push_back(ray);
    }
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
// threads): rays whose answers differ.
size_t disagreements(const Scene& scene, const std::vector<Ray>& rays) {
  BruteForce brute;
  brute.build(scene);
  const std::vector<Hit> expected = test::trace_all(brute, rays, 2);
  size_t bad = 0;
  for (const Config& config : {Config{"grid3d", 0, 0, false, 1}, Config{"grid3d", 0, 0, false, 2},
                               Config{"grid3d", 0, 4, true, 2}, Config{"bvh", 0, 0, false, 1},
                               Config{"bvh", 0, 1, false, 2}}) {
    const auto accel = make(config, scene);
    bad += mismatches(config_name({config, 0}), test::trace_all(*accel, rays, config.threads),
                      expected);
  }
  return bad;
}

Scene sphere_and_soup() {
  return test::merge(test::make_sphere({0.1f, 0.2f, -0.1f}, 1.0f, 16, 32),
                     test::make_soup(21, 1200, glm::vec3(-1.2f), glm::vec3(1.2f), 0.08f));
}

TEST(Stress, MovedAndScaledScenes) {
  const Scene base = sphere_and_soup();
  for (const auto& [scale, offset] :
       {std::pair{1e-4f, glm::vec3(0.0f)}, std::pair{1e4f, glm::vec3(0.0f)},
        std::pair{1.0f, glm::vec3(1e6f, -1e6f, 1e6f)}}) {
    const Scene scene = test::transformed(base, scale, offset);
    EXPECT_EQ(disagreements(scene, mixed_rays(scene, 3)), 0u)
        << "scale " << scale << " offset " << offset.x;
  }
}

TEST(Stress, ThousandsOfCoincidentTriangles) {
  Scene scene = test::make_soup(4, 300, glm::vec3(-1.0f), glm::vec3(1.0f), 0.1f);
  const uint32_t base = uint32_t(scene.vertices.size());
  scene.vertices.insert(scene.vertices.end(),
                        {{-0.5f, -0.5f, 0.2f}, {0.5f, -0.4f, 0.2f}, {0.0f, 0.6f, 0.25f}});
  for (int i = 0; i < 5000; ++i) scene.triangles.emplace_back(base, base + 1, base + 2);
  std::vector<Ray> rays = mixed_rays(scene, 1);
  EXPECT_EQ(disagreements(scene, rays), 0u);
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
  Scene flat =
      test::make_soup(9, 3000, glm::vec3(-1.0f, -1.0f, 0.0f), glm::vec3(1.0f, 1.0f, 0.0f), 0.05f);
  for (glm::vec3& v : flat.vertices) v.z = 0.0f;
  std::vector<Ray> rays = test::random_chords({{-1, -1, -1}, {1, 1, 1}}, 3, 3000);
  const auto edges = test::edge_and_vertex_rays(flat, 4, 2000);
  rays.insert(rays.end(), edges.begin(), edges.end());
  EXPECT_EQ(disagreements(flat, rays), 0u);

  for (const std::string name : {"grid3d", "bvh"}) {
    const auto empty = make_accelerator(name, AccelParams{});
    empty->build(Scene{});
    for (const Hit& hit : test::trace_all(*empty, rays, 2)) EXPECT_EQ(hit, Hit{});
    EXPECT_TRUE(test::trace_all(*empty, {}, 2).empty());

    Scene one;
    one.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    one.triangles = {{0, 1, 2}};
    const auto single = make_accelerator(name, AccelParams{});
    single->build(one);
    Ray ray;
    ray.origin = {0.2f, 0.3f, -1.0f};
    ray.dir = {0.0f, 0.0f, 2.0f};
    const Hit hit = single->intersect(ray, *single->make_context());
    EXPECT_EQ(hit.id, 0) << name;
    EXPECT_FLOAT_EQ(hit.t, 0.5f) << name;
    EXPECT_FLOAT_EQ(hit.u, 0.2f) << name;
    EXPECT_FLOAT_EQ(hit.v, 0.3f) << name;
  }
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
    const auto accel = make_accelerator(name, AccelParams{});
    accel->build(sphere);
    size_t escaped = 0;
    for (const Hit& hit : test::trace_all(*accel, rays, 2)) escaped += !hit.found();
    EXPECT_EQ(escaped, 0u) << name;
  }
}

}  // namespace
}  // namespace gs
