#include "tests/cases.h"

#include <gtest/gtest.h>

#include <random>
#include <sstream>
#include <utility>

namespace gs::test {

// ---------------------------------------------------------------------------------------
// Scenes

Scene sphere_in_soup() {
  return merge(make_sphere({0.3f, -0.2f, 0.1f}, 1.0f, 24, 48),
               make_soup(11, 1500, glm::vec3(-1.5f), glm::vec3(1.5f), 0.1f));
}

Scene small_sphere_in_soup(int soup_triangles) {
  return merge(make_sphere({0.1f, 0.2f, -0.1f}, 1.0f, 16, 32),
               make_soup(21, soup_triangles, glm::vec3(-1.2f), glm::vec3(1.2f), 0.08f));
}

std::vector<NamedScene> comparison_scenes(int stadium_detail, Scene wall_planes) {
  std::vector<NamedScene> scenes;
  scenes.push_back({"pyramid", make_builtin_scene("pyramid")});
  scenes.push_back({"sphere+soup", sphere_in_soup()});
  scenes.push_back({"stadium", stadium_scene(stadium_detail)});
  scenes.push_back({"wall planes", std::move(wall_planes)});
  return scenes;
}

NamedScene scaled_and_moved(const Scene& base, float scale, glm::vec3 offset) {
  std::ostringstream name;
  name << "scale " << scale << " offset " << offset.x << "," << offset.y << "," << offset.z;
  return {name.str(), transformed(base, scale, offset)};
}

std::vector<NamedScene> moved_and_scaled(const Scene& base) {
  return {scaled_and_moved(base, 1e-4f, glm::vec3(0.0f)),
          scaled_and_moved(base, 1e4f, glm::vec3(0.0f)),
          scaled_and_moved(base, 1.0f, glm::vec3(1e6f, -1e6f, 1e6f))};
}

Scene coincident_scene() {
  Scene scene = make_soup(4, 300, glm::vec3(-1.0f), glm::vec3(1.0f), 0.1f);
  const uint32_t base = uint32_t(scene.vertices.size());
  scene.vertices.insert(scene.vertices.end(),
                        {{-0.5f, -0.5f, 0.2f}, {0.5f, -0.4f, 0.2f}, {0.0f, 0.6f, 0.25f}});
  for (int i = 0; i < 5000; ++i) scene.triangles.emplace_back(base, base + 1, base + 2);
  return scene;
}

Scene flat_scene() {
  Scene scene =
      make_soup(9, 3000, glm::vec3(-1.0f, -1.0f, 0.0f), glm::vec3(1.0f, 1.0f, 0.0f), 0.05f);
  for (glm::vec3& v : scene.vertices) v.z = 0.0f;
  return scene;
}

Scene sliver_scene() {
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
  return scene;
}

Scene one_triangle() {
  Scene scene;
  scene.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  scene.triangles = {{0, 1, 2}};
  return scene;
}

// ---------------------------------------------------------------------------------------
// Rays

std::vector<Ray> mixed_rays(const Scene& scene, const Box& box, const RayMix& mix) {
  std::vector<Ray> rays = camera_rays(box, mix.camera_width, mix.camera_height);
  for (const auto& set : {random_chords(box, mix.chord_seed, mix.chords),
                          axis_parallel_rays(box, mix.axis_seed, mix.axis_parallel),
                          edge_and_vertex_rays(scene, mix.edge_seed, mix.edges_and_vertices)})
    rays.insert(rays.end(), set.begin(), set.end());
  return rays;
}

std::vector<Ray> mixed_rays(const Scene& scene, const RayMix& mix) {
  return mixed_rays(scene, scene.bounds(), mix);
}

void set_negative_zero_or_tiny_components(std::span<Ray> rays, size_t step) {
  for (size_t i = 0; i < rays.size(); i += step) rays[i].dir[i % 3] = (i % 2) ? -0.0f : 1e-30f;
}

std::vector<Ray> negative_zero_and_tiny_chords(const Box& box, uint32_t seed, int count) {
  std::vector<Ray> rays = random_chords(box, seed, count);
  set_negative_zero_or_tiny_components(rays, 1);
  for (size_t i = 0; i < rays.size(); i += 5) rays[i].dir[(i + 1) % 3] = -1e-30f;
  return rays;
}

std::vector<Ray> flat_scene_rays(const Scene& flat, int chords, int edges_and_vertices) {
  return mixed_rays(flat, Box{{-1, -1, -1}, {1, 1, 1}},
                    {.chords = chords,
                     .edges_and_vertices = edges_and_vertices,
                     .chord_seed = 3,
                     .edge_seed = 4});
}

std::vector<Ray> corner_view_rays(int side) {
  std::vector<Ray> rays;
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      Ray ray;
      ray.origin = {-9.0f + x * 0.01f, -9.0f + y * 0.01f, -11.0f};
      ray.dir = {0.0f, 0.0f, 1.0f};
      rays.push_back(ray);
    }
  return rays;
}

// ---------------------------------------------------------------------------------------
// Comparison with brute force

