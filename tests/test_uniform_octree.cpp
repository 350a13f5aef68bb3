// The uniform grid and the octree must give exactly brute's answers (same id, t, u, v) on
// every ray, for every parameter setting, with one thread or two; any_hit finds a hit iff
// brute does; numerical stress and degenerate input still give brute's answers, and every
// build ends with bounded memory.
#include <gtest/gtest.h>

#include <cstdio>
#include <glm/vec2.hpp>
#include <memory>

#include "core/accel/brute.h"
#include "core/accel/octree.h"
#include "core/accel/uniform_grid.h"
#include "tests/test_util.h"

namespace gs {
namespace {

struct Setting {
  std::string accel;  // "uniform" or "octree"
  double density = 0.0;
  int depth = 0;
  int leaf = 0;
  int threads = 1;
};

std::unique_ptr<Accelerator> make(const Setting& s, const Scene& scene) {
  AccelParams params;
  params.density = s.density;
  params.max_depth = s.depth;
  params.leaf_size = s.leaf;
  auto accel = make_accelerator(s.accel, params);
  accel->build(scene);
  return accel;
}

std::string setting_name(const testing::TestParamInfo<Setting>& info) {
  const Setting& s = info.param;
  std::string name = s.accel;  // built by appending: GCC 12 warns falsely on "literal" + string
  if (s.accel == "uniform") {
    name += "_density";
    name += s.density == 0.0 ? "default" : std::to_string(int(s.density * 10)) + "tenths";
  } else {
    name += "_depth" + std::to_string(s.depth) + "_leaf" + std::to_string(s.leaf);
  }
  name += "_t" + std::to_string(s.threads);
  return name;
}

using Case = test::BruteCase;

// Quads in the planes x, y, z = k/4 - 1 of the box [-1, 1]^3. The box is symmetric, so the
// planes through 0 lie exactly on the octree's root mid-planes and on the uniform grid's
// middle walls (even n); the others lie within float rounding of walls.
Scene wall_planes() {
  Scene scene;
  for (int k = 0; k <= 8; ++k) {
    const float c = k / 4.0f - 1.0f;
    for (int a = 0; a < 3; ++a) {
      const uint32_t b = uint32_t(scene.vertices.size());
      for (const glm::vec2 q : {glm::vec2(-0.9f, -0.9f), glm::vec2(0.9f, -0.9f),
                                glm::vec2(0.9f, 0.9f), glm::vec2(-0.9f, 0.9f)}) {
        glm::vec3 v;
        v[a] = c, v[(a + 1) % 3] = q.x, v[(a + 2) % 3] = q.y;
        scene.vertices.push_back(v);
      }
      scene.triangles.emplace_back(b, b + 1, b + 2);
      scene.triangles.emplace_back(b, b + 2, b + 3);
    }
  }
  return test::merge(scene, test::make_soup(3, 500, glm::vec3(-1), glm::vec3(1), 0.04f));
}

// Rays starting on the planes through 0 and running inside them.
std::vector<Ray> in_plane_rays(uint32_t seed, int count) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::vector<Ray> rays;
  for (int i = 0; i < count; ++i) {
    Ray ray;
    ray.origin = {unit(rng), unit(rng), unit(rng)};
    ray.dir = {unit(rng), unit(rng), unit(rng)};
    const int a = i % 3;
    ray.origin[a] = 0.0f;
    if (i % 2) ray.dir[a] = (i % 4 == 1) ? 0.0f : -0.0f;
    rays.push_back(ray);
  }
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
    scenes.emplace_back("stadium", test::stadium_scene(2500));
    scenes.emplace_back("wall planes", wall_planes());
    std::vector<Case> out;
    for (auto& [name, scene] : scenes) {
      Case c{name, scene, {}, {}};
      const Box box = scene.bounds();
      for (const auto& set :
           {test::camera_rays(box, 80, 75), test::random_chords(box, 1, 6000),
            test::axis_parallel_rays(box, 2, 4000), test::edge_and_vertex_rays(scene, 3, 5000)})
        c.rays.insert(c.rays.end(), set.begin(), set.end());
      if (name == "wall planes") {
        const auto planar = in_plane_rays(4, 3000);
        c.rays.insert(c.rays.end(), planar.begin(), planar.end());
      }
      c.expected = test::brute_answers(c.scene, c.rays);
      out.push_back(std::move(c));
    }
    return out;
  }();
  return all;
}

class MatchesBrute : public testing::TestWithParam<Setting> {};

