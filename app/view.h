// The `view` command (DESIGN.md §3): the interactive explorer. A window shows the image the
// progressive renderer (core/progressive.h) refines on worker threads, with the overlays of
// what the 1D grid has built so far, panels to change the structure and its cost constants,
// and an inspector for one ray's walk. Script flags (--frames, --click, --screenshot,
// --walk-out, --script, --stats) let tests and CI drive it without a person.
#pragma once
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "core/accel/accelerator.h"
#include "core/scene/camera.h"
#include "core/render/overlay.h"

namespace gs::app {

// One line of a --script file: at UI frame `frame` (counted from 1), what a person could do.
struct ScriptStep {
  enum class Action { resize, open, set, close };
  int frame = 1;
  Action action = Action::close;
  std::array<int, 2> size{0, 0};  // resize: the window's new size; 0x0 minimises it
  std::string name;               // open: SCENE; set: `accel` or a structure flag's name
  std::string value;              // set: its value, as the command line takes it
};

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
  std::string script;                          // --script FILE: steps, see parse_script
  std::string stats;                           // --stats FILE.json: written on exit
};

// X,Y: two numbers in 0..1. Throws UsageError otherwise.
std::array<double, 2> parse_click(const std::string& text);

// A --script file's steps, in frame order. One step a line, "frame N: ACTION" with ACTION
// one of `resize WxH` (0x0: minimised), `open SCENE`, `set NAME VALUE` (NAME `accel` or a
// structure flag without its dashes, e.g. `set max-granularity 8`; applied as the panel's
// Apply does) and `close`; blank lines and lines starting with '#' are skipped. `path`
// names the file in errors: InputError "FILE:LINE: problem".
std::vector<ScriptStep> parse_script(const std::string& text, const std::string& path);

// Usage errors first (structure name, --walk-out without --click or with a structure that
// has no cells), then the script and the scene (InputError naming the file), then the window
// (InputError when there is no OpenGL context). Returns when the window closes or the script is
// done.
void run_view(const ViewJob& job);

}  // namespace gs::app
