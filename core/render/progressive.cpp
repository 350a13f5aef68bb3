#include "core/render/progressive.h"

#include <algorithm>
#include <exception>
#include <glm/vec3.hpp>
#include <new>
#include <nlohmann/json.hpp>

#include "core/base/error.h"
#include "core/base/timing.h"

namespace gs {

namespace {

constexpr int kCoarseBlock = 8;  // the coarse pass: one ray per 8x8 block

// What a structure is a function of: when a restart keeps these, it keeps the structure
// (a camera or size change only lets the lazy structure grow). The scene is held so that it
// outlives the structure built over it.
struct StructureKey {
  std::shared_ptr<const Scene> scene;
  std::string accel;
  nlohmann::json params;

  explicit StructureKey(const ViewSetup& setup)
      : scene(setup.scene), accel(setup.accel), params(setup.params.to_json()) {}
  bool operator==(const StructureKey& other) const {
    return scene == other.scene && accel == other.accel && params == other.params;
  }
};

// The view's image with spp samples per pixel; render's defaults otherwise.
RenderSettings image_settings(const ViewSetup& setup, int spp) {
  RenderSettings settings;
  settings.width = setup.width, settings.height = setup.height, settings.spp = spp;
  settings.threads = setup.threads, settings.packets = setup.packets;
  return settings;
}

uint32_t saturating_add(uint32_t a, uint32_t b) { return a > UINT32_MAX - b ? UINT32_MAX : a + b; }

// Inside a catch block: what the exception says, on one line (the UI and stderr show it).
std::string caught_error_line() {
  std::string message = "unknown error";
  try {
    throw;
  } catch (const std::exception& error) {
    message = error.what();
  } catch (...) {
  }
  std::replace(message.begin(), message.end(), '\n', ' ');
  return message.empty() ? "unknown error" : message;
}

// The images and records of frames their last holder dropped, for later passes to write
// into: a fresh 1274x794 pass's 20 MB cost 12 ms of page faults on the controller's thread
// before the pass's first ray. Shared with the frames' deleters (on whichever thread drops
// a frame last, perhaps after the renderer is gone).
class StoragePool {
 public:
  // Storage for an image of `pixels` pixels: a kept set of that size, or none (a set of
  // another size, from before a resize, is dropped).
  PassStorage take(size_t pixels) {
    std::lock_guard lock(mutex_);
    while (!kept_.empty()) {
      PassStorage storage = std::move(kept_.back());
      kept_.pop_back();
      if (storage.pixels.size() == pixels) return storage;
    }
    return {};
  }
  void give_back(PassStorage storage) {
    if (storage.pixels.empty() || storage.rgba.size() != 4 * storage.pixels.size()) return;
    std::lock_guard lock(mutex_);
    if (kept_.size() < kKept) kept_.push_back(std::move(storage));
  }

 private:
  // A pass takes one set while the UI shows the previous frame: two cover a restart's
  // coarse and full passes; more would only hold memory.
  static constexpr size_t kKept = 2;
  std::mutex mutex_;
  std::vector<PassStorage> kept_;
};

// A new frame whose image and records go back to `pool` when its last holder drops it.
std::shared_ptr<ProgressiveFrame> make_frame(const std::shared_ptr<StoragePool>& pool) {
  return std::shared_ptr<ProgressiveFrame>(new ProgressiveFrame, [pool](ProgressiveFrame* frame) {
    pool->give_back({std::move(frame->image.rgba), std::move(frame->pixels)});
    delete frame;
  });
}

}  // namespace

struct ProgressiveRenderer::State {
  explicit State(std::function<void()> ready) : frame_ready(std::move(ready)) {}
  const std::function<void()> frame_ready;  // called after a frame is published

  // --- Guarded by `mutex`.
  std::mutex mutex;
  std::condition_variable work_cv;       // the controller: a new generation, or stop
  std::condition_variable structure_cv;  // record_walk: the structure settled, or stop
  bool stop = false;
  uint64_t generation = 0;
  ViewSetup setup;
  Clock::time_point restarted;  // when `generation` began: frames count their time from it
  // Whether the current generation's structure is known (built and sampled, or failed, or
  // none for no scene); `structure` is it then (null: none).
  bool settled = true;
  std::shared_ptr<Accelerator> structure;
  // The controller's built and sampled structure and what it was built from: a restart with
  // the same key settles at once on it.
  std::shared_ptr<Accelerator> ready;
  std::optional<StructureKey> ready_key;
  std::shared_ptr<const ProgressiveFrame> frame;  // the newest finished pass (immutable)
  // The newest structure built (build_status reads its progress) after the scene it was
  // built over (which must outlive it), when its build began and, once over, how long it
  // took and its figures then.
  std::shared_ptr<const Scene> last_build_scene;
  std::shared_ptr<const Accelerator> last_build;
  Clock::time_point build_started;
  std::optional<double> build_seconds;
  std::optional<BuildFigures> build_figures;