TEST_P(MatchesBrute, SameIdTAndUvOnEveryRay) {
  const Setting& setting = GetParam();
  size_t checked = 0;
  for (const Case& c : cases()) {
    const auto accel = make(setting, c.scene);
    const std::vector<Hit> hits = test::trace_all(*accel, c.rays, setting.threads);
    size_t mismatches = 0;
    for (size_t i = 0; i < hits.size(); ++i) {
      if (hits[i] == c.expected[i]) continue;
      if (++mismatches <= 5)
        ADD_FAILURE() << c.name << " ray " << i << ": " << setting.accel << " id " << hits[i].id
                      << " t " << hits[i].t << ", brute id " << c.expected[i].id << " t "
                      << c.expected[i].t;
    }
    EXPECT_EQ(mismatches, 0u) << c.name;
    EXPECT_GT(*accel->stats().leaves, 1u) << c.name << ": nothing was subdivided";
    checked += hits.size();
  }
  RecordProperty("rays_checked", int(checked));
}

TEST_P(MatchesBrute, AnyHitFindsAHitIffBruteDoes) {
  const Setting& setting = GetParam();
  for (const Case& c : cases()) {
    const auto accel = make(setting, c.scene);
    const std::vector<Hit> hits = test::trace_all(*accel, c.rays, setting.threads, true);
    size_t mismatches = 0;
    for (size_t i = 0; i < hits.size(); ++i) {
      const bool ok =
          hits[i].found() == c.expected[i].found() &&
          (!hits[i].found() || (hits[i].t > c.rays[i].tmin && hits[i].t <= c.rays[i].tmax &&
                                hits[i].t >= c.expected[i].t));
      mismatches += !ok;
    }
    EXPECT_EQ(mismatches, 0u) << c.name;
  }
}

std::vector<Setting> settings() {
  std::vector<Setting> out;
  for (int threads : {1, 2}) {
    for (double density : {0.0, 0.5, 4.0}) out.push_back({"uniform", density, 0, 0, threads});
    for (int depth : {3, 6, 8})
      for (int leaf : {1, 4, 16}) out.push_back({"octree", 0.0, depth, leaf, threads});
  }
  return out;
}

INSTANTIATE_TEST_SUITE_P(Settings, MatchesBrute, testing::ValuesIn(settings()), setting_name);

// Numerical stress: each scene through both structures (two settings each, 1 and 2
// threads); counts the rays whose answers differ from brute's.
size_t disagreements(const Scene& scene, const std::vector<Ray>& rays) {
  const std::vector<Hit> expected = test::brute_answers(scene, rays);
  size_t bad = 0;
  for (const Setting& s : {Setting{"uniform", 0.0, 0, 0, 1}, Setting{"uniform", 4.0, 0, 0, 2},
                           Setting{"octree", 0.0, 0, 0, 2}, Setting{"octree", 0.0, 8, 1, 1}}) {
    const auto accel = make(s, scene);
    const std::vector<Hit> hits = test::trace_all(*accel, rays, s.threads);
    for (size_t i = 0; i < rays.size(); ++i)
      if (!(hits[i] == expected[i]) && ++bad <= 3)
        ADD_FAILURE() << "ray " << i << " (" << s.accel << " depth " << s.depth << " density "
                      << s.density << "): " << hits[i].id << " t " << hits[i].t << ", brute "
                      << expected[i].id << " t " << expected[i].t;
  }
  return bad;
}

Scene sphere_and_soup() {
  return test::merge(test::make_sphere({0.1f, 0.2f, -0.1f}, 1.0f, 16, 32),
                     test::make_soup(21, 1200, glm::vec3(-1.2f), glm::vec3(1.2f), 0.08f));
}

std::vector<Ray> mixed_rays(const Scene& scene) {
  std::vector<Ray> rays = test::camera_rays(scene.bounds(), 50, 50);
  for (const auto& set : {test::random_chords(scene.bounds(), 5, 3000),
                          test::axis_parallel_rays(scene.bounds(), 6, 2000),
                          test::edge_and_vertex_rays(scene, 7, 2000)})
    rays.insert(rays.end(), set.begin(), set.end());
  return rays;
}

TEST(Stress, NegativeZeroAndTinyDirectionComponents) {
  const Scene scene = sphere_and_soup();
  std::vector<Ray> rays = test::random_chords(scene.bounds(), 8, 5000);
  for (size_t i = 0; i < rays.size(); ++i) {
    rays[i].dir[i % 3] = (i % 2) ? -0.0f : 1e-30f;
    if (i % 5 == 0) rays[i].dir[(i + 1) % 3] = -1e-30f;
  }
  EXPECT_EQ(disagreements(scene, rays), 0u);
}

