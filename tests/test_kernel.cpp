// The watertight kernel against closed-form answers, against its own long double
// instantiation, and against escapes through a closed mesh; the §6 cost function against
// hand-computed values.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <glm/geometric.hpp>
#include <limits>

#include "core/accel/brute.h"
#include "core/accel/grid1d/cost_model.h"
#include "core/accel/grid1d/grid1d.h"
#include "core/geometry/kernel.h"
#include "tests/test_util.h"

namespace gs {
namespace {

TEST(Kernel, ClosedFormHitAndBarycentrics) {
  Ray ray;
  ray.origin = {0.25f, 0.5f, 2.0f};
  ray.dir = {0.0f, 0.0f, -0.5f};  // not normalised: t is in units of dir
  const PreparedRay<KernelReal> prepared(ray, 0.0);
  float t, u, v;
  ASSERT_TRUE(intersect_triangle(prepared, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, ray.tmax, t, u, v));
  EXPECT_FLOAT_EQ(t, 4.0f);
  EXPECT_FLOAT_EQ(u, 0.25f);  // weight of the second corner (1,0,0)
  EXPECT_FLOAT_EQ(v, 0.5f);   // weight of the third corner (0,1,0)
  // tmin < t <= tmax: t == tmax hits, t == tmin does not.
  EXPECT_TRUE(intersect_triangle(prepared, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 4.0f, t, u, v));
  EXPECT_FALSE(intersect_triangle(prepared, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 3.99f, t, u, v));
  ray.tmin = 4.0f;
  EXPECT_FALSE(intersect_triangle(PreparedRay<KernelReal>(ray, 0.0), {0, 0, 0}, {1, 0, 0},
                                  {0, 1, 0}, ray.tmax, t, u, v));
}

TEST(Kernel, InvalidRaysMiss) {
  BruteForce brute;
  Scene scene;
  scene.vertices = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}};
  scene.triangles = {{0, 1, 2}};
  brute.build(scene);
  auto context = brute.make_context();
  Ray good;
  good.origin = {0, 0, 1};
  good.dir = {0, 0, -1};
  ASSERT_EQ(brute.intersect(good, *context).id, 0);
  for (int bad = 0; bad < 5; ++bad) {
    Ray ray = good;
    if (bad == 0) ray.dir = {0, 0, 0};
    if (bad == 1) ray.dir.x = NAN;
    if (bad == 2) ray.origin.y = INFINITY;
    if (bad == 3) ray.tmin = 2, ray.tmax = 1;
    if (bad == 4) ray.tmax = NAN;
    const Hit hit = brute.intersect(ray, *context);
    EXPECT_EQ(hit, Hit{}) << "case " << bad;
    EXPECT_TRUE(std::isinf(hit.t));
  }
}

// ray_is_valid tests bit patterns (exponent all ones, magnitude zero); the reference here is
// the definition, with std::isfinite and ==: every field through special values, and every
// direction made of zeros of both signs, denormals and ones.
TEST(Kernel, RayValidityIsItsDefinition) {
  const auto reference = [](const Ray& r) {
    for (int a = 0; a < 3; ++a)
      if (!std::isfinite(r.origin[a]) || !std::isfinite(r.dir[a])) return false;
    if (r.dir.x == 0.0f && r.dir.y == 0.0f && r.dir.z == 0.0f) return false;
    return r.tmin <= r.tmax;
  };
  const float denormal = std::numeric_limits<float>::denorm_min();
  const float special[] = {0.0f,   -0.0f,    denormal,  -denormal, 1.0f,
                           -3e38f, INFINITY, -INFINITY, NAN,       -NAN};
  Ray good;
  good.origin = {0.5f, -2.0f, 3.0f};
  good.dir = {0.25f, 1.0f, -0.5f};
  good.tmin = 0.0f, good.tmax = 10.0f;
  int invalid = 0, cases = 0;
  for (int field = 0; field < 8; ++field)
    for (const float value : special) {
      float fields[8];  // Ray is eight floats: origin, tmin, dir, tmax
      std::memcpy(fields, &good, sizeof(Ray));
      fields[field] = value;
      Ray ray;
      std::memcpy(&ray, fields, sizeof(Ray));
      EXPECT_EQ(ray_is_valid(ray), reference(ray)) << "field " << field << " value " << value;
      invalid += !reference(ray), ++cases;
    }
  // Non-finite in any of six components (4 values each); tmin above tmax = 10 (tmin = inf
  // or a NaN: 3); tmax below tmin = 0 (tmax = -denormal, -3e38, -inf or a NaN: 5).
  EXPECT_EQ(invalid, 6 * 4 + 3 + 5);
  const float parts[] = {0.0f, -0.0f, denormal, 1.0f};
  int zero_directions = 0;
  for (const float x : parts)
    for (const float y : parts)
      for (const float z : parts) {
        Ray ray = good;
        ray.dir = {x, y, z};
        EXPECT_EQ(ray_is_valid(ray), reference(ray)) << x << " " << y << " " << z;
        zero_directions += !ray_is_valid(ray);
      }
  EXPECT_EQ(zero_directions, 8);  // each component +0 or -0
  EXPECT_EQ(cases, 80);
}