std::vector<BruteCase> brute_cases(
    std::vector<NamedScene> scenes,
    const std::function<std::vector<Ray>(const NamedScene&)>& rays_of) {
  std::vector<BruteCase> cases;
  for (NamedScene& named : scenes) {
    std::vector<Ray> rays = rays_of(named);
    std::vector<Hit> expected = brute_answers(named.scene, rays);
    cases.push_back(
        {std::move(named.name), std::move(named.scene), std::move(rays), std::move(expected)});
  }
  return cases;
}

size_t count_mismatches(const std::string& what, const std::vector<Hit>& hits,
                        const std::vector<Hit>& expected) {
  constexpr size_t kReported = 5;  // enough to see a pattern, few enough to read
  size_t bad = 0;
  for (size_t i = 0; i < hits.size(); ++i) {
    if (hits[i] == expected[i]) continue;
    if (++bad <= kReported)
      ADD_FAILURE() << what << ": ray " << i << " id " << hits[i].id << " t " << hits[i].t << " u "
                    << hits[i].u << " v " << hits[i].v << ", brute id " << expected[i].id << " t "
                    << expected[i].t << " u " << expected[i].u << " v " << expected[i].v;
  }
  return bad;
}

size_t count_any_hit_mismatches(const std::vector<Ray>& rays, const std::vector<Hit>& hits,
                                const std::vector<Hit>& expected) {
  size_t bad = 0;
  for (size_t i = 0; i < hits.size(); ++i) {
    const bool ok = hits[i].found() == expected[i].found() &&
                    (!hits[i].found() || (hits[i].t > rays[i].tmin && hits[i].t <= rays[i].tmax &&
                                          hits[i].t >= expected[i].t));
    bad += !ok;
  }
  return bad;
}

std::string describe(const StructureRun& run) {
  const AccelParams defaults;
  const AccelParams& p = run.params;
  std::ostringstream text;
  text << run.accel << (run.eager ? " eager" : " lazy");
  if (p.max_granularity != defaults.max_granularity) text << " g=" << p.max_granularity;
  if (p.max_root_granularity != defaults.max_root_granularity)
    text << " root g=" << p.max_root_granularity;
  if (p.axis != defaults.axis) text << " axis=cost";
  if (p.max_depth != defaults.max_depth) text << " depth=" << p.max_depth;
  if (p.leaf_size != defaults.leaf_size) text << " leaf=" << p.leaf_size;
  if (p.density != defaults.density) text << " density=" << p.density;
  if (p.memory_budget != defaults.memory_budget) text << " budget=" << p.memory_budget;
  if (run.sample) text << " sampled every " << p.sample_every;
  if (run.packet > 0) text << ", packets of " << run.packet;
  text << ", " << run.threads << (run.threads == 1 ? " thread" : " threads");
  return text.str();
}

std::vector<StructureRun> lazy_and_eager_runs(const std::string& accel, const AccelParams& params) {
  std::vector<StructureRun> runs;
  for (const bool eager : {false, true})
    for (const int threads : {1, 2}) runs.push_back({accel, params, false, eager, threads});
  return runs;
}

size_t disagreements(const Scene& scene, const std::vector<Ray>& rays,
                     const std::vector<StructureRun>& runs, const std::vector<Hit>& expected) {
  size_t bad = 0;
  for (const StructureRun& run : runs) {
    const auto accel = build_structure(run, scene, rays);
    bad += count_mismatches(describe(run), trace_all(*accel, rays, run.threads, false, run.packet),
                            expected);
  }
  return bad;
}

size_t disagreements(const Scene& scene, const std::vector<Ray>& rays,
                     const std::vector<StructureRun>& runs) {
  return disagreements(scene, rays, runs, brute_answers(scene, rays));
}

size_t expect_brute_answers(const std::vector<BruteCase>& cases, const StructureRun& run,
                            Answers answers, const StructureCheck& check) {
  const bool any_hit = answers == Answers::any_hit;
  size_t checked = 0;
  for (const BruteCase& c : cases) {
    const auto accel = build_structure(run, c.scene, c.rays);
    const std::vector<Hit> hits = trace_all(*accel, c.rays, run.threads, any_hit, run.packet);
    const size_t bad = any_hit ? count_any_hit_mismatches(c.rays, hits, c.expected)
                               : count_mismatches(c.name + ", " + describe(run), hits, c.expected);
    EXPECT_EQ(bad, 0u) << c.name;
    if (!any_hit && check) check(c, *accel);
    checked += hits.size();
  }
  return checked;
}

void expect_empty_and_one_triangle_answers(const std::string& accel, const std::vector<Ray>& rays) {
  const auto empty = build_structure({.accel = accel}, Scene{});
  for (const Hit& hit : trace_all(*empty, rays, 2)) EXPECT_EQ(hit, Hit{}) << accel;
  EXPECT_TRUE(trace_all(*empty, {}, 2).empty()) << accel;

  const auto single = build_structure({.accel = accel}, one_triangle());
  Ray ray;
  ray.origin = {0.2f, 0.3f, -1.0f};
  ray.dir = {0.0f, 0.0f, 2.0f};
  const Hit hit = single->intersect(ray, *single->make_context());
  EXPECT_EQ(hit.id, 0) << accel;
  EXPECT_FLOAT_EQ(hit.t, 0.5f) << accel;
  EXPECT_FLOAT_EQ(hit.u, 0.2f) << accel;
  EXPECT_FLOAT_EQ(hit.v, 0.3f) << accel;
}

}  // namespace gs::test
