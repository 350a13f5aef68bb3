// The `view` command: the interactive explorer. A window shows the image the progressive
// renderer (core/render/progressive.h) refines on worker threads, with the overlays of what
// the 1D grid has built so far, panels to change the structure and its cost constants, and an
// inspector for one ray's walk. Script flags (--frames, --click, --screenshot, --walk-out,
// --script, --stats) let tests and CI drive it without a person.
//
// The viewer's parts live beside this header: viewer.h (the frame loop), state.h (what the
// parts share), script.h, camera_input.h, overlay_cache.h, layout.h and splitters.h (where
// the viewport and panels go), viewport.h, panels.h and the sections they show
// (structure_editor.h, overlay_panel.h, compare_view.h, scene_opener.h, inspector.h with
// cost_chart.h, states_table.h), build_progress.h, help_overlay.h, output.h.
#pragma once
#include <array>
#include <optional>
#include <string>

#include "app/view/script.h"
#include "core/accel/accelerator.h"
#include "core/render/overlay.h"
#include "core/scene/camera.h"

namespace gs::app {

struct ViewJob {
  std::string scene;  // empty: builtin:lumpy with the close-up camera
  std::optional<Camera> camera;
  std::string accel = "grid1d";
  AccelParams params;
  bool packets = true;             // --packets on|off: RenderSettings::packets
  int max_spp = 256;               // --max-spp N: ViewSetup::max_spp
  std::string compare;             // --compare SPEC (checked by parse_compare); empty: none
  int width = 1280, height = 800;  // the window
  int frames = 0;                  // 0: interactive; N: exit after N frames (and the first pass)
  std::optional<std::array<double, 2>> click;  // fractions of the viewport
  std::string screenshot;                      // PNG of the whole window, just before exiting
  std::string walk_out;                        // the clicked pixel's walk as JSON
  // Shown at the start (--overlay): a clicked walk with the walls of the voxels it crossed,
  // over an image otherwise left clear.
  OverlaySelection overlays{.cells = true, .walk = true, .near_walk = true};
  std::string script;  // --script FILE: steps, see parse_script
  std::string stats;   // --stats FILE.json: written on exit
};

// X,Y: two numbers in 0..1. Throws UsageError otherwise.
std::array<double, 2> parse_click(const std::string& text);

// Usage errors first (structure name, --walk-out without --click or with a structure that
// has no cells), then the script and the scene (InputError naming the file), then the window
// (InputError when there is no OpenGL context). Returns when the window closes or the script is
// done.
void run_view(const ViewJob& job);

}  // namespace gs::app
