// embree: the same nearest hits as brute on clear rays (every barycentric weight > 1e-4:
// same id, t within 1e-6 relative plus Embree's float error, see t_tolerance),
// any-hit answers iff brute finds a hit, null counters in its stats. zero: the paper's
// zero-overhead oracle reproduces the hit file it was given byte for byte, and refuses to
// run without one or with one of the wrong length. The embree tests skip with a message in
// a build without Embree (where `--accel embree` must be a usage error instead).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <glm/geometric.hpp>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/accel/accelerator.h"
#include "core/base/error.h"
#include "core/geometry/kernel.h"
#include "core/geometry/ray_io.h"
#include "tests/cases.h"

namespace gs {
namespace {

using test::quoted;
using test::slurp;
using test::temp_path;

bool have_embree() {
  const std::vector<std::string> names = accelerator_names();
  return std::find(names.begin(), names.end(), "embree") != names.end();
}

#define SKIP_WITHOUT_EMBREE() \
  if (!have_embree()) GTEST_SKIP() << "gridscope was built without Embree: embree tests skipped"

constexpr float kWeight = 1e-4f;  // a "clear" hit: every barycentric weight above this

bool clear(const Hit& hit) {
  return hit.found() && hit.u > kWeight && hit.v > kWeight && 1.0f - hit.u - hit.v > kWeight;
}

// How far Embree's t may be from our kernel's on triangle `id`: 1e-6 relative, plus what
// float arithmetic allows Embree (our kernel computes in double from the box entry point):
// a few float ulps of the largest coordinate involved, stretched by 1 / |cos| of the angle
// between the ray and the triangle's normal (a grazing ray's t is ill-conditioned).
double t_tolerance(const Scene& scene, const Ray& ray, int32_t id, float t) {
  const glm::dvec3 p0 = scene.vertex(uint32_t(id), 0), p1 = scene.vertex(uint32_t(id), 1),
                   p2 = scene.vertex(uint32_t(id), 2);
  const glm::dvec3 normal = glm::normalize(glm::cross(p1 - p0, p2 - p0));
  const glm::dvec3 dir = ray.dir;
  const double cosine = std::max(std::abs(glm::dot(normal, dir)) / glm::length(dir), 1e-3);
  const Box box = scene.bounds();
  double magnitude = 0.0;
  for (int a = 0; a < 3; ++a)
    magnitude = std::max({magnitude, double(std::abs(ray.origin[a])), double(std::abs(box.lo[a])),
                          double(std::abs(box.hi[a]))});
  const double float_error = 16.0 * std::numeric_limits<float>::epsilon() * magnitude;
  return 1e-6 * std::abs(t) + float_error / (cosine * glm::length(dir));
}

bool close_t(const Scene& scene, const Ray& ray, int32_t id, float a, float b) {
  return std::abs(double(a) - double(b)) <= t_tolerance(scene, ray, id, b);
}

using Case = test::BruteCase;

Scene with_degenerates() {
  // Degenerate triangles (a repeated corner, three collinear corners) between real ones:
  // the ids after them must not shift.
  Scene scene = test::make_sphere({0, 0, 0}, 1.0f, 12, 24);
  const uint32_t b = uint32_t(scene.vertices.size());
  scene.vertices.insert(scene.vertices.end(), {{-2, -2, 0}, {2, -2, 0}, {0, 2, 0}, {4, 4, 4}});
  scene.triangles.insert(scene.triangles.begin() + 5, {b, b, b + 1});
  scene.triangles.insert(scene.triangles.begin() + 9, {b, b + 1, b + 1});
  return test::merge(scene, test::make_soup(5, 300, glm::vec3(-1.5f), glm::vec3(1.5f), 0.2f));
}

const std::vector<Case>& cases() {
  static const std::vector<Case> all = test::brute_cases(
      {{"pyramid", make_builtin_scene("pyramid")},
       {"sphere+soup", test::sphere_in_soup()},
       {"far soup", test::transformed(test::make_soup(2, 2000, glm::vec3(-1), glm::vec3(1), 0.08f),
                                      100.0f, glm::vec3(5000, -300, 20))},
       {"degenerates", with_degenerates()}},
      [](const test::NamedScene& s) {
        return test::mixed_rays(
            s.scene,
            {.camera_width = 80, .camera_height = 60, .chords = 5000, .axis_parallel = 3000});
      });
  return all;
}

std::unique_ptr<Accelerator> embree(const Scene& scene, int build_threads) {
  AccelParams params;
  params.build_threads = build_threads;
  auto accel = make_accelerator("embree", params);
  accel->build(scene);
  return accel;
}

// Our kernel on one triangle: does `id` block `ray` at about `t`?
bool kernel_confirms(const Scene& scene, const Ray& ray, const Hit& hit) {
  const PreparedRay<KernelReal> prepared(ray, 0.0);
  float t, u, v;
  return intersect_triangle(prepared, scene.vertex(uint32_t(hit.id), 0),
                            scene.vertex(uint32_t(hit.id), 1), scene.vertex(uint32_t(hit.id), 2),
                            ray.tmax, t, u, v) &&
         close_t(scene, ray, hit.id, hit.t, t);
}

TEST(Embree, NearestHitsMatchBruteOnClearRays) {
  SKIP_WITHOUT_EMBREE();
  for (const int build_threads : {1, 0}) {
    for (const Case& c : cases()) {
      const auto accel = embree(c.scene, build_threads);
      const std::vector<Hit> hits = test::trace_all(*accel, c.rays, 2);
      size_t compared = 0, found = 0, bad = 0;
      for (size_t i = 0; i < c.rays.size(); ++i) {
        const Hit& want = c.expected[i];
        const Hit& got = hits[i];
        if (want.found() && !clear(want)) continue;
        // A miss is clear unless Embree grazes an edge brute's kernel just missed.
        if (!want.found() && got.found() && !clear(got)) continue;
        ++compared;
        found += want.found();
        const bool same = want.found() ? got.id == want.id &&
                                             close_t(c.scene, c.rays[i], want.id, got.t, want.t) &&
                                             std::abs(got.u - want.u) < 1e-3f &&
                                             std::abs(got.v - want.v) < 1e-3f
                                       : !got.found();
        if (!same && ++bad <= 5)
          ADD_FAILURE() << c.name << " ray " << i << " (build threads " << build_threads
                        << "): brute " << want.id << " t " << want.t << " u " << want.u << " v "
                        << want.v << ", embree " << got.id << " t " << got.t << " u " << got.u
                        << " v " << got.v;
      }
      EXPECT_EQ(bad, 0u) << c.name;
      EXPECT_GT(compared, c.rays.size() * 9 / 10) << c.name;
      EXPECT_GT(found, c.rays.size() / 10) << c.name;
    }
  }
}

TEST(Embree, AnyHitFoundIffBruteFindsOne) {
  SKIP_WITHOUT_EMBREE();
  for (const Case& c : cases()) {
    const auto accel = embree(c.scene, 0);
    const std::vector<Hit> nearest = test::trace_all(*accel, c.rays, 1);
    const std::vector<Hit> any = test::trace_all(*accel, c.rays, 2, true);
    size_t bad = 0, confirmed = 0;
    for (size_t i = 0; i < c.rays.size(); ++i) {
      const Hit& want = c.expected[i];
      if (want.found() ? !clear(want) : nearest[i].found()) continue;  // only clear rays
      const Ray& ray = c.rays[i];
      bool ok = any[i].found() == want.found();
      if (any[i].found()) {
        // A real blocker: inside the segment, and our kernel agrees when the hit is clear.
        ok = ok && any[i].t > ray.tmin && any[i].t <= ray.tmax &&
             size_t(any[i].id) < c.scene.triangle_count();
        if (clear(any[i])) {
          ok = ok && kernel_confirms(c.scene, ray, any[i]);
          ++confirmed;
        }
      }
      if (!ok && ++bad <= 5)
        ADD_FAILURE() << c.name << " ray " << i << ": brute " << want.id << ", any-hit "
                      << any[i].id << " t " << any[i].t;
    }
    EXPECT_EQ(bad, 0u) << c.name;
    EXPECT_GT(confirmed, 0u) << c.name;
  }
}

// Embree's packet mode (trace_packet: rtcIntersect16 / rtcOccluded16) answers what its
// single-ray queries answer: nearest hits byte for byte, any-hit found on the same rays and
// each named blocker inside the ray's segment. Packets of 64 and of 7 (a part-filled 16).
TEST(Embree, PacketsAnswerAsSingleRays) {
  SKIP_WITHOUT_EMBREE();
  for (const Case& c : cases()) {
    const auto accel = embree(c.scene, 0);
    const std::vector<Hit> nearest = test::trace_all(*accel, c.rays, 1);
    const std::vector<Hit> any = test::trace_all(*accel, c.rays, 1, true);
    size_t found = 0;
    for (const size_t packet : {size_t{64}, size_t{7}}) {
      const std::vector<Hit> packed = test::trace_all(*accel, c.rays, 2, false, packet);
      const std::vector<Hit> packed_any = test::trace_all(*accel, c.rays, 2, true, packet);
      EXPECT_EQ(test::count_mismatches(c.name + " embree packets", packed, nearest), 0u);
      size_t bad = 0;
      for (size_t i = 0; i < c.rays.size(); ++i) {
        found += packed_any[i].found();
        const Ray& ray = c.rays[i];
        bad +=
            packed_any[i].found() != any[i].found() ||
            (packed_any[i].found() && !(packed_any[i].t > ray.tmin && packed_any[i].t <= ray.tmax));
      }
      EXPECT_EQ(bad, 0u) << c.name << ", packets of " << packet;
    }
    EXPECT_GT(found, c.rays.size() / 10) << c.name;
  }
}

TEST(Embree, InvalidRaysAreMisses) {
  SKIP_WITHOUT_EMBREE();
  const Case& c = cases()[0];
  const auto accel = embree(c.scene, 1);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const glm::vec3 centre = 0.5f * (c.scene.bounds().lo + c.scene.bounds().hi);
  const glm::vec3 eye = centre + glm::vec3(0, 0, 100);
  const std::vector<Ray> rays = {
      {eye, 0.0f, {0, 0, 0}, inf},          {eye, 0.0f, {nan, 0, -1}, inf},
      {eye, 0.0f, {0, 0, -inf}, inf},       {{nan, 0, 0}, 0.0f, {0, 0, -1}, inf},
      {{inf, 0, 0}, 0.0f, {0, 0, -1}, inf}, {eye, 5.0f, {0, 0, -1}, 1.0f},
      {eye, nan, {0, 0, -1}, inf}};
  auto context = accel->make_context();
  for (const Ray& ray : rays) {
    EXPECT_EQ(accel->intersect(ray, *context), Hit{});
    EXPECT_EQ(accel->any_hit(ray, *context), Hit{});
  }
}

using Outcome = test::CommandOutcome;

// Exit status `status` with one stderr line mentioning `mention`.
void expect_failure(const Outcome& result, int status, const std::string& mention) {
  EXPECT_EQ(result.status, status) << result.err;
  EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
  EXPECT_NE(result.err.find(mention), std::string::npos) << result.err;
}

// A pyramid ray file: a camera view plus random chords (misses among them) and one
// invalid ray.
std::string pyramid_rays() {
  static const std::string path = [] {
    const Scene scene = make_builtin_scene("pyramid");
    std::vector<Ray> rays = test::camera_rays(scene.bounds(), 64, 48);
    const std::vector<Ray> chords = test::random_chords(scene.bounds(), 9, 2000);
    rays.insert(rays.end(), chords.begin(), chords.end());
    rays.push_back({{0, 0, 0}, 0.0f, {0, 0, 0}, 1.0f});
    const std::string file = temp_path("ez_pyramid.rays");
    write_rays(file, rays);
    return file;
  }();
  return path;
}

std::string trace_args(const std::string& rays, const std::string& out, const std::string& rest) {
  return "trace builtin:pyramid --rays " + quoted(rays) + " --out " + quoted(out) + " " + rest;
}

TEST(EmbreeCli, StatsHaveNullCountersAndEchoBuildThreads) {
  const std::string stats = temp_path("ez_embree.json"), hits = temp_path("ez_embree.hits");
  const Outcome result = test::run_gridscope(
      trace_args(pyramid_rays(), hits,
                 "--accel embree --threads 2 --build-threads 1 --stats " + quoted(stats)));
  if (!have_embree()) {
    expect_failure(result, 2, "built without Embree");
    GTEST_SKIP() << "gridscope was built without Embree: --accel embree is exit 2 as it must be";
  }
  ASSERT_EQ(result.status, 0) << result.err;
  const nlohmann::json json = nlohmann::json::parse(slurp(stats));
  EXPECT_EQ(json["accel"], "embree");
  EXPECT_TRUE(json["intersection_tests"].is_null());
  EXPECT_TRUE(json["traversal_steps"].is_null());
  EXPECT_TRUE(json["mailbox_rejections"].is_null());
  EXPECT_TRUE(json["nodes"].is_null());
  EXPECT_EQ(json["parameters"]["build_threads"], 1);
  EXPECT_GT(json["memory_bytes"].get<uint64_t>(), 0u);
  EXPECT_EQ(slurp(hits).size(), 16 * read_rays(pyramid_rays()).size());
}

// brute's hits, then zero given them: the same bytes; and likewise for --occluded.
TEST(ZeroCli, ReproducesTheOracleByteForByte) {
  for (const std::string mode : {"", "--occluded"}) {
    const std::string oracle = temp_path("ez_oracle.hits"), out = temp_path("ez_zero.hits");
    const std::string stats = temp_path("ez_zero.json");
    Outcome result =
        test::run_gridscope(trace_args(pyramid_rays(), oracle, "--accel brute " + mode));
    ASSERT_EQ(result.status, 0) << result.err;
    result = test::run_gridscope(trace_args(pyramid_rays(), out,
                                            "--accel zero --threads 2 --repeat 2 --oracle " +
                                                quoted(oracle) + " --stats " + quoted(stats) + " " +
                                                mode));
    ASSERT_EQ(result.status, 0) << result.err;
    const std::string expected = slurp(oracle);
    ASSERT_FALSE(expected.empty());
    EXPECT_TRUE(slurp(out) == expected) << "zero's hits differ from the oracle's " << mode;
    const nlohmann::json json = nlohmann::json::parse(slurp(stats));
    EXPECT_EQ(json["accel"], "zero");
    EXPECT_EQ(json["parameters"]["oracle"], oracle);
    // One test per ray the oracle says hits, none for the others.
    size_t hit_count = 0;
    for (const Hit& hit : read_hits(oracle)) hit_count += hit.found();
    EXPECT_EQ(json["intersection_tests"], hit_count);
  }
}

TEST(ZeroCli, NeedsAnOracle) {
  const Outcome result =
      test::run_gridscope(trace_args(pyramid_rays(), temp_path("ez_none.hits"), "--accel zero"));
  expect_failure(result, 2, "--oracle");
  // Renders are not keyed by ray index: zero is a trace-only structure.
  expect_failure(test::run_gridscope("render builtin:pyramid --accel zero --out " +
                                     quoted(temp_path("ez_zero.png"))),
                 2, "--oracle");
}

TEST(ZeroCli, RefusesAnOracleOfTheWrongLength) {
  const std::string oracle = temp_path("ez_short.hits");
  write_hits(oracle, std::vector<Hit>(7));
  expect_failure(test::run_gridscope(trace_args(pyramid_rays(), temp_path("ez_short_out.hits"),
                                                "--accel zero --oracle " + quoted(oracle))),
                 1, oracle);
  // Not a whole number of records, and a file that is not there.
  std::ofstream(oracle, std::ios::binary) << std::string(23, '\0');
  expect_failure(test::run_gridscope(trace_args(pyramid_rays(), temp_path("ez_short_out.hits"),
                                                "--accel zero --oracle " + quoted(oracle))),
                 1, oracle);
  const std::string missing = temp_path("ez_missing.hits");
  expect_failure(test::run_gridscope(trace_args(pyramid_rays(), temp_path("ez_short_out.hits"),
                                                "--accel zero --oracle " + quoted(missing))),
                 1, missing);
}

TEST(Zero, RefusesRaysWithoutAnIndex) {
  AccelParams params;
  EXPECT_THROW(make_accelerator("zero", params), UsageError);
  const std::string oracle = temp_path("ez_lib.hits");
  write_hits(oracle, std::vector<Hit>(3));
  params.oracle_path = oracle;
  auto zero = make_accelerator("zero", params);
  zero->build(make_builtin_scene("pyramid"));
  auto context = zero->make_context();
  EXPECT_THROW(zero->intersect(Ray{}, *context), UsageError);
  context->ray_index = 2;
  EXPECT_EQ(zero->intersect(Ray{}, *context), Hit{});  // the oracle says miss
}

}  // namespace
}  // namespace gs
