// The `view` command (DESIGN.md §3): the interactive explorer. A window shows the image the
// progressive renderer (core/progressive.h) refines on worker threads, with the overlays of
// what the 1D grid has built so far, panels to change the structure and its cost constants,
// and an inspector for one ray's walk. Script flags (--frames, --click, --screenshot,
// --walk-out) let tests and CI drive it without a person.
#pragma once
#include <array>
#include <optional>
#include <string>

#include "core/accelerator.h"
#include "core/camera.h"
#include "core/overlay.h"

namespace gs::app {

struct ViewJob {
  std::string scene;  // empty: builtin:lumpy with the close-up camera
  std::optional<Camera> camera;
  std::string accel = "grid1d";
  AccelParams params;
  int width = 1280, height = 800;  // the window
  int frames = 0;                  // 0: interactive; N: exit after N frames (and the first pass)
  std::optional<std::array<double, 2>> click;  // fractions of the viewport
  std::string screenshot;                      // PNG of the whole window, just before exiting
  std::string walk_out;                        // the clicked pixel's walk as JSON
  OverlaySelection overlays{.walk = true};     // shown at the start (--overlay)
};

// X,Y: two numbers in 0..1. Throws UsageError otherwise.
std::array<double, 2> parse_click(const std::string& text);

// Usage errors first (structure name, --walk-out without --click or with a structure that
// has no cells), then the scene (InputError naming the file), then the window (InputError
// when there is no OpenGL context). Returns when the window closes or the script is done.
void run_view(const ViewJob& job);

}  // namespace gs::app