  // --- Read by the rendering threads without the mutex.
  std::atomic<uint64_t> live_generation{0};  // rows of any other generation are skipped
  std::atomic<bool> stopping{false};
  std::atomic<bool> busy{false};

  // --- The tracing gate: rows and record_walk trace "shared", with_structure_paused visits
  // "exclusive". A pending visit holds new rows back, so visits cannot starve.
  std::mutex gate_mutex;
  std::condition_variable gate_cv;
  int tracing = 0;         // rows and walks in flight
  int pause_requests = 0;  // visits waiting or running
  bool visiting = false;

  // --- The controller's own (only its thread touches these).
  double lazy_seconds = 0.0;  // lazy building in the passes over `ready`, for its stats
  // The accumulating passes' display-space sums and summed records, kept from one
  // generation to the next for their storage.
  std::vector<glm::vec3> sums;
  std::vector<PixelRecord> records;
  const std::shared_ptr<StoragePool> storage_pool = std::make_shared<StoragePool>();

  std::thread controller;

  void enter_tracing() {
    std::unique_lock lock(gate_mutex);
    gate_cv.wait(lock, [&] { return pause_requests == 0; });
    ++tracing;
  }
  void leave_tracing() {
    std::lock_guard lock(gate_mutex);
    if (--tracing == 0 && pause_requests > 0) gate_cv.notify_all();
  }
  void enter_visit() {
    std::unique_lock lock(gate_mutex);
    ++pause_requests;
    gate_cv.wait(lock, [&] { return tracing == 0 && !visiting; });
    visiting = true;
  }
  void leave_visit() {
    std::lock_guard lock(gate_mutex);
    visiting = false;
    --pause_requests;
    gate_cv.notify_all();
  }

  // RAII holders of the gate.
  class Tracing {
   public:
    explicit Tracing(State& state) : state_(state) { state_.enter_tracing(); }
    ~Tracing() { state_.leave_tracing(); }
    Tracing(const Tracing&) = delete;
    Tracing& operator=(const Tracing&) = delete;

   private:
    State& state_;
  };
  class Visiting {
   public:
    explicit Visiting(State& state) : state_(state) { state_.enter_visit(); }
    ~Visiting() { state_.leave_visit(); }
    Visiting(const Visiting&) = delete;
    Visiting& operator=(const Visiting&) = delete;

   private:
    State& state_;
  };

  // Whether the newest setup still asks for a structure made from `key`.
  bool wanted(const StructureKey& key) {
    std::lock_guard lock(mutex);
    return !stop && StructureKey(setup) == key;
  }

  // The build build_status reports on: from begin_build to end_build (the first call ends it).
  void begin_build(std::shared_ptr<const Accelerator> accel, std::shared_ptr<const Scene> scene) {
    std::lock_guard lock(mutex);
    last_build = std::move(accel);  // the old one goes while its scene is still held
    last_build_scene = std::move(scene);
    build_started = Clock::now();
    build_seconds.reset();
    build_figures.reset();
  }
  void end_build() {
    std::lock_guard lock(mutex);
    if (!last_build || build_seconds) return;
    build_seconds = seconds_since(build_started);
    if (const BuildProgress* progress = last_build->build_progress())
      build_figures = progress->figures();
  }