TEST(Stress, MovedAndScaledScenes) {
  const Scene base = sphere_and_soup();
  for (const auto& [scale, offset] :
       {std::pair{1e-4f, glm::vec3(0.0f)}, std::pair{1e4f, glm::vec3(0.0f)},
        std::pair{1.0f, glm::vec3(1e6f, -1e6f, 1e6f)}}) {
    const Scene scene = test::transformed(base, scale, offset);
    EXPECT_EQ(disagreements(scene, mixed_rays(scene)), 0u)
        << "scale " << scale << " offset " << offset.x;
  }
}

TEST(Stress, ThousandsOfCoincidentTrianglesEndWithBoundedMemory) {
  Scene scene = test::make_soup(4, 300, glm::vec3(-1.0f), glm::vec3(1.0f), 0.1f);
  const uint32_t base = uint32_t(scene.vertices.size());
  scene.vertices.insert(scene.vertices.end(),
                        {{-0.5f, -0.5f, 0.2f}, {0.5f, -0.4f, 0.2f}, {0.0f, 0.6f, 0.25f}});
  for (int i = 0; i < 5000; ++i) scene.triangles.emplace_back(base, base + 1, base + 2);
  EXPECT_EQ(disagreements(scene, mixed_rays(scene)), 0u);
  UniformGrid grid(AccelParams{});
  grid.build(scene);
  AccelParams deep;
  deep.max_depth = 8, deep.leaf_size = 1;
  Octree octree(deep);
  octree.build(scene);
  std::printf("coincident: uniform %llu cells, %llu references; octree %zu nodes, %llu refs\n",
              (unsigned long long)grid.cell_count(), (unsigned long long)grid.references(),
              octree.nodes().size(), (unsigned long long)octree.references());
  EXPECT_LT(grid.references(), 5000u * 400u);
  EXPECT_LT(octree.references(), 5000u * 400u);  // cuts that separate nothing are not made
  EXPECT_LT(octree.nodes().size(), 200000u);
}

TEST(Stress, EverythingInOnePlane) {
  Scene scene =
      test::make_soup(9, 3000, glm::vec3(-1.0f, -1.0f, 0.0f), glm::vec3(1.0f, 1.0f, 0.0f), 0.05f);
  for (glm::vec3& v : scene.vertices) v.z = 0.0f;
  UniformGrid grid(AccelParams{});
  grid.build(scene);
  EXPECT_EQ(grid.resolution()[2], 1u);  // one cell across the flat axis
  EXPECT_GT(grid.cell_count(), 1000u);
  std::vector<Ray> rays = test::random_chords({{-1, -1, -1}, {1, 1, 1}}, 3, 6000);
  const auto edges = test::edge_and_vertex_rays(scene, 4, 3000);
  rays.insert(rays.end(), edges.begin(), edges.end());
  EXPECT_EQ(disagreements(scene, rays), 0u);
}

TEST(Stress, EmptySceneOneTriangleAndNoRays) {
  const std::vector<Ray> rays = test::random_chords({{-1, -1, -1}, {1, 1, 1}}, 3, 100);
  for (const std::string name : {"uniform", "octree"}) {
    const auto empty = make({name}, Scene{});
    for (const Hit& hit : test::trace_all(*empty, rays, 2)) EXPECT_EQ(hit, Hit{});
    EXPECT_TRUE(test::trace_all(*empty, {}, 2).empty());

    Scene one;
    one.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    one.triangles = {{0, 1, 2}};
    const auto single = make({name}, one);
    Ray ray;
    ray.origin = {0.2f, 0.3f, -1.0f};
    ray.dir = {0.0f, 0.0f, 2.0f};
    auto context = single->make_context();
    const Hit hit = single->intersect(ray, *context);
    EXPECT_EQ(hit.id, 0) << name;
    EXPECT_FLOAT_EQ(hit.t, 0.5f);
    EXPECT_FLOAT_EQ(hit.u, 0.2f);
    EXPECT_FLOAT_EQ(hit.v, 0.3f);
  }
  Scene one;
  one.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  one.triangles = {{0, 1, 2}};
  EXPECT_EQ(disagreements(one, mixed_rays(one)), 0u);
}

// A closed (watertight) sphere far from the origin, shot from inside in every direction:
// every ray must hit it (none escapes through a crack between cells or triangles).
TEST(Stress, ClosedSphereFarAwayShotFromInsideHasNoEscapes) {
  const glm::vec3 centre(2e4f, -3e4f, 1e4f);
  const Scene scene = test::make_sphere(centre, 5.0f, 32, 64);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::vector<Ray> rays;
  while (rays.size() < 20000) {
    const glm::vec3 offset(unit(rng), unit(rng), unit(rng));
    if (glm::length(offset) > 1.0f) continue;
    Ray ray;
    ray.origin = centre + 3.0f * offset;
    ray.dir = {unit(rng), unit(rng), unit(rng)};
    if (rays.size() % 7 == 0) ray.dir[rays.size() % 3] = 0.0f;
    rays.push_back(ray);
  }
  const std::vector<Hit> expected = test::brute_answers(scene, rays);
  for (const std::string name : {"uniform", "octree"}) {
    const auto accel = make({name}, scene);
    const std::vector<Hit> hits = test::trace_all(*accel, rays, 2);
    size_t escapes = 0, mismatches = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
      escapes += !hits[i].found();
      mismatches += !(hits[i] == expected[i]);
    }
    EXPECT_EQ(escapes, 0u) << name;
    EXPECT_EQ(mismatches, 0u) << name;
  }
}

