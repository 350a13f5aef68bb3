// The renderer's workloads and their replay: ray keys are a bijection onto [0, keys), a
// recorded render of scenes whose answers follow from their geometry holds exactly those
// answers, the paper's workload (bounces 0) gives the closed-form colours of a lit and of a
// shadowed floor, bounces only add light and do not depend on the thread count, and the
// zero-overhead oracle replays a recorded render into the same image byte for byte. The
// display table gives the bytes the gamma transform's definition gives, float by float
// around each of its steps.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "core/accel/brute.h"
#include "core/accel/grid1d/grid1d.h"
#include "core/accel/registry.h"
#include "core/accel/zero_overhead.h"
#include "core/base/error.h"
#include "core/geometry/ray_io.h"
#include "core/render/display.h"
#include "core/render/render.h"
#include "tests/test_util.h"

namespace gs {
namespace {

using test::quoted;
using test::temp_path;

// The square [-100, 100]^2 in the plane z = `z`, as two triangles.
Scene square_at(float z) {
  Scene scene;
  scene.vertices = {{-100, -100, z}, {100, -100, z}, {100, 100, z}, {-100, 100, z}};
  scene.triangles = {{0, 1, 2}, {0, 2, 3}};
  return scene;
}

// The floor z = 0 alone (triangles 0, 1): lit everywhere, nothing to block a shadow ray.
Scene open_floor() { return square_at(0.0f); }
// The floor and, just behind the camera, a ceiling (triangles 2, 3) between every floor
// point and the light (which sits above and behind the camera): the floor is all in shadow.
Scene covered_floor() { return test::merge(square_at(0.0f), square_at(5.5f)); }

// Looking straight down at the floor from z = 5; an odd image size puts the centre pixel's
// ray on the axis, through the origin.
Camera down_camera() {
  Camera camera;
  camera.eye = {0, 0, 5};
  camera.target = {0, 0, 0};
  camera.up = {0, 1, 0};
  return camera;
}

RenderSettings settings_of(int width, int height, int spp, int bounces, int threads) {
  RenderSettings settings{width, height, spp, threads};
  settings.bounces = bounces;
  return settings;
}

struct Recorded {
  RenderOutcome outcome;
  std::vector<Hit> answers;
};

Recorded record(const Scene& scene, const std::string& accel_name, const Camera& camera,
                const RenderSettings& settings) {
  const std::unique_ptr<Accelerator> accel = make_accelerator(accel_name, AccelParams{});
  Recorded run;
  run.outcome = build_and_render(scene, *accel, camera, settings, &run.answers).outcome;
  return run;
}

// Render answers by key: nearest hits bit for bit; shadow rays blocked or not (any-hit may
// name another blocker: which one a walk meets first depends on the order of its tests, and
// with lazy building on two threads, on what the other thread has built).
void expect_same_answers(const std::vector<Hit>& got, const std::vector<Hit>& expected,
                         const std::string& what) {
  ASSERT_EQ(got.size(), expected.size()) << what;
  for (size_t key = 0; key < got.size(); ++key)
    if (key % 2 == size_t(RayKind::nearest))
      ASSERT_EQ(got[key], expected[key]) << what << ", key " << key;
    else
      ASSERT_EQ(got[key].found(), expected[key].found()) << what << ", key " << key;
}

// 8-bit value the renderer writes for a linear intensity (gamma 2.2, rounded).
int display_value(double linear) { return int(255.0 * std::pow(linear, 1.0 / 2.2) + 0.5); }

constexpr double kAlbedo[3] = {0.85, 0.80, 0.72};
constexpr double kAmbient = 0.15;

// A linear value's byte by the transform's definition: gamma 2.2 by powf, then 8 bits.
int byte_by_definition(float linear) {
  const float display = std::pow(std::min(linear, 1.0f), 1.0f / 2.2f);
  return int(uint8_t(std::clamp(display, 0.0f, 1.0f) * 255.0f + 0.5f));
}

TEST(DisplayTable, StepsAreWhereTheDefinitionsByteRises) {
  const std::array<float, 256>& steps = linear_byte_steps();
  EXPECT_EQ(steps[0], 0.0f);
  for (int k = 1; k < 256; ++k) {
    const float step = steps[size_t(k)];
    ASSERT_GT(step, steps[size_t(k - 1)]) << k;
    EXPECT_EQ(byte_by_definition(step), k);
    EXPECT_EQ(byte_by_definition(std::nextafter(step, 0.0f)), k - 1);
  }
}

TEST(DisplayTable, GivesTheDefinitionsByteForEveryFloatNearEachStep) {
  // Only near a step can powf's rounding make the two differ (docs/design.md §6.10).
  constexpr uint32_t kAround = 4096;
  const uint32_t one = std::bit_cast<uint32_t>(1.0f);
  const std::array<float, 256>& steps = linear_byte_steps();
  for (int k = 1; k < 256; ++k) {
    const uint32_t at = std::bit_cast<uint32_t>(steps[size_t(k)]);
    const uint32_t last = std::min(at + kAround, one);
    for (uint32_t bits = at - std::min(at, kAround); bits <= last; ++bits) {
      const float x = std::bit_cast<float>(bits);
      ASSERT_EQ(int(linear_byte(x)), byte_by_definition(x)) << "x = " << x << ", step " << k;
    }
  }
}

TEST(DisplayTable, GivesTheDefinitionsByteOnRandomAndSpecialValues) {
  std::mt19937 random(7);
  std::uniform_int_distribution<uint32_t> any_bits(0, std::bit_cast<uint32_t>(1.0f));
  std::uniform_real_distribution<float> any_value(0.0f, 2.0f);
  std::vector<float> values = {0.0f,
                               -0.0f,
                               std::numeric_limits<float>::denorm_min(),
                               std::numeric_limits<float>::min(),
                               1.0f,
                               std::nextafter(1.0f, 2.0f),
                               2.0f,
                               std::numeric_limits<float>::infinity()};
  for (int i = 0; i < 100000; ++i) {
    values.push_back(std::bit_cast<float>(any_bits(random)));
    values.push_back(any_value(random));
  }
  for (const float x : values) ASSERT_EQ(int(linear_byte(x)), byte_by_definition(x)) << x;
  // The three channels, and the multi-sample path (display colour, then its bytes).
  for (size_t i = 0; i + 2 < values.size(); i += 3) {
    const glm::vec3 linear(values[i], values[i + 1], values[i + 2]);
    const std::array<uint8_t, 3> bytes = linear_bytes(linear);
    EXPECT_EQ(bytes, display_bytes(display_colour(linear)));
    for (int c = 0; c < 3; ++c) ASSERT_EQ(int(bytes[size_t(c)]), byte_by_definition(linear[c]));
  }
}

TEST(RenderKeys, AreABijectionOntoTheKeyRange) {
  for (const RenderSettings settings :
       {settings_of(3, 2, 1, 0, 1), settings_of(3, 2, 3, 2, 1), settings_of(1, 5, 2, 4, 1)}) {
    const uint64_t expected = uint64_t(settings.width * settings.height * settings.spp) *
                              uint64_t(settings.bounces + 1) * 2;
    ASSERT_EQ(render_ray_keys(settings), expected);
    std::vector<int> seen(expected, 0);
    for (size_t pixel = 0; pixel < size_t(settings.width * settings.height); ++pixel)
      for (int sample = 0; sample < settings.spp; ++sample)
        for (int bounce = 0; bounce <= settings.bounces; ++bounce)
          for (const RayKind kind : {RayKind::nearest, RayKind::shadow}) {
            const uint64_t key = render_ray_key(settings, pixel, sample, bounce, kind);
            ASSERT_LT(key, expected);
            ++seen[key];
          }
    // As many tuples as keys, each key met once: a bijection.
    for (uint64_t key = 0; key < expected; ++key) EXPECT_EQ(seen[key], 1) << "key " << key;
  }
}

TEST(RenderRecord, OpenFloorEveryPrimaryHitsNoShadowRayIsBlocked) {
  const RenderSettings settings = settings_of(9, 7, 2, 1, 2);
  const Recorded run = record(open_floor(), "brute", down_camera(), settings);
  ASSERT_EQ(run.answers.size(), render_ray_keys(settings));
  for (size_t pixel = 0; pixel < 9 * 7; ++pixel)
    for (int s = 0; s < settings.spp; ++s) {
      const Hit primary = run.answers[render_ray_key(settings, pixel, s, 0, RayKind::nearest)];
      EXPECT_TRUE(primary.id == 0 || primary.id == 1) << "pixel " << pixel;
      // Nothing but the floor: shadow rays and upward bounces find nothing.
      EXPECT_FALSE(run.answers[render_ray_key(settings, pixel, s, 0, RayKind::shadow)].found());
      EXPECT_FALSE(run.answers[render_ray_key(settings, pixel, s, 1, RayKind::nearest)].found());
      EXPECT_FALSE(run.answers[render_ray_key(settings, pixel, s, 1, RayKind::shadow)].found());
    }
  // Primary + shadow + bounce per sample (the bounce's hit is a miss: no shadow ray).
  EXPECT_EQ(run.outcome.rays, uint64_t(9 * 7 * 2 * 3));
}

TEST(RenderRecord, CoveredFloorEveryShadowRayHitsTheCeiling) {
  const RenderSettings settings = settings_of(9, 7, 1, 1, 2);
  const Recorded run = record(covered_floor(), "brute", down_camera(), settings);
  for (size_t pixel = 0; pixel < 9 * 7; ++pixel) {
    const auto answer = [&](int bounce, RayKind kind) {
      return run.answers[render_ray_key(settings, pixel, 0, bounce, kind)];
    };
    const Hit primary = answer(0, RayKind::nearest), shadow = answer(0, RayKind::shadow);
    EXPECT_TRUE(primary.id == 0 || primary.id == 1) << "pixel " << pixel;
    EXPECT_TRUE(shadow.id == 2 || shadow.id == 3) << "pixel " << pixel;
    EXPECT_GT(shadow.t, 0.0f);
    EXPECT_LE(shadow.t, 1.0f);  // before the light
    // A bounce goes up to the ceiling (or grazes out past it) and sees its unlit underside:
    // no shadow ray is cast from there.
    const Hit bounce = answer(1, RayKind::nearest);
    EXPECT_TRUE(!bounce.found() || bounce.id == 2 || bounce.id == 3) << "pixel " << pixel;
    EXPECT_FALSE(answer(1, RayKind::shadow).found());
  }
}

// The light as render.cpp places it: above, behind and right of the eye, scaled by the
// scene box's diagonal.
glm::dvec3 light_of(const Scene& scene, const Camera& camera) {
  const Box box = scene.bounds();
  const double size = glm::length(glm::dvec3(box.hi - box.lo));
  return glm::dvec3(camera.eye) - glm::dvec3(camera.forward()) * (0.5 * size) +
         glm::dvec3(camera.true_up()) * size + glm::dvec3(camera.right()) * (0.3 * size);
}

TEST(RenderImage, LitAndShadowedFloorHaveClosedFormColours) {
  const RenderSettings settings = settings_of(9, 9, 1, 0, 1);
  const RenderOutcome lit = record(open_floor(), "grid1d", down_camera(), settings).outcome;
  const RenderOutcome dark = record(covered_floor(), "grid1d", down_camera(), settings).outcome;
  // The centre pixel sees the origin, whose normal is +z.
  const glm::dvec3 light = light_of(open_floor(), down_camera());
  const double lambert = light.z / glm::length(light);
  const size_t centre = 4 * 9 + 4;
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(lit.image.rgba[4 * centre + k],
                display_value(kAlbedo[k] * (kAmbient + (1.0 - kAmbient) * lambert)), 1);
    EXPECT_NEAR(dark.image.rgba[4 * centre + k], display_value(kAlbedo[k] * kAmbient), 1);
  }
}

// Renders place the light by their structure's box (make_lighting(accel.bounds(), ...)), not
// by a scan of the scene's triangles on every pass: every structure must keep exactly the
// box Scene::bounds computes, or its images would be lit from elsewhere. A floor and a
// pyramid whose triangles leave a vertex unused (far off, so that a box of the vertices
// rather than of the triangles' corners would differ).
TEST(RenderImage, EveryStructureKeepsTheSceneBoxTheLightIsPlacedBy) {
  for (Scene scene : {open_floor(), load_scene("builtin:pyramid")}) {
    scene.vertices.push_back({1e6f, -1e6f, 1e6f});
    const Box box = scene.bounds();
    ASSERT_LT(box.hi.x, 1e6f);
    int checked = 0;
    for (const Structure& structure : structures()) {
      if (!structure.available() || structure.needs_oracle) continue;
      const std::unique_ptr<Accelerator> accel = structure.make(AccelParams{});
      accel->build(scene);
      const Box kept = accel->bounds();
      for (int a = 0; a < 3; ++a) {
        EXPECT_EQ(kept.lo[a], box.lo[a]) << structure.name << " axis " << a;
        EXPECT_EQ(kept.hi[a], box.hi[a]) << structure.name << " axis " << a;
      }
      ++checked;
    }
    EXPECT_GE(checked, 6);
  }
}

// Stands in for a structure to see what an image's sampling pass hands over: the sample, the
// weight of each sample ray and the rays spawned from brute force's answers.
class SampleSpy final : public Accelerator {
 public:
  std::string name() const override { return "spy"; }
  void build(const Scene& scene) override { brute_.build(scene); }
  void sample(std::span<const Ray> rays, double weight, const SpawnRays& spawn,
              int /*threads*/) override {
    const std::unique_ptr<ThreadContext> context = brute_.make_context();
    primaries.assign(rays.begin(), rays.end());
    rays_per_sample_ray = weight;
    for (const Ray& ray : primaries) spawn(ray, brute_.intersect(ray, *context), spawned);
  }
  Box bounds() const override { return brute_.bounds(); }
  std::unique_ptr<ThreadContext> make_context() const override { return brute_.make_context(); }
  Hit intersect(const Ray& ray, ThreadContext& context) const override {
    return brute_.intersect(ray, context);
  }
  Hit any_hit(const Ray& ray, ThreadContext& context) const override {
    return brute_.any_hit(ray, context);
  }
  StructureStats stats() const override { return brute_.stats(); }