  void controller_loop();
  void run_generation(uint64_t gen, const ViewSetup& setup, Clock::time_point start,
                      std::shared_ptr<Accelerator> accel);
};

void ProgressiveRenderer::State::controller_loop() {
  uint64_t done = 0;
  for (;;) {
    uint64_t gen = 0;
    ViewSetup current;
    Clock::time_point start;
    std::shared_ptr<Accelerator> accel;
    {
      std::unique_lock lock(mutex);
      work_cv.wait(lock, [&] { return stop || generation != done; });
      if (stop) return;
      gen = done = generation;
      current = setup;
      start = restarted;
      if (!current.scene || current.width <= 0 || current.height <= 0) {
        // Nothing to render: no structure, no frames.
        settled = true;
        structure.reset();
        busy = false;
        structure_cv.notify_all();
        continue;
      }
      if (ready && ready_key && *ready_key == StructureKey(current)) {
        accel = ready;
        if (!settled) {
          settled = true;
          structure = ready;
          structure_cv.notify_all();
        }
      } else {
        // Dropped under the lock, so no restart from now on can settle on it.
        ready.reset();
        ready_key.reset();
      }
    }
    run_generation(gen, current, start, std::move(accel));
  }
}

void ProgressiveRenderer::State::run_generation(uint64_t gen, const ViewSetup& setup,
                                                Clock::time_point start,
                                                std::shared_ptr<Accelerator> accel) {
  auto abandoned = [&] {
    return stopping.load(std::memory_order_relaxed) ||
           live_generation.load(std::memory_order_relaxed) != gen;
  };
  int last_pass = 0;
  try {
    const int w = setup.width, h = setup.height;
    const RenderSettings centre = image_settings(setup, 1);
    check_render_settings(centre);
    if (!accel) {
      // A new structure: built and sampled here (not cancellable; the image's sampling pass
      // with spp 1, as `trace --sample-image WxH` does it).
      std::shared_ptr<Accelerator> built = make_accelerator(setup.accel, setup.params);
      begin_build(built, setup.scene);
      built->build(*setup.scene);
      // Parameters changed (or the window closed) during the build: skip the sampling pass
      // of a structure nobody will use. A camera change keeps it: it still fits.
      if (!wanted(StructureKey(setup))) {
        end_build();
        return;
      }
      sample_image(*setup.scene, *built, setup.camera, centre);
      // A structure that reports its progress builds lazily: the first passes' rays go on
      // building it, and its build ends with the first full-resolution pass (publish).
      if (!built->build_progress()) end_build();
      lazy_seconds = 0.0;
      std::lock_guard lock(mutex);
      ready = built;
      ready_key.emplace(setup);
      if (generation != gen) return;  // the next generation may still use it
      settled = true;
      structure = built;
      structure_cv.notify_all();
      accel = std::move(built);
    }

    const RowRunner run_row = [&](const std::function<void()>& row) {
      if (abandoned()) return;
      Tracing hold(*this);
      if (!abandoned()) row();
    };
    uint64_t rays = 0;
    const size_t pixel_count = size_t(w) * size_t(h);
    // Publishes a finished pass; false when the generation was abandoned meanwhile.
    auto publish = [&](int pass, int spp, RenderOutcome& outcome) {
      if (abandoned()) return false;
      lazy_seconds += outcome.counters.lazy_build_seconds;
      rays += outcome.rays;
      std::shared_ptr<ProgressiveFrame> frame = make_frame(storage_pool);
      frame->generation = gen;
      frame->width = w;
      frame->height = h;
      frame->pass = pass;
      frame->spp = spp;
      frame->image = std::move(outcome.image);
      frame->pixels = std::move(outcome.pixels);
      frame->rays_per_second = outcome.seconds > 0.0 ? double(outcome.rays) / outcome.seconds : 0.0;
      frame->rays = rays;
      frame->pass_rays = outcome.rays;
      frame->seconds = seconds_since(start);
      frame->counters = outcome.counters;
      frame->structure = accel->stats();
      frame->structure.build_seconds += lazy_seconds;
      if (const BuildProgress* progress = accel->build_progress())
        frame->build = progress->figures();
      // Ended before the frame is handed out: whoever sees the frame sees the build over.
      if (pass >= 2) end_build();
      {
        std::lock_guard lock(mutex);
        if (generation != gen) return false;
        this->frame = std::move(frame);
        last_pass = pass;
      }
      if (frame_ready) frame_ready();
      return true;
    };

    const Scene& scene = *setup.scene;
    RenderOutcome outcome = render_pass(scene, *accel, setup.camera, centre, kCoarseBlock, 0,
                                        nullptr, run_row, storage_pool->take(pixel_count));
    if (!publish(1, 0, outcome)) return;
    outcome = render_pass(scene, *accel, setup.camera, centre, 1, 0, nullptr, run_row,
                          storage_pool->take(pixel_count));
    if (!publish(2, 1, outcome)) return;

    // Accumulation: the pass with spp N adds render_image's samples for spp N that the
    // image does not have yet (pass 3 takes samples 0 and 1, as render_image jitters every
    // sample for spp > 1 and none for spp 1), so the image equals render_image's for spp N.
    const int max_spp = std::clamp(setup.max_spp, 1, kMaxSpp);
    // (The sums are started afresh by the pass that takes sample 0.)
    sums.resize(pixel_count);
    for (int spp = 2; spp <= max_spp; ++spp) {
      const int first = spp == 2 ? 0 : spp - 1;
      const RenderSettings settings = image_settings(setup, spp);
      outcome = render_pass(scene, *accel, setup.camera, settings, 1, first, &sums, run_row,
                            storage_pool->take(pixel_count));
      if (abandoned()) return;
      // The frame shows the records summed over its samples, in the pass's own storage.
      if (first == 0) {
        records.assign(outcome.pixels.begin(), outcome.pixels.end());
      } else {
        for (size_t i = 0; i < records.size(); ++i) {
          records[i].steps = saturating_add(records[i].steps, outcome.pixels[i].steps);
          records[i].tests = saturating_add(records[i].tests, outcome.pixels[i].tests);
          records[i].built = saturating_add(records[i].built, outcome.pixels[i].built);
        }
        std::copy(records.begin(), records.end(), outcome.pixels.begin());
      }
      if (!publish(spp + 1, spp, outcome)) return;
    }
    std::lock_guard lock(mutex);
    if (generation == gen) busy = false;
  } catch (...) {
    const std::string message = caught_error_line();
    end_build();
    std::lock_guard lock(mutex);
    if (generation != gen) return;
    std::shared_ptr<ProgressiveFrame> frame = make_frame(storage_pool);
    frame->generation = gen;
    frame->width = setup.width;
    frame->height = setup.height;
    frame->pass = last_pass + 1;
    frame->error = message;
    this->frame = std::move(frame);
    if (frame_ready) frame_ready();
    if (!settled) {
      settled = true;
      structure.reset();
      structure_cv.notify_all();
    }
    busy = false;
  }
}

ProgressiveRenderer::ProgressiveRenderer(std::function<void()> frame_ready)
    : state_(std::make_unique<State>(std::move(frame_ready))) {
  state_->controller = std::thread([state = state_.get()] { state->controller_loop(); });
}

ProgressiveRenderer::~ProgressiveRenderer() {
  {
    std::lock_guard lock(state_->mutex);
    state_->stop = true;
    state_->stopping = true;
    state_->work_cv.notify_all();
    state_->structure_cv.notify_all();
  }
  state_->controller.join();
}

void ProgressiveRenderer::restart(const ViewSetup& setup) {
  State& s = *state_;
  std::lock_guard lock(s.mutex);
  s.setup = setup;
  s.restarted = Clock::now();
  s.live_generation = ++s.generation;
  s.busy = true;
  if (s.ready && s.ready_key && *s.ready_key == StructureKey(setup) && setup.width > 0 &&
      setup.height > 0) {
    s.settled = true;
    s.structure = s.ready;
  } else {
    s.settled = false;
    s.structure.reset();
  }
  s.work_cv.notify_all();
  s.structure_cv.notify_all();
}

std::shared_ptr<const ProgressiveFrame> ProgressiveRenderer::take_frame(uint64_t have_generation,
                                                                        int have_pass) {
  std::shared_ptr<const ProgressiveFrame> frame;
  {
    std::lock_guard lock(state_->mutex);
    frame = state_->frame;
  }
  if (!frame || frame->generation < have_generation ||
      (frame->generation == have_generation && frame->pass <= have_pass))
    return nullptr;
  return frame;
}

std::optional<Walk> ProgressiveRenderer::record_walk(int x, int y) {
  State& s = *state_;
  std::shared_ptr<Accelerator> accel;
  Camera camera;
  int w = 0, h = 0;
  {
    std::unique_lock lock(s.mutex);
    s.structure_cv.wait(lock, [&] { return s.stop || s.settled; });
    if (s.stop || !s.structure || !s.setup.scene) return std::nullopt;
    accel = s.structure;
    camera = s.setup.camera;
    w = s.setup.width;
    h = s.setup.height;
  }
  if (x < 0 || y < 0 || x >= w || y >= h) return std::nullopt;
  // With the workers paused between rows: a voxel another thread is cutting would be walked
  // as a leaf (the lazy build never waits), so the walk would depend on timing. Paused, every
  // voxel is either finished or cut by this walk itself, and the walk is the one the
  // structure gives (that of `trace --walk` after the same sampling pass).
  State::Visiting hold(s);
  const std::unique_ptr<ThreadContext> context = accel->make_context();
  return accel->record_walk(camera.primary_ray(x, y, w, h), *context);
}

void ProgressiveRenderer::with_structure_paused(
    const std::function<void(const Accelerator&)>& visit) {
  State& s = *state_;
  std::shared_ptr<Accelerator> accel;
  {
    std::lock_guard lock(s.mutex);
    if (s.settled) accel = s.structure;
  }
  if (!accel) return;
  State::Visiting hold(s);
  visit(*accel);
}

bool ProgressiveRenderer::busy() const { return state_->busy.load(); }

bool ProgressiveRenderer::structure_ready() const {
  std::lock_guard lock(state_->mutex);
  return state_->settled;
}

BuildStatus ProgressiveRenderer::build_status() const {
  State& s = *state_;
  BuildStatus status;
  // Held in this order so that, should they be the last holders, the structure goes first.
  std::shared_ptr<const Scene> scene;
  std::shared_ptr<const Accelerator> accel;
  {
    std::lock_guard lock(s.mutex);
    if (!s.last_build) return status;
    scene = s.last_build_scene;
    accel = s.last_build;
    status.structure = accel->name();
    status.building = !s.build_seconds;
    status.seconds = s.build_seconds ? *s.build_seconds : seconds_since(s.build_started);
    if (!status.building) {
      status.figures = s.build_figures;
      return status;
    }
  }
  // Outside the lock: the figures are atomics the building threads update without it.
  if (const BuildProgress* progress = accel->build_progress()) status.figures = progress->figures();
  return status;
}

struct SceneLoader::State {
  // Guarded by `mutex`. Requests are numbered; `taken` is the newest one handed out.
  mutable std::mutex mutex;
  std::condition_variable cv;  // the worker: a new request, or stop
  bool stop = false;
  uint64_t requested = 0, taken = 0;
  std::string spec;              // of request `requested`
  std::optional<Result> result;  // of request `requested`, when done
  std::thread worker;

