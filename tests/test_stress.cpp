// Numerical stress and degenerate input for grid1d: every answer still equals brute's,
// every build ends, and what is never seen is never built.
#include <gtest/gtest.h>

#include <cstdio>

#include "core/accel/brute.h"
#include "core/accel/grid1d/grid1d.h"
#include "tests/test_util.h"

namespace gs {
namespace {

// Traces `rays` through brute and through grid1d (lazy and eager, 1 and 2 threads) and
// counts the rays whose answers differ.
size_t disagreements(const Scene& scene, const std::vector<Ray>& rays, AccelParams params = {}) {
  BruteForce brute;
  brute.build(scene);
  const std::vector<Hit> expected = test::trace_all(brute, rays, 2);
  size_t bad = 0;
  for (bool eager : {false, true})
    for (int threads : {1, 2}) {
      Grid1D grid(params);
      grid.build(scene);
      if (eager) grid.build_all();
      const std::vector<Hit> hits = test::trace_all(grid, rays, threads);
      for (size_t i = 0; i < rays.size(); ++i)
        if (!(hits[i] == expected[i])) {
          if (++bad <= 3)
            ADD_FAILURE() << "ray " << i << " (eager " << eager << ", threads " << threads
                          << "): grid1d " << hits[i].id << " t " << hits[i].t << ", brute "
                          << expected[i].id << " t " << expected[i].t;
        }
    }
  return bad;
}

Scene sphere_and_soup() {
  return test::merge(test::make_sphere({0.1f, 0.2f, -0.1f}, 1.0f, 16, 32),
                     test::make_soup(21, 1200, glm::vec3(-1.2f), glm::vec3(1.2f), 0.08f));
}

std::vector<Ray> mixed_rays(const Scene& scene) {
  std::vector<Ray> rays = test::camera_rays(scene.bounds(), 60, 60);
  for (const auto& set : {test::random_chords(scene.bounds(), 5, 4000),
                          test::axis_parallel_rays(scene.bounds(), 6, 3000),
                          test::edge_and_vertex_rays(scene, 7, 3000)})
    rays.insert(rays.end(), set.begin(), set.end());
  return rays;
}

TEST(Stress, NegativeZeroAndTinyDirectionComponents) {
  const Scene scene = sphere_and_soup();
  std::vector<Ray> rays = test::random_chords(scene.bounds(), 8, 6000);
  for (size_t i = 0; i < rays.size(); ++i) {
    rays[i].dir[i % 3] = (i % 2) ? -0.0f : 1e-30f;
    if (i % 5 == 0) rays[i].dir[(i + 1) % 3] = -1e-30f;
  }
  EXPECT_EQ(disagreements(scene, rays), 0u);
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
  const Scene base = sphere_and_soup();
  for (const auto& [scale, offset] :
       {std::pair{1e-4f, glm::vec3(0.0f)}, std::pair{1e4f, glm::vec3(0.0f)},
        std::pair{1.0f, glm::vec3(1e6f, -1e6f, 1e6f)},
        std::pair{1e3f, glm::vec3(1e6f, 2e6f, -3e6f)}}) {
    const Scene scene = test::transformed(base, scale, offset);
    EXPECT_EQ(disagreements(scene, mixed_rays(scene)), 0u)
        << "scale " << scale << " offset " << offset.x;
  }
}

TEST(Stress, LongThinSlivers) {
  Scene scene;
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  for (int i = 0; i < 1500; ++i) {
    const glm::vec3 a(unit(rng) * 50, unit(rng), unit(rng));
    const glm::vec3 b(-a.x, a.y + unit(rng) * 1e-3f, a.z);
    const glm::vec3 c = a + glm::vec3(0.0f, unit(rng) * 1e-2f, 1e-2f);
    scene.vertices.insert(scene.vertices.end(), {a, b, c});
    const uint32_t k = uint32_t(scene.vertices.size() - 3);
    scene.triangles.emplace_back(k, k + 1, k + 2);
  }
  EXPECT_EQ(disagreements(scene, mixed_rays(scene)), 0u);
}

TEST(Stress, ThousandsOfCoincidentTriangles) {
  Scene scene = test::make_soup(4, 300, glm::vec3(-1.0f), glm::vec3(1.0f), 0.1f);
  const uint32_t base = uint32_t(scene.vertices.size());
  scene.vertices.insert(scene.vertices.end(),
                        {{-0.5f, -0.5f, 0.2f}, {0.5f, -0.4f, 0.2f}, {0.0f, 0.6f, 0.25f}});
  for (int i = 0; i < 5000; ++i) scene.triangles.emplace_back(base, base + 1, base + 2);
  EXPECT_EQ(disagreements(scene, mixed_rays(scene)), 0u);
  Grid1D grid(AccelParams{});
  grid.build(scene);
  grid.build_all();
  EXPECT_LT(grid.voxel_count(), 200000u);  // the cost model cannot separate coincident triangles
}

TEST(Stress, EverythingInOnePlaneAndZeroExtent) {
  Scene scene =
      test::make_soup(9, 3000, glm::vec3(-1.0f, -1.0f, 0.0f), glm::vec3(1.0f, 1.0f, 0.0f), 0.05f);
  for (glm::vec3& v : scene.vertices) v.z = 0.0f;
  Grid1D grid(AccelParams{});
  grid.build(scene);
  grid.build_all();
  EXPECT_GT(*grid.stats().voxels_subdivided, 0u);
  for (uint32_t id = 0; id < grid.voxel_count(); ++id)
    if (grid.voxel(id).status.load() == Grid1D::kSplit) {
      ASSERT_NE(grid.voxel(id).axis, 2);
    }
  std::vector<Ray> rays = test::random_chords({{-1, -1, -1}, {1, 1, 1}}, 3, 8000);
  const auto edges = test::edge_and_vertex_rays(scene, 4, 4000);
  rays.insert(rays.end(), edges.begin(), edges.end());
  EXPECT_EQ(disagreements(scene, rays), 0u);
}

TEST(Stress, EmptySceneOneTriangleAndNoRays) {
  Scene empty;
  std::vector<Ray> rays = test::random_chords({{-1, -1, -1}, {1, 1, 1}}, 3, 100);
  Grid1D grid(AccelParams{});
  grid.build(empty);
  for (const Hit& hit : test::trace_all(grid, rays, 2)) EXPECT_EQ(hit, Hit{});
  EXPECT_TRUE(test::trace_all(grid, {}, 2).empty());

  Scene one;
  one.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  one.triangles = {{0, 1, 2}};
  Grid1D single(AccelParams{});
  single.build(one);
  Ray ray;
  ray.origin = {0.2f, 0.3f, -1.0f};
  ray.dir = {0.0f, 0.0f, 2.0f};
  auto context = single.make_context();
  const Hit hit = single.intersect(ray, *context);
  EXPECT_EQ(hit.id, 0);
  EXPECT_FLOAT_EQ(hit.t, 0.5f);
  EXPECT_FLOAT_EQ(hit.u, 0.2f);
  EXPECT_FLOAT_EQ(hit.v, 0.3f);
  EXPECT_EQ(disagreements(one, mixed_rays(one)), 0u);
}

// A budget too small for the structure leaves voxels uncut (and says so); the answers stay
// brute's.
TEST(Stress, MemoryBudgetLeavesVoxelsUncutButAnswersStayExact) {
  const Scene scene = sphere_and_soup();
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
  std::vector<Ray> rays;
  for (int y = 0; y < 100; ++y)
    for (int x = 0; x < 100; ++x) {
      Ray ray;
      ray.origin = {-9.0f + x * 0.01f, -9.0f + y * 0.01f, -11.0f};
      ray.dir = {0.0f, 0.0f, 1.0f};
      rays.push_back(ray);
    }
  Grid1D lazy(AccelParams{}), eager(AccelParams{});
  lazy.build(scene);
  eager.build(scene);
  test::run_sampling_pass(lazy, rays, 64);
  test::run_sampling_pass(eager, rays, 64);
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
    test::run_sampling_pass(grid, test::edge_and_vertex_rays(scene, 5, 262144), 64);
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