// Same hit and t within 1e-4 relative wherever the hit is not grazing an edge (all
// barycentric weights above 1e-4): the kernel checked against the same test one type wider.
TEST(Kernel, AgreesWithItsLongDoubleInstantiation) {
  const Scene scene = test::merge(test::make_sphere({0.2f, 0.1f, -0.3f}, 1.0f, 20, 40),
                                  test::make_soup(5, 800, glm::vec3(-1.5f), glm::vec3(1.5f), 0.2f));
  BruteForce brute;
  brute.build(scene);
  std::vector<Ray> rays = test::random_chords(scene.bounds(), 9, 20000);
  const auto cam = test::camera_rays(scene.bounds(), 80, 80);
  rays.insert(rays.end(), cam.begin(), cam.end());
  const std::vector<Hit> hits = test::trace_all(brute, rays, 2);
  size_t compared = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    const Hit exact = brute.intersect_long_double(rays[i]);
    const float w0 = 1.0f - exact.u - exact.v;
    if (exact.found() && std::min({w0, exact.u, exact.v}) <= 1e-4f) continue;
    ++compared;
    ASSERT_EQ(hits[i].id, exact.id) << "ray " << i;
    if (exact.found()) {
      EXPECT_NEAR(hits[i].t, exact.t, 1e-4 * std::fabs(exact.t)) << "ray " << i;
    }
  }
  EXPECT_GT(compared, rays.size() * 9 / 10);
}

// From inside a closed sphere far from the origin, aimed exactly at every vertex and at
// points on every edge, and in random directions: no ray may slip through.
TEST(Kernel, NoEscapeFromClosedSphere) {
  const glm::vec3 centre(1000.0f, -2000.0f, 500.0f);
  const Scene sphere = test::make_sphere(centre, 3.0f, 24, 48);
  std::vector<Ray> rays;
  const glm::vec3 inside = centre + glm::vec3(0.3f, -0.2f, 0.1f);
  for (uint32_t t = 0; t < sphere.triangle_count(); ++t)
    for (int c = 0; c < 3; ++c) {
      const glm::vec3 a = sphere.vertex(t, c), b = sphere.vertex(t, (c + 1) % 3);
      for (float s : {0.0f, 0.5f, 0.25f, 1.0f / 3.0f}) {
        Ray ray;
        ray.origin = inside;
        ray.dir = a + s * (b - a) - inside;
        rays.push_back(ray);
      }
    }
  std::mt19937 rng(4);
  std::normal_distribution<float> normal;
  for (int i = 0; i < 20000; ++i) {
    Ray ray;
    ray.origin = inside;
    ray.dir = {normal(rng), normal(rng), normal(rng)};
    rays.push_back(ray);
  }
  BruteForce brute;
  brute.build(sphere);
  Grid1D grid(AccelParams{});
  grid.build(sphere);
  for (const Accelerator* accel :
       {static_cast<const Accelerator*>(&brute), static_cast<const Accelerator*>(&grid)}) {
    const std::vector<Hit> hits = test::trace_all(*accel, rays, 2);
    size_t escapes = 0;
    for (const Hit& hit : hits) escapes += !hit.found();
    EXPECT_EQ(escapes, 0u) << accel->name() << " of " << rays.size() << " rays";
  }
}

// A 2 x 1 x 4 voxel with 10 triangles of mean size 0.5 along x, cut along x into 4:
// w = 0.5, k = 1; A_x = 4, A_y = 8, A_z = 2, sum 14.
TEST(CostModel, MatchesHandComputedValues) {
  AccelParams params;
  params.intcost = 1.0, params.travcost = 0.5, params.repcost = 0.25, params.vertcost = 2.0;
  params.subcost = 3.0;
  VoxelFigures voxel;
  voxel.triangles = 10;
  voxel.extent[0] = 2, voxel.extent[1] = 1, voxel.extent[2] = 4;
  voxel.mean_size[0] = 0.5;
  const CutCost cost = cut_cost(params, voxel, 0, 4);
  EXPECT_EQ(cost.spanned_cells, 1);
  EXPECT_DOUBLE_EQ(cost.int_cost, 1.0 * (8 + 2) * 10 * 1 / 4.0 / 14);
  EXPECT_DOUBLE_EQ(cost.trav_cost, 0.5 * 4 * 3 / 14.0);
  EXPECT_DOUBLE_EQ(cost.rep_cost, 0.0);
  EXPECT_DOUBLE_EQ(cost.ver_cost, 2.0);
  EXPECT_DOUBLE_EQ(no_split_cost(params, voxel, 0), 1.0 * 10 * 10 / 14.0);
  EXPECT_DOUBLE_EQ(along_axis_cost(params, voxel, 0), 1.0 * 4 * 10 / 14.0);
  // g = 8: w = 0.25, k = 2.
  const CutCost finer = cut_cost(params, voxel, 0, 8);
  EXPECT_EQ(finer.spanned_cells, 2);
  EXPECT_DOUBLE_EQ(finer.rep_cost, 0.25 * 4 * 1 * 10 / 14.0);
  // With few rays, sorting the triangles costs more than it saves (§6.5).
  voxel.rays = 1;
  EXPECT_EQ(plan_axis(params, voxel, 0, 20).granularity, 1);
  voxel.rays = 1000;
  const AxisPlan plan = plan_axis(params, voxel, 0, 20);
  EXPECT_GE(plan.granularity, 2);
  double best = INFINITY;
  int best_g = 0;
  for (int g = 2; g <= 20; ++g)
    if (cut_cost(params, voxel, 0, g).total < best)
      best = cut_cost(params, voxel, 0, g).total, best_g = g;
  EXPECT_EQ(plan.granularity, best_g);
}

}  // namespace
}  // namespace gs