// The paper's setting: about cbrt(N) cells per side, N cells in all, as cubic as the box's
// aspect allows; --density scales the total.
TEST(UniformGridBuild, ResolutionFollowsTriangleCountAspectAndDensity) {
  const Scene cube = test::make_soup(2, 8000, glm::vec3(-1.0f), glm::vec3(1.0f), 0.05f);
  UniformGrid grid(AccelParams{});
  grid.build(cube);
  for (uint32_t n : grid.resolution()) EXPECT_NEAR(double(n), 20.0, 1.0);  // cbrt(8000)
  AccelParams dense;
  dense.density = 8.0;
  UniformGrid fine(dense);
  fine.build(cube);
  for (uint32_t n : fine.resolution()) EXPECT_NEAR(double(n), 40.0, 1.0);
  const Scene slab =
      test::make_soup(2, 8000, glm::vec3(-4, -1, -0.5f), glm::vec3(4, 1, 0.5f), 0.05f);
  UniformGrid flat(AccelParams{});
  flat.build(slab);
  const auto n = flat.resolution();
  EXPECT_NEAR(double(n[0]) / n[1], 4.0, 0.5);
  EXPECT_NEAR(double(n[1]) / n[2], 2.0, 0.5);
  EXPECT_NEAR(double(flat.cell_count()), 8000.0, 2000.0);
}

// Glassner's rule: only nodes at the depth cap, or whose cut would separate nothing, keep
// more than leaf-size triangles; stats add up; --max-depth is capped.
TEST(OctreeBuild, LeavesAreSmallUnlessAtTheDepthCap) {
  const Scene scene = sphere_and_soup();
  AccelParams params;
  params.max_depth = 5, params.leaf_size = 6;
  Octree octree(params);
  octree.build(scene);
  const StructureStats stats = octree.stats();
  EXPECT_EQ(*stats.nodes, octree.nodes().size());
  EXPECT_EQ(*stats.nodes, *stats.leaves + *stats.voxels_subdivided);
  EXPECT_EQ(*stats.nodes, 1 + 8 * *stats.voxels_subdivided);
  EXPECT_LE(octree.depth_reached(), 5);
  // Walk the tree: a leaf above the cap holds at most leaf-size triangles.
  std::vector<std::pair<uint32_t, int>> stack{{0, 0}};
  size_t big = 0;
  while (!stack.empty()) {
    const auto [id, depth] = stack.back();
    stack.pop_back();
    const Octree::Node& node = octree.nodes()[id];
    if (node.count == Octree::kInternal) {
      for (uint32_t k = 0; k < 8; ++k) stack.push_back({node.first + k, depth + 1});
    } else if (depth < 5 && node.count > 6) {
      ++big;
    }
  }
  // ... except the few whose cut would only copy straddling triangles (Octree::split).
  std::printf("octree: %zu of %llu leaves above the depth cap keep more than leaf-size\n", big,
              (unsigned long long)*stats.leaves);
  EXPECT_LT(big * 10, *stats.leaves);
  AccelParams capped;
  capped.max_depth = 64;
  EXPECT_EQ(Octree(capped).max_depth(), Octree::kDepthCap);
  EXPECT_EQ(Octree(AccelParams{}).max_depth(), Octree::kDefaultMaxDepth);
}

// Counters: the uniform grid's steps are cell steps, the octree's are leaves visited.
TEST(Counters, TestsRejectionsAndSteps) {
  const Case& c = cases()[1];
  for (const std::string name : {"uniform", "octree"}) {
    const auto accel = make({name}, c.scene);
    auto context = accel->make_context();
    for (const Ray& ray : c.rays) accel->intersect(ray, *context);
    const TraceCounters& counters = context->counters;
    EXPECT_GT(counters.intersection_tests, 0u) << name;
    EXPECT_GT(counters.mailbox_rejections, 0u) << name;
    EXPECT_GT(counters.traversal_steps, c.rays.size() / 2) << name;
    // Far fewer tests than brute's N per ray.
    EXPECT_LT(counters.intersection_tests, c.rays.size() * c.scene.triangle_count() / 10) << name;
  }
}

}  // namespace
}  // namespace gs