  void worker_loop();
};

void SceneLoader::State::worker_loop() {
  uint64_t done = 0;
  for (;;) {
    uint64_t request = 0;
    Result loaded;
    {
      std::unique_lock lock(mutex);
      cv.wait(lock, [&] { return stop || requested != done; });
      if (stop) return;
      request = done = requested;
      loaded.spec = spec;
    }
    try {
      loaded.scene = std::make_shared<const Scene>(load_scene(loaded.spec));
    } catch (const InputError&) {
      loaded.error = caught_error_line();  // "FILE: problem" already
    } catch (const std::bad_alloc&) {
      loaded.error = loaded.spec + ": out of memory";
    } catch (...) {
      loaded.error = loaded.spec + ": " + caught_error_line();
    }
    std::lock_guard lock(mutex);
    if (request == requested) result = std::move(loaded);  // else superseded: dropped
  }
}

SceneLoader::SceneLoader() : state_(std::make_unique<State>()) {
  state_->worker = std::thread([state = state_.get()] { state->worker_loop(); });
}

SceneLoader::~SceneLoader() {
  {
    std::lock_guard lock(state_->mutex);
    state_->stop = true;
    state_->cv.notify_all();
  }
  state_->worker.join();
}

void SceneLoader::load(const std::string& spec) {
  std::lock_guard lock(state_->mutex);
  state_->spec = spec;
  ++state_->requested;
  state_->result.reset();
  state_->cv.notify_all();
}

std::optional<SceneLoader::Result> SceneLoader::take() {
  std::lock_guard lock(state_->mutex);
  if (!state_->result) return std::nullopt;
  std::optional<Result> result = std::move(state_->result);
  state_->result.reset();
  state_->taken = state_->requested;
  return result;
}

std::optional<std::string> SceneLoader::pending() const {
  std::lock_guard lock(state_->mutex);
  if (state_->taken == state_->requested) return std::nullopt;
  return state_->spec;
}

}  // namespace gs