  std::vector<Ray> primaries, spawned;
  double rays_per_sample_ray = 0.0;

 private:
  BruteForce brute_{};
};

// 17x9 pixels make 3x2 blocks of 8x8: six sample pixels, each standing for 17*9*2/6 = 51 of
// the image's primary rays (spp 2). Each primary meets the floor, which faces the light: one
// shadow ray each, from just above the floor to the light.
TEST(RenderSample, SamplesEachHitsShadowRayAtThePrimariesWeight) {
  const Scene scene = open_floor();
  SampleSpy spy;
  spy.build(scene);
  sample_image(scene, spy, down_camera(), settings_of(17, 9, 2, 0, 1));
  ASSERT_EQ(spy.primaries.size(), 6u);
  EXPECT_EQ(spy.rays_per_sample_ray, 51.0);
  ASSERT_EQ(spy.spawned.size(), 6u);
  const glm::dvec3 light = light_of(scene, down_camera());
  for (const Ray& shadow : spy.spawned) {
    EXPECT_GT(shadow.origin.z, 0.0f);
    EXPECT_LT(shadow.origin.z, 0.1f);
    EXPECT_EQ(shadow.tmax, 1.0f);
    const glm::dvec3 end = glm::dvec3(shadow.origin) + glm::dvec3(shadow.dir);
    EXPECT_LT(glm::length(end - light), 1e-4 * glm::length(light));
  }
  // Looking away from the floor: no primary hits, no shadow ray.
  Camera up = down_camera();
  up.target = {0, 0, 10};
  SampleSpy away;
  away.build(scene);
  sample_image(scene, away, up, settings_of(17, 9, 2, 0, 1));
  EXPECT_EQ(away.primaries.size(), 6u);
  EXPECT_TRUE(away.spawned.empty());
}

// grid1d counts the shadow rays too: under the ceiling the six primaries and their six
// shadow rays all cross the scene box, so the root stands for 12 * 51 rays.
TEST(RenderSample, Grid1DCountsPrimaryAndShadowSegments) {
  const Scene scene = covered_floor();
  Grid1D grid(AccelParams{});
  grid.build(scene);
  sample_image(scene, grid, down_camera(), settings_of(17, 9, 2, 0, 1));
  EXPECT_EQ(grid.cost_report(0).figures.rays, 12.0 * 51.0);
}

TEST(RenderImage, BouncesOnlyAddLightAndIgnoreTheThreadCount) {
  const Scene scene = load_scene("builtin:pyramid");
  const Camera camera = frame_box(scene.bounds(), 32.0f / 24.0f);
  const Image direct = record(scene, "grid1d", camera, settings_of(32, 24, 2, 0, 2)).outcome.image;
  const Image one = record(scene, "grid1d", camera, settings_of(32, 24, 2, 1, 1)).outcome.image;
  const Image two = record(scene, "grid1d", camera, settings_of(32, 24, 2, 1, 2)).outcome.image;
  EXPECT_EQ(one.rgba, two.rgba);
  // Same primary rays and direct light, plus non-negative bounce light.
  size_t brighter = 0;
  for (size_t i = 0; i < direct.rgba.size(); ++i) {
    ASSERT_GE(one.rgba[i], direct.rgba[i]) << "byte " << i;
    brighter += one.rgba[i] > direct.rgba[i];
  }
  EXPECT_GT(brighter, 0u);
}

TEST(RenderReplay, ZeroReproducesTheRecordedImageExactly) {
  const Scene scene = load_scene("builtin:pyramid");
  const Camera camera = frame_box(scene.bounds(), 24.0f / 16.0f);
  for (const int bounces : {0, 1})
    for (const int spp : {1, 4}) {
      const Recorded run = record(scene, "grid1d", camera, settings_of(24, 16, spp, bounces, 1));
      const Recorded again = record(scene, "grid1d", camera, settings_of(24, 16, spp, bounces, 2));
      expect_same_answers(again.answers, run.answers, "1 and 2 threads");
      for (const int threads : {1, 2}) {
        ZeroOverhead zero(run.answers);
        const RenderOutcome replay =
            build_and_render(scene, zero, camera, settings_of(24, 16, spp, bounces, threads))
                .outcome;
        EXPECT_EQ(replay.image.rgba, run.outcome.image.rgba)
            << "bounces " << bounces << ", spp " << spp << ", threads " << threads;
        EXPECT_EQ(replay.rays, run.outcome.rays);
      }
    }
}

RenderSettings with_packets(RenderSettings settings, bool packets) {
  settings.packets = packets;
  return settings;
}

// Packets (8x8 blocks of primary rays, then their shadow rays) change how rays are traced,
// never what they answer: each ray's answer and the image are those of single rays, and for
// grid1d those of brute force. 37x21 leaves partial blocks at the right and bottom.
TEST(RenderPackets, AnswerAsSingleRaysAndBruteForce) {
  const Scene scene = load_scene("builtin:pyramid");
  const Camera camera = frame_box(scene.bounds(), 37.0f / 21.0f);
  std::vector<std::string> accels = {"grid1d"};
  if (find_structure("embree")->available()) accels.push_back("embree");
  for (const int bounces : {0, 1})
    for (const int spp : {1, 3}) {
      const RenderSettings single = with_packets(settings_of(37, 21, spp, bounces, 1), false);
      const Recorded brute = record(scene, "brute", camera, single);
      for (const std::string& accel : accels)
        for (const int threads : {1, 2}) {
          const std::string what = accel + ", bounces " + std::to_string(bounces) + ", spp " +
                                   std::to_string(spp) + ", threads " + std::to_string(threads);
          RenderSettings settings = settings_of(37, 21, spp, bounces, threads);
          const Recorded off = record(scene, accel, camera, with_packets(settings, false));
          const Recorded on = record(scene, accel, camera, with_packets(settings, true));
          // Embree counts nothing of its own walk.
          if (accel == "grid1d") {
            EXPECT_GT(on.outcome.counters.packets, 0u) << what;
          }
          EXPECT_EQ(off.outcome.counters.packets, 0u) << what;
          expect_same_answers(on.answers, off.answers, what);
          EXPECT_EQ(on.outcome.image.rgba, off.outcome.image.rgba) << what;
          EXPECT_EQ(on.outcome.rays, off.outcome.rays) << what;
          if (accel != "grid1d") continue;
          EXPECT_EQ(on.outcome.image.rgba, brute.outcome.image.rgba) << what;
          expect_same_answers(on.answers, brute.answers, what);
        }
    }
}

// With packets a pixel's record holds its share of its block's cost: the shares add up to
// what the render's counters say, as single rays' records do.
TEST(RenderPackets, PixelRecordsAddUpToTheCounters) {
  const Scene scene = load_scene("builtin:lumpy");
  const Camera camera = frame_box(scene.bounds(), 1.0f);
  for (const bool packets : {false, true}) {
    const Recorded run =
        record(scene, "grid1d", camera, with_packets(settings_of(20, 20, 2, 0, 2), packets));
    uint64_t steps = 0, tests = 0;
    for (const PixelRecord& pixel : run.outcome.pixels) steps += pixel.steps, tests += pixel.tests;
    EXPECT_EQ(steps, run.outcome.counters.traversal_steps) << "packets " << packets;
    EXPECT_EQ(tests, run.outcome.counters.intersection_tests) << "packets " << packets;
    EXPECT_GT(tests, 0u);
  }
}

// The viewer's passes (coarse, full, accumulated) give the same images by packets.
TEST(RenderPackets, ProgressivePassesMatchSingleRays) {
  const Scene scene = load_scene("builtin:pyramid");
  const Camera camera = frame_box(scene.bounds(), 29.0f / 19.0f);
  const std::unique_ptr<Accelerator> accel = make_accelerator("grid1d", AccelParams{});
  accel->build(scene);
  for (const int stride : {8, 1}) {
    std::vector<Image> images;
    for (const bool packets : {false, true}) {
      const RenderSettings settings = with_packets(settings_of(29, 19, 1, 0, 2), packets);
      images.push_back(render_pass(scene, *accel, camera, settings, stride, 0, nullptr).image);
    }
    EXPECT_EQ(images[0].rgba, images[1].rgba) << "stride " << stride;
  }
  std::vector<std::vector<glm::vec3>> sums(2, std::vector<glm::vec3>(29 * 19));
  for (int spp = 2; spp <= 4; ++spp) {
    std::vector<Image> images;
    for (const bool packets : {false, true}) {
      const RenderSettings settings = with_packets(settings_of(29, 19, spp, 1, 2), packets);
      images.push_back(
          render_pass(scene, *accel, camera, settings, 1, spp == 2 ? 0 : spp - 1, &sums[packets])
              .image);
    }
    EXPECT_EQ(images[0].rgba, images[1].rgba) << "spp " << spp;
  }
}

TEST(RenderReplay, ZeroRefusesAnOracleOfTheWrongLength) {
  const Scene scene = open_floor();
  const RenderSettings settings = settings_of(4, 4, 1, 0, 1);
  ZeroOverhead zero(std::vector<Hit>(render_ray_keys(settings) - 1));
  EXPECT_THROW(build_and_render(scene, zero, down_camera(), settings), InputError);
}

TEST(RenderSettingsCheck, BouncesOutsideTheRangeAreUsageErrors) {
  for (const int bounces : {-1, kMaxBounces + 1})
    EXPECT_THROW(check_render_settings(settings_of(4, 4, 1, bounces, 1)), UsageError);
  EXPECT_NO_THROW(check_render_settings(settings_of(4, 4, 1, kMaxBounces, 1)));
}

TEST(RenderCli, BadBouncesExitWithStatus2) {
  const std::string out = quoted(temp_path("bounces.png"));
  for (const std::string command : {"render", "shot"})
    for (const std::string value : {"-1", "5", "x", "1.5"}) {
      const test::CommandOutcome run = test::run_gridscope(
          command + " builtin:pyramid --size 8x8 --out " + out + " --bounces=" + value);
      EXPECT_EQ(run.status, 2) << command << " --bounces " << value << ": " << run.err;
      EXPECT_NE(run.err.find("--bounces"), std::string::npos) << run.err;
    }
}

TEST(RenderCli, PacketsOnAndOffWriteTheSamePngAndHits) {
  std::vector<std::string> images;
  std::vector<std::vector<Hit>> answers;
  for (const std::string packets : {"on", "off"}) {
    const std::string png = temp_path("packets-" + packets + ".png"),
                      hits = temp_path("packets-" + packets + ".hits"),
                      stats = temp_path("packets-" + packets + ".json");
    const test::CommandOutcome run = test::run_gridscope(
        "render builtin:lumpy --size 24x16 --spp 2 --threads 2 --packets " + packets + " --out " +
        quoted(png) + " --record-hits " + quoted(hits) + " --stats " + quoted(stats));
    ASSERT_EQ(run.status, 0) << run.err;
    images.push_back(test::slurp(png));
    answers.push_back(read_hits(hits));
    const nlohmann::json figures = nlohmann::json::parse(test::slurp(stats));
    EXPECT_EQ(figures["parameters"]["packets"], packets == "on");
    EXPECT_EQ(figures["packets"].is_null(), packets == "off") << figures["packets"];
  }
  EXPECT_EQ(images[0], images[1]);
  expect_same_answers(answers[0], answers[1], "render --packets on and off");
  for (const std::string command : {"render", "shot"}) {
    const test::CommandOutcome run = test::run_gridscope(
        command + " builtin:pyramid --size 8x8 --packets yes --out " + quoted(temp_path("x.png")));
    EXPECT_EQ(run.status, 2) << command << ": " << run.err;
    EXPECT_NE(run.err.find("--packets"), std::string::npos) << run.err;
  }
}

TEST(RenderCli, RecordedHitsReplayWithZeroIntoTheSamePng) {
  const std::string png = temp_path("recorded.png"), hits = temp_path("recorded.hits"),
                    replay = temp_path("replayed.png");
  const std::string common = " builtin:pyramid --size 20x12 --spp 2 --bounces 1 --threads 2";
  ASSERT_EQ(test::run_gridscope("render" + common + " --out " + quoted(png) + " --record-hits " +
                                quoted(hits))
                .status,
            0);
  EXPECT_EQ(read_hits(hits).size(), render_ray_keys(settings_of(20, 12, 2, 1, 1)));
  const test::CommandOutcome run = test::run_gridscope(
      "render" + common + " --accel zero --oracle " + quoted(hits) + " --out " + quoted(replay));
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(test::slurp(replay), test::slurp(png));
}

TEST(RenderCli, ZeroWithAShortOracleExitsWithStatus1NamingIt) {
  const std::string hits = temp_path("short.hits");
  write_hits(hits, std::vector<Hit>(10));
  const test::CommandOutcome run =
      test::run_gridscope("render builtin:pyramid --size 8x8 --accel zero --oracle " +
                          quoted(hits) + " --out " + quoted(temp_path("short.png")));
  EXPECT_EQ(run.status, 1);
  EXPECT_NE(run.err.find(hits), std::string::npos) << run.err;
  EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
}

// `trace --sample-image WxH --camera C` on the image's primary rays samples what render's pass
// samples (primaries and their shadow rays), so it builds render's structure: the same voxels
// as sample_image in this process, built out. Without --camera it samples the primaries only,
// and on this view that cuts differently.
TEST(RenderCli, TraceWithTheImagesCameraBuildsTheRendersStructure) {
  const std::string camera = "eye=0.5,-2.2,1.4;target=0,0,0.3;up=0,0,1;fov=45";
  const Scene scene = load_scene("builtin:pyramid");
  // Constants at which the shadow rays' segments change some cut on this small image, so that
  // building without them (no --camera) gives a different structure.
  AccelParams params;
  params.repcost = 0.35, params.travcost = 12.0, params.vertcost = 10.0, params.subcost = 25.0;
  Grid1D grid(params);
  grid.build(scene);
  sample_image(scene, grid, parse_camera(camera), settings_of(160, 120, 1, 0, 1));
  grid.build_all();
  const StructureStats expected = grid.stats();

  const std::string rays = temp_path("image.rays"), stats = temp_path("image_trace.json");
  ASSERT_EQ(test::run_gridscope("rays builtin:pyramid --size 160x120 --camera " + quoted(camera) +
                                " --out " + quoted(rays))
                .status,
            0);
  const auto traced = [&](const std::string& flags) {
    const test::CommandOutcome run = test::run_gridscope(
        "trace builtin:pyramid --eager --repcost 0.35 --travcost 12 --vertcost 10 --subcost 25 "
        "--sample-image 160x120 --rays " +
        quoted(rays) + " --out " + quoted(temp_path("image.hits")) + " --stats " + quoted(stats) +
        flags);
    EXPECT_EQ(run.status, 0) << run.err;
    const nlohmann::json record = nlohmann::json::parse(test::slurp(stats));
    return std::pair<uint64_t, uint64_t>(record.at("voxels_subdivided"), record.at("leaves"));
  };
  const auto with_camera = traced(" --camera " + quoted(camera));
  EXPECT_EQ(with_camera.first, *expected.voxels_subdivided);
  EXPECT_EQ(with_camera.second, *expected.leaves);
  EXPECT_NE(traced(""), with_camera);
  EXPECT_EQ(test::run_gridscope("trace builtin:pyramid --rays " + quoted(rays) + " --out " +
                                quoted(temp_path("image.hits")) + " --camera " + quoted(camera))
                .status,
            2)
      << "--camera without --sample-image";
}

TEST(RenderCli, ZeroWithoutOracleIsAUsageError) {
  const test::CommandOutcome run = test::run_gridscope(
      "render builtin:pyramid --size 8x8 --accel zero --out " + quoted(temp_path("no.png")));
  EXPECT_EQ(run.status, 2) << run.err;
}

}  // namespace
}  // namespace gs
