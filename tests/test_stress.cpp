// Numerical stress and degenerate input for grid1d: every answer still equals brute's,
// every build ends, and what is never seen is never built.
#include <gtest/gtest.h>

#include <cstdio>
#include <glm/geometric.hpp>

#include "core/accel/grid1d/grid1d.h"
#include "core/trace/sampling.h"
#include "tests/cases.h"

namespace gs {
namespace {

// Traces `rays` through brute and through grid1d (lazy and eager, 1 and 2 threads) and
// counts the (run, ray) pairs whose answers differ.
size_t disagreements(const Scene& scene, const std::vector<Ray>& rays, AccelParams params = {}) {
  return test::disagreements(scene, rays, test::lazy_and_eager_runs("grid1d", params));
}

std::vector<Ray> mixed_rays(const Scene& scene) {
  return test::mixed_rays(scene, {.camera_width = 60,
                                  .camera_height = 60,
                                  .chords = 4000,
                                  .axis_parallel = 3000,
                                  .edges_and_vertices = 3000,
                                  .chord_seed = 5,
                                  .axis_seed = 6,
                                  .edge_seed = 7});
}

TEST(Stress, NegativeZeroAndTinyDirectionComponents) {
  const Scene scene = test::small_sphere_in_soup();
  EXPECT_EQ(disagreements(scene, test::negative_zero_and_tiny_chords(scene.bounds(), 8, 6000)), 0u);
}

// Rays from 1e3 to 1e28 times the scene's size away, aimed at the sphere's vertices, edge
// midpoints and face centres, some along an axis: the kernel tests the line through the
// origin moved to the box entry in double, off the true line by up to ~1e12 that far out;
// every structure, walking that same line, answers as brute does.
TEST(Stress, OriginsFarAwayGetBrutesAnswers) {
  const Scene scene = test::make_sphere({0.25f, -0.5f, 0.75f}, 1.0f, 12, 24);
  std::vector<Ray> rays;
  uint32_t seed = 9;
  for (const float distance : {1e3f, 1e7f, 1e12f, 1e20f, 1e28f}) {
    for (uint32_t id = 0; id < scene.triangle_count(); id += 3) {
      const glm::vec3 a = scene.vertex(id, 0), b = scene.vertex(id, 1), c = scene.vertex(id, 2);
      const glm::vec3 targets[3] = {a, 0.5f * (a + b), (a + b + c) / 3.0f};
      for (const glm::vec3& target : targets) {
        seed = seed * 1664525u + 1013904223u;
        glm::vec3 away(float(seed >> 8 & 255) - 127.5f, float(seed >> 16 & 255) - 127.5f,
                       float(seed >> 24) - 127.5f);
        if (seed % 5 == 0) away = glm::vec3(0.0f), away[seed % 3] = seed % 2 ? 1.0f : -1.0f;
        Ray ray;
        ray.origin = target + distance * glm::normalize(away);
        ray.dir = target - ray.origin;
        rays.push_back(ray);
      }
    }
  }
  const std::vector<Hit> expected = test::brute_answers(scene, rays);
  size_t hits = 0;
  for (const Hit& hit : expected) hits += hit.found();
  EXPECT_GT(hits, rays.size() / 10);
  for (const std::string name : {"grid1d", "uniform", "octree", "grid3d", "bvh"})
    EXPECT_EQ(test::disagreements(scene, rays, test::lazy_and_eager_runs(name), expected), 0u)
        << name;
}

// A unit-box scene cut with granularity 2 has its walls at multiples of 1/2^k, exact in
// float: rays start exactly on walls, and run inside wall planes.
TEST(Stress, OriginsOnCellWallsAndRaysInsideWalls) {
  Scene scene = test::make_soup(31, 3000, glm::vec3(0.0f), glm::vec3(1.0f), 0.03f);
  scene.vertices.insert(scene.vertices.end(), {{0, 0, 0}, {1, 1, 1}, {1, 0, 1}});
  scene.triangles.emplace_back(uint32_t(scene.vertices.size() - 3),
                               uint32_t(scene.vertices.size() - 2),
                               uint32_t(scene.vertices.size() - 1));
  std::mt19937 rng(12);
  std::uniform_int_distribution<int> wall(0, 64);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), signed_unit(-1.0f, 1.0f);
  std::vector<Ray> rays;
  for (int i = 0; i < 12000; ++i) {
    Ray ray;
    ray.origin = {unit(rng), unit(rng), unit(rng)};
    const int a = i % 3;
    ray.origin[a] = wall(rng) / 64.0f;
    ray.dir = {signed_unit(rng), signed_unit(rng), signed_unit(rng)};
    if (i % 2) ray.dir[a] = 0.0f;  // inside the wall plane
    if (i % 4 == 1) ray.origin[(a + 1) % 3] = wall(rng) / 64.0f, ray.dir[(a + 1) % 3] = 0.0f;
    rays.push_back(ray);
  }
  AccelParams params;
  params.max_granularity = 2;
  EXPECT_EQ(disagreements(scene, rays, params), 0u);
  params.max_granularity = 4;
  params.axis = AxisRule::cost;
  EXPECT_EQ(disagreements(scene, rays, params), 0u);
}

TEST(Stress, MovedAndScaledScenes) {
  const Scene base = test::small_sphere_in_soup();
  std::vector<test::NamedScene> scenes = test::moved_and_scaled(base);
  scenes.push_back(test::scaled_and_moved(base, 1e3f, glm::vec3(1e6f, 2e6f, -3e6f)));
  for (const test::NamedScene& moved : scenes)
    EXPECT_EQ(disagreements(moved.scene, mixed_rays(moved.scene)), 0u) << moved.name;
}

TEST(Stress, LongThinSlivers) {
  const Scene scene = test::sliver_scene();
  EXPECT_EQ(disagreements(scene, mixed_rays(scene)), 0u);
}

TEST(Stress, ThousandsOfCoincidentTriangles) {
  const Scene scene = test::coincident_scene();
  EXPECT_EQ(disagreements(scene, mixed_rays(scene)), 0u);
  Grid1D grid(AccelParams{});
  grid.build(scene);
  grid.build_all();
  EXPECT_LT(grid.voxel_count(), 200000u);  // the cost model cannot separate coincident triangles
}

TEST(Stress, EverythingInOnePlaneAndZeroExtent) {
  const Scene scene = test::flat_scene();
  Grid1D grid(AccelParams{});
  grid.build(scene);
  grid.build_all();
  EXPECT_GT(*grid.stats().voxels_subdivided, 0u);
  for (uint32_t id = 0; id < grid.voxel_count(); ++id)
    if (grid.voxel(id).status.load() == Grid1D::kSplit) {
      ASSERT_NE(grid.voxel(id).axis, 2);
    }
  EXPECT_EQ(disagreements(scene, test::flat_scene_rays(scene, 8000, 4000)), 0u);
}

TEST(Stress, EmptySceneOneTriangleAndNoRays) {
  test::expect_empty_and_one_triangle_answers(
      "grid1d", test::random_chords({{-1, -1, -1}, {1, 1, 1}}, 3, 100));
  const Scene one = test::one_triangle();
  EXPECT_EQ(disagreements(one, mixed_rays(one)), 0u);
}

// A budget too small for the structure leaves voxels uncut (and says so); the answers stay
// brute's.
TEST(Stress, MemoryBudgetLeavesVoxelsUncutButAnswersStayExact) {
  const Scene scene = test::small_sphere_in_soup();
  AccelParams params;
  params.memory_budget = 64 << 10;
  EXPECT_EQ(disagreements(scene, mixed_rays(scene), params), 0u);
  Grid1D grid(params);
  grid.build(scene);
  grid.build_all();
  const StructureStats stats = grid.stats();
  EXPECT_GT(stats.voxels_over_budget, 0u);
  // The budget covers what the cuts allocate; the triangles, their boxes and the state
  // table come on top.
  const uint64_t fixed = scene.triangle_count() * (sizeof(TriangleVerts) + 6 * sizeof(double)) +
                         grid.state_count() * sizeof(Grid1D::StateInfo);
  EXPECT_LE(stats.memory_bytes, fixed + params.memory_budget);
}

// Rays that see only one corner of a large scene build a small part of what --eager does.
TEST(Laziness, PartialViewBuildsFarFewerNodes) {
  const Scene scene = test::make_soup(17, 60000, glm::vec3(-10.0f), glm::vec3(10.0f), 0.1f);
  const std::vector<Ray> rays = test::corner_view_rays(100);
  Grid1D lazy(AccelParams{}), eager(AccelParams{});
  lazy.build(scene);
  eager.build(scene);
  sample_run(lazy, sample_subset(rays, 64), rays.size(), 2);
  sample_run(eager, sample_subset(rays, 64), rays.size(), 1);
  eager.build_all();
  test::trace_all(lazy, rays, 2);
  const uint64_t lazy_nodes = *lazy.stats().nodes, eager_nodes = *eager.stats().nodes;
  std::printf("laziness: %llu nodes lazy, %llu eager\n", (unsigned long long)lazy_nodes,
              (unsigned long long)eager_nodes);
  EXPECT_LT(lazy_nodes * 10, eager_nodes);
}

// §4: voxels on the same global 1D grid share one traversal state (the whole structure,
// as --eager builds it after a sampling pass of rays aimed at the triangles).
TEST(Sharing, StatesAreAFractionOfSubdividedVoxels) {
  for (const std::string& name : builtin_scene_names()) {
    const Scene scene = make_builtin_scene(name);
    Grid1D grid(AccelParams{});
    grid.build(scene);
    // Sample rays aimed at the triangles themselves, so dense detail is seen however small.
    const std::vector<Ray> rays = test::edge_and_vertex_rays(scene, 5, 262144);
    sample_run(grid, sample_subset(rays, 64), rays.size(), 1);
    grid.build_all();
    const StructureStats stats = grid.stats();
    const double ratio = double(*stats.traversal_states) / double(*stats.voxels_subdivided);
    std::printf("sharing on builtin:%s: %llu states for %llu subdivided voxels (%.2f%%)\n",
                name.c_str(), (unsigned long long)*stats.traversal_states,
                (unsigned long long)*stats.voxels_subdivided, 100.0 * ratio);
    EXPECT_GT(*stats.voxels_subdivided, 100u) << name;
    EXPECT_LT(ratio, 0.1) << name;
  }
}

}  // namespace
}  // namespace gs
