// The `shot` command (docs/design.md §3): the viewer's frame, headless through OSMesa. Renders
// the image on the CPU as `render` does, adds the chosen overlays, draws the frame (and, if
// asked, the statistics panel) with OpenGL and writes it as a PNG.
#pragma once
#include <array>
#include <optional>
#include <string>

#include "app/compare_spec.h"
#include "core/accel/accelerator.h"
#include "core/render/overlay.h"
#include "core/render/render.h"
#include "core/scene/camera.h"

namespace gs::app {

struct ShotJob {
  std::string scene;
  std::string out_path;  // PNG
  std::string accel = "grid1d";
  AccelParams params;
  RenderSettings settings;
  std::optional<Camera> camera;             // default: frame_box of the scene
  OverlaySelection overlays;                // --overlay cells,states,walk,heat:KIND
  std::optional<std::array<int, 2>> pixel;  // the walk's pixel; default: the image centre
  bool ui = false;                          // draw the statistics panel over the frame
  std::optional<CompareSpec> compare;       // --compare: side B beside A
};

// Throws UsageError for usage problems (bad settings, a Grid1D overlay with another
// structure, --pixel outside the image) before reading any file, InputError for a missing
// scene, an unwritable PNG or no OpenGL context.
void run_shot(const ShotJob& job);

}  // namespace gs::app
