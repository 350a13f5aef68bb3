// The viewer's progressive CPU renderer (issue 3): on worker threads, never on the UI
// thread, it renders a view in passes: a coarse pass (one ray per 8x8 block, shown as
// blocks), then full resolution at pixel centres (the same image `gridscope render --spp 1`
// gives), then jittered samples accumulated one per pixel per pass (antialiasing, soft
// shadows). Any change of view, scene, structure or parameters restarts it; the UI thread
// only takes finished frames.
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

#include "core/accelerator.h"
#include "core/camera.h"
#include "core/render.h"
#include "core/scene.h"
#include "core/walk.h"

namespace gs {

// What to render: a change of any field restarts the passes.
struct ViewSetup {
  std::shared_ptr<const Scene> scene;  // shared with the UI, never modified
  std::string accel = "grid1d";
  AccelParams params;
  Camera camera;
  int width = 0, height = 0;
  int threads = default_thread_count();
  int max_spp = 256;  // accumulation stops here
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
  StructureStats structure;      // of the structure the frame was rendered with
  std::string error;             // a failed build or render: what went wrong, one line
};

class ProgressiveRenderer {
 public:
  ProgressiveRenderer();
  ~ProgressiveRenderer();  // stops and joins the workers
  ProgressiveRenderer(const ProgressiveRenderer&) = delete;
  ProgressiveRenderer& operator=(const ProgressiveRenderer&) = delete;

  // Starts over with a new setup (a new structure is built when the scene, structure or
  // parameters changed; a camera or size change keeps the structure). Returns at once.
  void restart(const ViewSetup& setup);
  // The newest finished pass, if one newer than `have_generation`/`have_pass` exists.
  std::optional<ProgressiveFrame> take_frame(uint64_t have_generation, int have_pass);
  // Records the walk of pixel (x, y)'s ray (pixel centre, no jitter) through the current
  // structure, by the same traversal that renders. Waits for the structure to exist;
  // nothing when the structure has no cells (brute) or there is no scene.
  std::optional<Walk> record_walk(int x, int y);
  // Runs `visit(accel)` on the current structure while no worker traces (for overlays:
  // cell_lines etc. must not run concurrently with lazy building).
  void with_structure_paused(const std::function<void(const Accelerator&)>& visit);
  // True while passes are still being rendered (not yet at max_spp).
  bool busy() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace gs
