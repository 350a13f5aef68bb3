// The progressive renderer, checked against answers computed here another way: images from
// render_image on a separately built structure, walks recorded on a separately built and
// sampled Grid1D, overlay sizes counted voxel by voxel.
#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <limits>
#include <thread>

#include "core/accel/grid1d/grid1d.h"
#include "core/render/camera_control.h"
#include "core/render/overlay.h"
#include "core/render/progressive.h"
#include "core/render/render.h"
#include "core/trace/sampling.h"

namespace gs {
namespace {

constexpr int kW = 64, kH = 48;
// Generous: the suite also runs under ThreadSanitizer on 2 shared cores.
constexpr auto kTimeout = std::chrono::seconds(300);

std::shared_ptr<const Scene> pyramid() {
  static const std::shared_ptr<const Scene> scene =
      std::make_shared<const Scene>(load_scene("builtin:pyramid"));
  return scene;
}

Camera first_camera() { return frame_box(pyramid()->bounds(), float(kW) / float(kH)); }
Camera second_camera() {
  return orbit(dolly(first_camera(), 0.3f), first_camera().target, 0.6f, -0.2f);
}

ViewSetup setup_for(const Camera& camera, int max_spp, int width = kW, int height = kH) {
  ViewSetup setup;
  setup.scene = pyramid();
  setup.camera = camera;
  setup.width = width;
  setup.height = height;
  setup.threads = 2;
  setup.max_spp = max_spp;
  return setup;
}

// A kW x kH image with spp samples per pixel on `threads` threads.
RenderSettings settings(int spp, int threads = 2) {
  RenderSettings settings;
  settings.width = kW, settings.height = kH, settings.spp = spp, settings.threads = threads;
  return settings;
}

// render_image on its own Grid1D, built and sampled as `render` does.
RenderOutcome reference(const Camera& camera, int spp, const Scene& scene = *pyramid(),
                        const AccelParams& params = {}) {
  Grid1D grid{params};
  grid.build(scene);
  sample_image(scene, grid, camera, settings(1));
  return render_image(scene, grid, camera, settings(spp));
}

// Takes every frame it can until one of generation `generation` satisfies `done` (returned
// last); every frame taken is returned in order.
std::vector<ProgressiveFrame> collect(ProgressiveRenderer& renderer, uint64_t generation,
                                      const std::function<bool(const ProgressiveFrame&)>& done) {
  std::vector<ProgressiveFrame> frames;
  uint64_t have_generation = 0;
  int have_pass = 0;
  const auto deadline = std::chrono::steady_clock::now() + kTimeout;
  while (std::chrono::steady_clock::now() < deadline) {
    std::shared_ptr<const ProgressiveFrame> frame = renderer.take_frame(have_generation, have_pass);
    if (!frame) {
      std::this_thread::yield();
      continue;
    }
    have_generation = frame->generation;
    have_pass = frame->pass;
    frames.push_back(*frame);
    if (frames.back().generation == generation && done(frames.back())) return frames;
  }
  ADD_FAILURE() << "no finished frame of generation " << generation << " in time";
  return frames;
}

// The first frame taken of that generation at `pass` or later.
ProgressiveFrame frame_at(ProgressiveRenderer& renderer, uint64_t generation, int pass) {
  std::vector<ProgressiveFrame> frames =
      collect(renderer, generation, [&](const ProgressiveFrame& f) { return f.pass >= pass; });
  if (frames.empty()) return {};
  return frames.back();
}

// Passes of one generation strictly in order, each with its samples per pixel.
void expect_in_order(const std::vector<ProgressiveFrame>& frames, uint64_t generation) {
  int last = 0;
  for (const ProgressiveFrame& f : frames) {
    if (f.generation != generation) continue;
    EXPECT_TRUE(f.error.empty()) << f.error;
    EXPECT_GT(f.pass, last);
    last = f.pass;
    EXPECT_EQ(f.spp, f.pass == 1 ? 0 : f.pass - 1) << "pass " << f.pass;
    EXPECT_EQ(f.width, kW);
    EXPECT_EQ(f.height, kH);
    EXPECT_EQ(f.image.rgba.size(), size_t(kW * kH * 4));
    EXPECT_EQ(f.pixels.size(), size_t(kW * kH));
    EXPECT_GT(f.rays, 0u);
    ASSERT_TRUE(f.structure.nodes.has_value());
    EXPECT_GT(*f.structure.nodes, 1u);
  }
}

void expect_same_image(const ProgressiveFrame& frame, const RenderOutcome& expected) {
  ASSERT_EQ(frame.image.width, expected.image.width);
  ASSERT_EQ(frame.image.height, expected.image.height);
  EXPECT_EQ(frame.image.rgba, expected.image.rgba);
  ASSERT_EQ(frame.pixels.size(), expected.pixels.size());
  for (size_t i = 0; i < frame.pixels.size(); ++i)
    ASSERT_EQ(frame.pixels[i].depth, expected.pixels[i].depth) << "pixel " << i;
}

TEST(Progressive, PassesComeCoarseThenFullThenAccumulating) {
  ProgressiveRenderer renderer;
  EXPECT_EQ(renderer.take_frame(0, 0), nullptr);
  renderer.restart(setup_for(first_camera(), 4));
  const std::vector<ProgressiveFrame> frames =
      collect(renderer, 1, [](const ProgressiveFrame& f) { return f.pass >= 5; });
  ASSERT_FALSE(frames.empty());
  expect_in_order(frames, 1);
  EXPECT_EQ(frames.back().spp, 4);
  EXPECT_EQ(renderer.take_frame(1, 5), nullptr);  // nothing newer than the last pass
  const auto deadline = std::chrono::steady_clock::now() + kTimeout;
  while (renderer.busy() && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  EXPECT_FALSE(renderer.busy());
  // Frames that were replaced before they were taken are missed, so restart (the structure
  // is kept, passes are quick) until the coarse pass has been seen.
  const RenderOutcome centres = reference(first_camera(), 1);
  bool seen_coarse = false;
  for (uint64_t generation = 2; generation < 60 && !seen_coarse; ++generation) {
    renderer.restart(setup_for(first_camera(), 2));
    const std::vector<ProgressiveFrame> again =
        collect(renderer, generation, [](const ProgressiveFrame& f) { return f.pass >= 3; });
    expect_in_order(again, generation);
    for (const ProgressiveFrame& f : again) {
      if (f.generation != generation || f.pass != 1) continue;
      seen_coarse = true;
      // Every 8x8 block is the colour, depth and cost of its centre pixel's ray, which is
      // render_image's pixel there.
      for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
          const size_t centre = size_t((y / 8 * 8 + 4) * kW + x / 8 * 8 + 4);
          const size_t i = size_t(y * kW + x);
          for (int k = 0; k < 4; ++k)
            ASSERT_EQ(f.image.rgba[4 * i + k], centres.image.rgba[4 * centre + k]) << x << "," << y;
          ASSERT_EQ(f.pixels[i].depth, centres.pixels[centre].depth) << x << "," << y;
          ASSERT_EQ(f.pixels[i].steps, f.pixels[centre].steps);
          ASSERT_EQ(f.pixels[i].tests, f.pixels[centre].tests);
        }
    }
  }
  EXPECT_TRUE(seen_coarse) << "the coarse pass was never taken";
}

TEST(Progressive, FullAndAccumulatedPassesEqualRenderImage) {
  ProgressiveRenderer renderer;
  renderer.restart(setup_for(first_camera(), 1));
  expect_same_image(frame_at(renderer, 1, 2), reference(first_camera(), 1));
  // Pass N + 1 holds N samples: render_image's for spp N.
  renderer.restart(setup_for(first_camera(), 2));
  const ProgressiveFrame two = frame_at(renderer, 2, 3);
  EXPECT_EQ(two.spp, 2);
  expect_same_image(two, reference(first_camera(), 2));
  renderer.restart(setup_for(first_camera(), 3));
  const ProgressiveFrame three = frame_at(renderer, 3, 4);
  EXPECT_EQ(three.spp, 3);
  expect_same_image(three, reference(first_camera(), 3));
  // Costs are summed over the samples: each pixel traced at least 3 primary rays' steps.
  uint64_t steps = 0;
  for (const PixelRecord& r : three.pixels) steps += r.steps;
  uint64_t steps_one = 0;
  for (const PixelRecord& r : reference(first_camera(), 1).pixels) steps_one += r.steps;
  EXPECT_GT(steps, 2 * steps_one);
}

// Later passes write into the storage of frames nobody holds any more, never into a frame
// still held: the one kept here stays as it was through a restart and eight more passes.
TEST(Progressive, AHeldFrameIsNotWrittenByLaterPasses) {
  ProgressiveRenderer renderer;
  renderer.restart(setup_for(first_camera(), 1));
  std::shared_ptr<const ProgressiveFrame> held;
  const auto deadline = std::chrono::steady_clock::now() + kTimeout;
  while (!held && std::chrono::steady_clock::now() < deadline) {
    held = renderer.take_frame(1, 1);
    std::this_thread::yield();
  }
  ASSERT_NE(held, nullptr);
  const ProgressiveFrame copy = *held;
  renderer.restart(setup_for(second_camera(), 8));
  const ProgressiveFrame last = frame_at(renderer, 2, 9);
  EXPECT_EQ(last.spp, 8);
  expect_same_image(last, reference(second_camera(), 8));
  EXPECT_EQ(held->image.rgba, copy.image.rgba);
  ASSERT_EQ(held->pixels.size(), copy.pixels.size());
  for (size_t i = 0; i < copy.pixels.size(); ++i) {
    ASSERT_EQ(held->pixels[i].depth, copy.pixels[i].depth) << "pixel " << i;
    ASSERT_EQ(held->pixels[i].steps, copy.pixels[i].steps) << "pixel " << i;
  }
  expect_same_image(*held, reference(first_camera(), 1));
}

TEST(Progressive, RestartWithANewCameraRendersTheNewView) {
  ProgressiveRenderer renderer;
  renderer.restart(setup_for(first_camera(), 1));
  const ProgressiveFrame first = frame_at(renderer, 1, 2);
  EXPECT_EQ(first.generation, 1u);
  renderer.restart(setup_for(second_camera(), 1));
  const ProgressiveFrame second = frame_at(renderer, 2, 2);
  EXPECT_EQ(second.generation, 2u);
  const RenderOutcome expected = reference(second_camera(), 1);
  EXPECT_NE(expected.image.rgba, reference(first_camera(), 1).image.rgba);
  expect_same_image(second, expected);
  // The structure was kept and grown, not rebuilt: never fewer nodes than before.
  ASSERT_TRUE(first.structure.nodes && second.structure.nodes);
  EXPECT_GE(*second.structure.nodes, *first.structure.nodes);
  // A restart in the middle of accumulation: the next generation still comes out right.
  renderer.restart(setup_for(first_camera(), 256));
  renderer.restart(setup_for(second_camera(), 1));
  expect_same_image(frame_at(renderer, 4, 2), expected);
}

TEST(Progressive, FailuresAreReportedInTheFrame) {
  ProgressiveRenderer renderer;
  ViewSetup bad = setup_for(first_camera(), 2);
  bad.accel = "no-such-structure";
  renderer.restart(bad);
  const ProgressiveFrame failed =
      frame_at(renderer, 1, 1);  // an error frame is pass 1 when nothing came before
  EXPECT_NE(failed.error.find("no-such-structure"), std::string::npos) << failed.error;
  EXPECT_FALSE(renderer.record_walk(10, 10).has_value());
  EXPECT_FALSE(renderer.busy());
  // An image size out of range.
  ViewSetup huge = setup_for(first_camera(), 2, kMaxImageSide + 1, 4);
  renderer.restart(huge);
  const ProgressiveFrame too_big = frame_at(renderer, 2, 1);
  EXPECT_FALSE(too_big.error.empty());
  // And a good setup afterwards works.
  renderer.restart(setup_for(first_camera(), 1));
  const ProgressiveFrame good = frame_at(renderer, 3, 2);
  EXPECT_TRUE(good.error.empty()) << good.error;
  expect_same_image(good, reference(first_camera(), 1));
}

void expect_same_walk(const Walk& got, const Walk& expected) {
  EXPECT_EQ(got.hit.id, expected.hit.id);
  EXPECT_EQ(got.hit.t, expected.hit.t);
  EXPECT_EQ(got.hit.u, expected.hit.u);
  EXPECT_EQ(got.hit.v, expected.hit.v);
  ASSERT_EQ(got.cells.size(), expected.cells.size());
  // Voxel ids depend on the order voxels were built in; boxes, depths and work do not.
  for (size_t k = 0; k < got.cells.size(); ++k) {
    const WalkCell &a = got.cells[k], &b = expected.cells[k];
    EXPECT_EQ(a.depth, b.depth) << "cell " << k;
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_EQ(a.lo[axis], b.lo[axis]) << "cell " << k;
      EXPECT_EQ(a.hi[axis], b.hi[axis]) << "cell " << k;
    }
    EXPECT_EQ(a.t_enter, b.t_enter) << "cell " << k;
    EXPECT_EQ(a.entered_axis, b.entered_axis) << "cell " << k;
    EXPECT_EQ(a.tests, b.tests) << "cell " << k;
    EXPECT_EQ(a.hit, b.hit) << "cell " << k;
  }
}

TEST(Progressive, RecordWalkIsTheWalkOfTheImagesStructure) {
  const Camera camera = first_camera();
  Grid1D grid{AccelParams{}};
  const std::shared_ptr<const Scene> scene = pyramid();
  grid.build(*scene);
  sample_image(*scene, grid, camera, settings(1, 1));
  const std::unique_ptr<ThreadContext> context = grid.make_context();

  ProgressiveRenderer renderer;
  EXPECT_FALSE(renderer.record_walk(1, 1).has_value());  // no view yet
  renderer.restart(setup_for(camera, 64));
  int hits = 0;
  // Recorded while the passes render (the first waits for the structure).
  std::vector<std::pair<int, int>> pixels;
  for (int y = 0; y < kH; y += 5)
    for (int x = 1; x < kW; x += 6) pixels.emplace_back(x, y);
  for (const auto& [x, y] : pixels) {
    const std::optional<Walk> got = renderer.record_walk(x, y);
    ASSERT_TRUE(got.has_value()) << x << "," << y;
    const std::optional<Walk> expected =
        grid.record_walk(camera.primary_ray(x, y, kW, kH), *context);
    ASSERT_TRUE(expected.has_value());
    EXPECT_EQ(got->ray.origin, expected->ray.origin);
    EXPECT_EQ(got->ray.dir, expected->ray.dir);
    expect_same_walk(*got, *expected);
    if (got->hit.found()) ++hits;
  }
  EXPECT_GE(hits, 10);
  EXPECT_LT(hits, int(pixels.size()));
  EXPECT_FALSE(renderer.record_walk(kW, 0).has_value());  // outside the image
  EXPECT_FALSE(renderer.record_walk(0, -1).has_value());

  // Brute force has no cells to walk.
  ViewSetup brute = setup_for(camera, 1);
  brute.accel = "brute";
  renderer.restart(brute);
  EXPECT_FALSE(renderer.record_walk(32, 24).has_value());
  const ProgressiveFrame frame = frame_at(renderer, 2, 2);
  EXPECT_TRUE(frame.error.empty()) << frame.error;
  expect_same_image(frame, reference(camera, 1));
}

TEST(Progressive, DestroyingMidPassOrMidBuildReturns) {
  {
    ProgressiveRenderer renderer;
    renderer.restart(setup_for(first_camera(), 256, 320, 240));
    frame_at(renderer, 1, 1);
    EXPECT_TRUE(renderer.busy());
  }  // destroyed while accumulating
  {
    ProgressiveRenderer renderer;
    renderer.restart(setup_for(first_camera(), 256, 320, 240));
  }  // destroyed while building
  {
    ProgressiveRenderer renderer;  // never started
  }
  SUCCEED();
}

TEST(Progressive, StructureVisitsPauseTheWorkers) {
  ProgressiveRenderer renderer;
  int visits = 0;
  // Nothing to visit before any setup.
  renderer.with_structure_paused([&](const Accelerator&) { ++visits; });
  EXPECT_EQ(visits, 0);
  renderer.restart(setup_for(first_camera(), kMaxSpp));  // renders until destroyed
  const ProgressiveFrame before = frame_at(renderer, 1, 2);
  auto visit = [&](const Accelerator& accel) {
    ++visits;
    const Grid1D* grid = accel.grid1d();
    ASSERT_NE(grid, nullptr);
    // No worker builds while we look: the walls counted voxel by voxel are the lines drawn.
    size_t expected = 12, splits = 0;
    for (uint32_t id = 0; id < grid->voxel_count(); ++id)
      if (grid->voxel(id).status.load(std::memory_order_acquire) == Grid1D::kSplit)
        expected += 4 * (grid->voxel(id).granularity - 1), ++splits;
    EXPECT_GT(splits, 0u);
    const LineSet lines = cell_lines(*grid, CellColoring::depth,
                                     {.max_segments = std::numeric_limits<size_t>::max()});
    EXPECT_EQ(lines.vertices.size(), 2 * expected);
  };
  renderer.with_structure_paused(visit);
  EXPECT_EQ(visits, 1);
  // Rendering goes on after the visit, and visits can come while it does.
  const ProgressiveFrame later = frame_at(renderer, 1, before.pass + 3);  // three passes later
  EXPECT_GT(later.spp, before.spp);
  for (int k = 0; k < 5; ++k) renderer.with_structure_paused(visit);
  EXPECT_EQ(visits, 6);
  const ProgressiveFrame after = frame_at(renderer, 1, later.pass + 2);
  EXPECT_GT(after.spp, later.spp);
  EXPECT_TRUE(renderer.busy());
}

TEST(Progressive, ZeroSizeRendersNothingAndRestoringRendersAgain) {
  ProgressiveRenderer renderer;
  renderer.restart(setup_for(first_camera(), 1));
  frame_at(renderer, 1, 2);
  // A minimised window: generation 2 has nothing to render, so no frame and no walk.
  renderer.restart(setup_for(first_camera(), 1, 0, 0));
  const auto deadline = std::chrono::steady_clock::now() + kTimeout;
  while (renderer.busy() && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  EXPECT_FALSE(renderer.busy());
  EXPECT_TRUE(renderer.structure_ready());
  EXPECT_EQ(renderer.take_frame(2, 0), nullptr);
  EXPECT_FALSE(renderer.record_walk(0, 0).has_value());
  // Restored: the same structure, the same image.
  renderer.restart(setup_for(first_camera(), 1));
  expect_same_image(frame_at(renderer, 3, 2), reference(first_camera(), 1));
}

// Parameters changed while a structure is being built (the viewer's Apply during a build):
// the old structure is dropped without a race, and the frames are the new structure's. The
// new one has a memory budget so small that some voxels stay leaves, which the frame shows.
TEST(Progressive, NewParametersDuringTheBuildTakeEffect) {
  const auto lumpy = std::make_shared<const Scene>(load_scene("builtin:lumpy"));
  const Camera camera = frame_box(lumpy->bounds(), float(kW) / float(kH));
  ViewSetup roomy = setup_for(camera, 1);
  roomy.scene = lumpy;
  ViewSetup tight = roomy;
  tight.params.memory_budget = uint64_t{300} << 10;
  const RenderOutcome expected = reference(camera, 1, *lumpy, tight.params);
  ProgressiveRenderer renderer;
  uint64_t generation = 0;
  // The change comes at once, and after the build has had some time to start.
  for (const int delay_ms : {0, 1, 10, 50}) {
    renderer.restart(roomy);
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
    renderer.with_structure_paused([](const Accelerator&) {});
    renderer.restart(tight);
    generation += 2;
    const std::optional<Walk> walk = renderer.record_walk(kW / 2, kH / 2);
    EXPECT_TRUE(walk.has_value());
    const ProgressiveFrame frame = frame_at(renderer, generation, 2);
    EXPECT_TRUE(frame.error.empty()) << frame.error;
    EXPECT_GT(frame.structure.voxels_over_budget, 0u) << "delay " << delay_ms;
    expect_same_image(frame, expected);
  }
}

// A Grid1D's build figures counted voxel by voxel: examined voxels are those with triangles
// whose status left kUnexamined (empty cells are leaves from birth, never examined); the
// triangles sorted are those of the voxels cut.
struct VoxelCount {
  uint64_t examined = 0, cut = 0, triangles_of_cut = 0;
};

VoxelCount count_voxels(const Grid1D& grid) {
  VoxelCount count;
  for (uint32_t id = 0; id < grid.voxel_count(); ++id) {
    const Grid1D::Voxel& voxel = grid.voxel(id);
    const uint8_t status = voxel.status.load();
    count.examined += voxel.tri_count > 0 && status != Grid1D::kUnexamined;
    if (status == Grid1D::kSplit) {
      ++count.cut;
      count.triangles_of_cut += voxel.tri_count;
    }
  }
  return count;
}

void expect_figures_match(const BuildFigures& figures, const Grid1D& grid) {
  const VoxelCount count = count_voxels(grid);
  EXPECT_GT(count.cut, 0u);  // the scene is cut, so the comparisons below can fail
  EXPECT_EQ(figures.voxels_built, count.examined);
  EXPECT_EQ(figures.voxels_subdivided, count.cut);
  EXPECT_EQ(figures.triangles_sorted, count.triangles_of_cut);
  EXPECT_EQ(grid.stats().voxels_subdivided, count.cut);
}

TEST(BuildProgress, SamplingFractionIsTheShareOfSampleRaysTraced) {
  BuildFigures figures;
  EXPECT_FALSE(figures.sampling_fraction().has_value());  // no sampling pass begun
  figures.sample_rays = 200;
  figures.sample_rays_traced = 50;
  EXPECT_EQ(figures.sampling_fraction(), 0.25);
  figures.sample_rays_traced = 200;
  EXPECT_EQ(figures.sampling_fraction(), 1.0);
}

TEST(BuildProgress, EagerGrid1DBuildCountsEveryVoxelItBuilt) {
  const Scene scene = load_scene("builtin:lumpy");
  Grid1D grid{AccelParams{}};
  grid.build(scene);
  ASSERT_NE(grid.build_progress(), nullptr);
  EXPECT_EQ(grid.build_progress()->figures().voxels_built, 0u);  // only the root, unexamined
  grid.build_all();
  expect_figures_match(grid.build_progress()->figures(), grid);
  // Eager: every voxel with triangles was examined.
  uint64_t with_triangles = 0;
  for (uint32_t id = 0; id < grid.voxel_count(); ++id)
    with_triangles += grid.voxel(id).tri_count > 0;
  EXPECT_EQ(grid.build_progress()->figures().voxels_built, with_triangles);
}

TEST(BuildProgress, LazyGrid1DCountsWhatTheRaysBuiltAndTheSamplingPass) {
  const Scene scene = load_scene("builtin:lumpy");
  const Camera camera = frame_box(scene.bounds(), float(kW) / float(kH));
  Grid1D grid{AccelParams{}};
  grid.build(scene);
  sample_image(scene, grid, camera, settings(1));
  const BuildFigures sampled = grid.build_progress()->figures();
  // One sample ray per 8x8 block of the image.
  EXPECT_EQ(sampled.sample_rays, uint64_t((kW + 7) / 8 * ((kH + 7) / 8)));
  EXPECT_EQ(sampled.sample_rays_traced, sampled.sample_rays);
  EXPECT_GT(sampled.scout_voxels_built, 0u);
  EXPECT_EQ(sampled.voxels_built, 0u);  // the scout's voxels are not the structure's
  render_image(scene, grid, camera, settings(1, 2));
  expect_figures_match(grid.build_progress()->figures(), grid);
}

TEST(BuildProgress, TheScoutsVoxelsAreThoseItsRaysBuildInAStructureWithoutSample) {
  const Scene scene = load_scene("builtin:lumpy");
  const Camera camera = frame_box(scene.bounds(), float(kW) / float(kH));
  std::vector<Ray> rays;
  for (const size_t pixel : image_sample_pixels(kW, kH))
    rays.push_back(camera.primary_ray(int(pixel % kW), int(pixel / kW), kW, kH));
  Grid1D grid{AccelParams{}};
  grid.build(scene);
  grid.sample(rays, 64.0);
  // The scout is a Grid1D without sample that traces the sample's rays in order.
  Grid1D unsampled{AccelParams{}};
  unsampled.build(scene);
  const std::unique_ptr<ThreadContext> context = unsampled.make_context();
  for (const Ray& ray : rays) unsampled.intersect(ray, *context);
  EXPECT_EQ(grid.build_progress()->figures().scout_voxels_built, count_voxels(unsampled).examined);
}

TEST(BuildProgress, TheRendererReportsTheBuildOrThatTheStructureCannot) {
  ProgressiveRenderer renderer;
  EXPECT_FALSE(renderer.build_status().building);  // nothing built yet
  ViewSetup setup = setup_for(first_camera(), 1);
  setup.threads = 1;  // one thread: the voxels the rays build do not depend on timing
  setup.packets = false;
  renderer.restart(setup);
  const ProgressiveFrame grid_frame = frame_at(renderer, 1, 2);
  ASSERT_TRUE(grid_frame.build.has_value());
  // The full-resolution pass's rays (the coarse pass's are among them) build what
  // render_image's build on a separately built and sampled Grid1D.
  Grid1D separate{AccelParams{}};
  separate.build(*pyramid());
  sample_image(*pyramid(), separate, first_camera(), settings(1));
  RenderSettings one_by_one = settings(1, 1);
  one_by_one.packets = false;
  render_image(*pyramid(), separate, first_camera(), one_by_one);
  expect_figures_match(*grid_frame.build, separate);
  EXPECT_EQ(grid_frame.build->sample_rays, uint64_t(kW / 8 * (kH / 8)));
  const BuildStatus grid_status = renderer.build_status();
  EXPECT_EQ(grid_status.structure, "grid1d");
  EXPECT_FALSE(grid_status.building);
  EXPECT_GT(grid_status.seconds, 0.0);
  ASSERT_TRUE(grid_status.figures.has_value());
  // The build ended with the full-resolution pass (the last, with max_spp 1): its figures
  // are that frame's.
  EXPECT_EQ(grid_status.figures->voxels_built, grid_frame.build->voxels_built);
  EXPECT_EQ(grid_status.figures->triangles_sorted, grid_frame.build->triangles_sorted);
  EXPECT_EQ(grid_status.figures->sample_rays_traced, grid_frame.build->sample_rays);

  setup.accel = "bvh";
  renderer.restart(setup);
  const ProgressiveFrame bvh_frame = frame_at(renderer, 2, 2);
  EXPECT_FALSE(bvh_frame.build.has_value());
  const BuildStatus bvh_status = renderer.build_status();
  EXPECT_EQ(bvh_status.structure, "bvh");
  EXPECT_FALSE(bvh_status.building);
  EXPECT_FALSE(bvh_status.figures.has_value());
}

TEST(SceneLoader, ReportsAFailedLoadAndKeepsTheNewestRequest) {
  SceneLoader loader;
  EXPECT_FALSE(loader.pending().has_value());
  EXPECT_FALSE(loader.take().has_value());
  const auto wait_for_result = [&loader] {
    const auto deadline = std::chrono::steady_clock::now() + kTimeout;
    while (std::chrono::steady_clock::now() < deadline) {
      if (std::optional<SceneLoader::Result> result = loader.take()) return result;
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    ADD_FAILURE() << "no load finished in time";
    return std::optional<SceneLoader::Result>();
  };

  loader.load("/nonexistent/scene.obj");
  EXPECT_EQ(loader.pending(), "/nonexistent/scene.obj");
  const std::optional<SceneLoader::Result> failed = wait_for_result();
  ASSERT_TRUE(failed.has_value());
  EXPECT_EQ(failed->scene, nullptr);
  EXPECT_NE(failed->error.find("/nonexistent/scene.obj"), std::string::npos) << failed->error;
  EXPECT_EQ(failed->error.find('\n'), std::string::npos);
  EXPECT_FALSE(loader.pending().has_value());
  EXPECT_FALSE(loader.take().has_value());  // handed out once

  // A second request supersedes the first: only the newest one's result comes out.
  loader.load("builtin:lumpy");
  loader.load("builtin:pyramid");
  EXPECT_EQ(loader.pending(), "builtin:pyramid");
  const std::optional<SceneLoader::Result> loaded = wait_for_result();
  ASSERT_TRUE(loaded.has_value());
  EXPECT_EQ(loaded->spec, "builtin:pyramid");
  EXPECT_TRUE(loaded->error.empty()) << loaded->error;
  ASSERT_NE(loaded->scene, nullptr);
  EXPECT_EQ(loaded->scene->triangle_count(), pyramid()->triangle_count());
  EXPECT_FALSE(loader.take().has_value());

  loader.load("builtin:sphereflake");  // destroyed while loading: waits, then returns
}

}  // namespace
}  // namespace gs
