// The uniform grid and the octree must give exactly brute's answers (same id, t, u, v) on
// every ray, for every parameter setting, with one thread or two; any_hit finds a hit iff
// brute does; numerical stress and degenerate input still give brute's answers, and every
// build ends with bounded memory.
#include <gtest/gtest.h>

#include <cstdio>
#include <glm/vec2.hpp>

#include "core/accel/octree.h"
#include "core/accel/uniform_grid.h"
#include "tests/cases.h"

namespace gs {
namespace {

// The uniform grid at one density, or the octree with one depth cap and leaf size; traced
// by one thread or two.
test::StructureRun uniform_run(double density, int threads) {
  AccelParams params;
  params.density = density;
  return {"uniform", params, false, false, threads};
}

test::StructureRun octree_run(int depth, int leaf, int threads) {
  AccelParams params;
  params.max_depth = depth;
  params.leaf_size = leaf;
  return {"octree", params, false, false, threads};
}

std::string setting_name(const testing::TestParamInfo<test::StructureRun>& info) {
  const test::StructureRun& s = info.param;
  std::string name = s.accel;  // built by appending: GCC 12 warns falsely on "literal" + string
  if (s.accel == "uniform") {
    name += "_density";
    name +=
        s.params.density == 0.0 ? "default" : std::to_string(int(s.params.density * 10)) + "tenths";
  } else {
    name += "_depth" + std::to_string(s.params.max_depth) + "_leaf" +
            std::to_string(s.params.leaf_size);
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

const std::vector<Case>& cases() {
  static const std::vector<Case> all = test::brute_cases(
      test::comparison_scenes(2500, wall_planes()), [](const test::NamedScene& s) {
        std::vector<Ray> rays = test::mixed_rays(s.scene, {.camera_width = 80,
                                                           .camera_height = 75,
                                                           .chords = 6000,
                                                           .axis_parallel = 4000,
                                                           .edges_and_vertices = 5000});
        if (s.name == "wall planes") {
          const auto planar = in_plane_rays(4, 3000);
          rays.insert(rays.end(), planar.begin(), planar.end());
        }
        return rays;
      });
  return all;
}

class MatchesBrute : public testing::TestWithParam<test::StructureRun> {};

TEST_P(MatchesBrute, SameIdTAndUvOnEveryRay) {
  const size_t checked = test::expect_brute_answers(
      cases(), GetParam(), test::Answers::nearest, [](const Case& c, const Accelerator& accel) {
        EXPECT_GT(*accel.stats().leaves, 1u) << c.name << ": nothing was subdivided";
      });
  RecordProperty("rays_checked", int(checked));
}

TEST_P(MatchesBrute, AnyHitFindsAHitIffBruteDoes) {
  test::expect_brute_answers(cases(), GetParam(), test::Answers::any_hit);
}

std::vector<test::StructureRun> settings() {
  std::vector<test::StructureRun> out;
  for (int threads : {1, 2}) {
    for (double density : {0.0, 0.5, 4.0}) out.push_back(uniform_run(density, threads));
    for (int depth : {3, 6, 8})
      for (int leaf : {1, 4, 16}) out.push_back(octree_run(depth, leaf, threads));
  }
  return out;
}

INSTANTIATE_TEST_SUITE_P(Settings, MatchesBrute, testing::ValuesIn(settings()), setting_name);

// Numerical stress: each scene through both structures (two settings each, 1 and 2
// threads); counts the (setting, ray) pairs whose answers differ from brute's.
size_t disagreements(const Scene& scene, const std::vector<Ray>& rays) {
  return test::disagreements(
      scene, rays,
      {uniform_run(0.0, 1), uniform_run(4.0, 2), octree_run(0, 0, 2), octree_run(8, 1, 1)});
}

std::vector<Ray> mixed_rays(const Scene& scene) {
  return test::mixed_rays(scene, {.camera_width = 50,
                                  .camera_height = 50,
                                  .chords = 3000,
                                  .axis_parallel = 2000,
                                  .edges_and_vertices = 2000,
                                  .chord_seed = 5,
                                  .axis_seed = 6,
                                  .edge_seed = 7});
}

TEST(Stress, NegativeZeroAndTinyDirectionComponents) {
  const Scene scene = test::small_sphere_in_soup();
  EXPECT_EQ(disagreements(scene, test::negative_zero_and_tiny_chords(scene.bounds(), 8, 5000)), 0u);
}

TEST(Stress, MovedAndScaledScenes) {
  for (const test::NamedScene& moved : test::moved_and_scaled(test::small_sphere_in_soup()))
    EXPECT_EQ(disagreements(moved.scene, mixed_rays(moved.scene)), 0u) << moved.name;
}

TEST(Stress, ThousandsOfCoincidentTrianglesEndWithBoundedMemory) {
  const Scene scene = test::coincident_scene();
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
  const Scene scene = test::flat_scene();
  UniformGrid grid(AccelParams{});
  grid.build(scene);
  EXPECT_EQ(grid.resolution()[2], 1u);  // one cell across the flat axis
  EXPECT_GT(grid.cell_count(), 1000u);
  EXPECT_EQ(disagreements(scene, test::flat_scene_rays(scene, 6000, 3000)), 0u);
}

TEST(Stress, EmptySceneOneTriangleAndNoRays) {
  const std::vector<Ray> rays = test::random_chords({{-1, -1, -1}, {1, 1, 1}}, 3, 100);
  for (const std::string name : {"uniform", "octree"})
    test::expect_empty_and_one_triangle_answers(name, rays);
  const Scene one = test::one_triangle();
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
    const auto accel = test::build_structure({.accel = name}, scene);
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
  const Scene scene = test::small_sphere_in_soup();
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
    const auto accel = test::build_structure({.accel = name}, c.scene);
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
