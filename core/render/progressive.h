// The viewer's progressive CPU renderer: on worker threads, never on the UI
// thread, it renders a view in passes: a coarse pass (one ray per 8x8 block, shown as
// blocks), then full resolution at pixel centres (the same image `gridscope render --spp 1`
// gives), then jittered samples accumulated one per pixel per pass (antialiasing, soft
// shadows). Any change of view, scene, structure or parameters restarts it; the UI thread
// only takes finished frames. SceneLoader reads scene files on a worker thread for the same
// reason: the UI never waits for a file.
#pragma once
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/accel/accelerator.h"
#include "core/accel/walk.h"
#include "core/render/render.h"
#include "core/scene/camera.h"
#include "core/scene/scene.h"

namespace gs {

// What to render: a change of any field restarts the passes.
struct ViewSetup {
  std::shared_ptr<const Scene> scene;  // shared with the UI, never modified
  // scene->bounds(), computed once with the scene: the UI draws every frame with it (near
  // and far planes), and a scan of the 871k-triangle dragon takes about 6 ms.
  Box scene_box;
  std::string accel = "grid1d";
  AccelParams params;
  Camera camera;
  int width = 0, height = 0;
  int threads = default_thread_count();
  int max_spp = 256;    // accumulation stops here
  bool packets = true;  // RenderSettings::packets; a change keeps the structure
};

// A snapshot the UI thread can draw. The image is RGBA8 (row-major from the top-left);
// pixels carry depth and per-pixel costs, summed over the samples taken so far.
struct ProgressiveFrame {
  uint64_t generation = 0;  // increments on every restart; frames of an older view are stale
  int width = 0, height = 0;
  int pass = 0;  // 0 none yet, 1 coarse, 2 full resolution, 3+ accumulating
  int spp = 0;   // samples per pixel in the image (0 for the coarse pass)
  Image image;
  std::vector<PixelRecord> pixels;
  double rays_per_second = 0.0;  // of the last finished pass
  uint64_t rays = 0;             // traced since the restart
  uint64_t pass_rays = 0;        // traced by the last finished pass (the counters' rays)
  double seconds = 0.0;          // from the restart to this pass's end (build included)
  TraceCounters counters;        // of the last finished pass (packet figures among them)
  StructureStats structure;      // of the structure the frame was rendered with
  std::string error;             // a failed build or render: what went wrong, one line
  // Its build's figures taken with `structure` (null: the structure reports none).
  std::optional<BuildFigures> build;
};

// The newest structure build as a progress display shows it: what the first image waits
// for. That is the build proper and the image's sampling pass and, for a structure that
// reports its progress (grid1d, which builds lazily), the first passes too, whose rays build
// it: its build ends when the first full-resolution pass is published.
struct BuildStatus {
  std::string structure;  // its name (the setup may already ask for another)
  bool building = false;  // not yet ended
  double seconds = 0.0;   // since it began; its whole length once it has ended
  // As far as the structure can tell (null: it cannot; Accelerator::build_progress): live
  // while building, then as they were when the build ended (later passes add to the
  // structure's own record).
  std::optional<BuildFigures> figures;
};

class ProgressiveRenderer {
 public:
  // `frame_ready`, when given, is called on the renderer's thread after each frame is
  // published (the viewer wakes its event loop with it, instead of polling).
  explicit ProgressiveRenderer(std::function<void()> frame_ready = {});
  ~ProgressiveRenderer();  // stops and joins the workers
  ProgressiveRenderer(const ProgressiveRenderer&) = delete;
  ProgressiveRenderer& operator=(const ProgressiveRenderer&) = delete;

  // Starts over with a new setup (a new structure is built when the scene, structure or
  // parameters changed; a camera or size change keeps the structure). Returns at once.
  void restart(const ViewSetup& setup);
  // The newest finished pass, if one newer than `have_generation`/`have_pass` exists (else
  // null). Shared, not copied: a published frame never changes, and a copy of its image and
  // records (20 MB at 1274x794) cost the viewer fresh pages on every pass.
  std::shared_ptr<const ProgressiveFrame> take_frame(uint64_t have_generation, int have_pass);
  // Records the walk of pixel (x, y)'s ray (pixel centre, no jitter) through the current
  // structure, by the same traversal that renders. Waits for the structure to exist;
  // nothing when the structure has no cells (brute) or there is no scene.
  std::optional<Walk> record_walk(int x, int y);
  // Runs `visit(accel)` on the current structure while no worker traces (for overlays:
  // cell_lines etc. must not run concurrently with lazy building).
  void with_structure_paused(const std::function<void(const Accelerator&)>& visit);
  // True while passes are still being rendered (not yet at max_spp).
  bool busy() const;
  // True when the current setup's structure is known (built and sampled, failed, or none):
  // record_walk then does not wait for a build, only for the rows in flight.
  bool structure_ready() const;
  // The newest build's progress (none begun: not building, no figures). Never waits for it.
  BuildStatus build_status() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// Loads scenes on a worker thread, one request at a time: a newer request supersedes an
// older one (a load in progress is finished and dropped: load_scene cannot be interrupted).
class SceneLoader {
 public:
  struct Result {
    std::string spec;                    // what was asked for
    std::shared_ptr<const Scene> scene;  // null when the load failed
    std::string error;                   // then: one line naming the file and the problem
  };

  SceneLoader();
  ~SceneLoader();  // waits for a load in progress
  SceneLoader(const SceneLoader&) = delete;
  SceneLoader& operator=(const SceneLoader&) = delete;

  // Starts loading SCENE (a path or builtin:NAME) and returns at once.
  void load(const std::string& spec);
  // The newest request's result, once it is done; each result is handed out once.
  std::optional<Result> take();
  // The newest request while its result has not been taken.
  std::optional<std::string> pending() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace gs
