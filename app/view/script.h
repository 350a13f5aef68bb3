// The viewer driven without a person: the --script file's steps, --frames, --click (and the
// --walk-out it writes). The viewer's frame loop asks this part which steps are due, when to
// click, and when the run is done.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "app/view/layout.h"

namespace gs {
struct ProgressiveFrame;
}

namespace gs::app {

struct ViewJob;
struct ViewState;

// One line of a --script file: at UI frame `frame` (counted from 1), what a person could do.
struct ScriptStep {
  enum class Action { resize, open, set, orbit, drag_splitter, help_key, tab, wait, close };
  int frame = 1;
  Action action = Action::close;
  std::array<int, 2> size{0, 0};  // resize: the window's new size; 0x0 minimises it
  std::string name;               // open: SCENE; set: `accel`, `packets`, `overlay`, `compare`,
                                  // `compare-view` or a structure flag's name; tab: the tab
  std::string value;              // set: its value, as the command line takes it
  float degrees = 0.0f;           // orbit: the turn about the pivot
  Splitter splitter = Splitter::right;  // drag-splitter: which bar ...
  int pixels = 0;                       // ... and how far, right or down (window units)
};

// A --script file's steps, in frame order. One step a line, "frame N: ACTION" with ACTION
// one of `resize WxH` (0x0: minimised), `open SCENE`, `set NAME VALUE` (NAME `accel` or a
// structure flag without its dashes, e.g. `set max-granularity 8`, applied as the panel's
// Apply does; `packets` with on or off, as the panel's checkbox; `overlay` with a list as
// --overlay takes it, e.g. `set overlay cells,walk,depth:1-3`, replacing the overlays shown;
// `compare SPEC` with SPEC's
// words joined by commas, or `compare off`, as the A/B section's buttons; `compare-view`
// with split, a, b or difference), `orbit DEG` (turns the
// camera about the pivot by DEG degrees, as a horizontal drag does), `drag-splitter right|bottom
// PIXELS` (moves that bar PIXELS units right or down, as a drag does: the viewport grows by
// as much, within the panels' minimums), `key F1` (or `key ?`: toggles the help overlay), `tab
// NAME` (shows the bottom panel's tab walk, statistics or states, as a click on it), `wait` (later
// steps wait until the current view's full-resolution pass is shown) and `close`; blank lines and
// lines starting with '#' are skipped. `path` names the file in errors: InputError "FILE:LINE:
// problem".
std::vector<ScriptStep> parse_script(const std::string& text, const std::string& path);

// Counts the UI frames (minimised ones too) and decides, from them and the view shown, what
// the script does next.
class Script {
 public:
  Script(const ViewJob& job, std::vector<ScriptStep> steps);

  // Scripted runs draw as fast as they can (no vsync).
  bool scripted() const;
  // The next step due by this frame (in file order), or null; each is handed out once. A
  // `wait` is due once the current view's full-resolution pass is shown (a window minimised
  // meanwhile holds it until it is restored).
  const ScriptStep* next_due_step(const ViewState& state);
  // Script mode (--frames) stops at a failed render: InputError.
  void check_frame(const ProgressiveFrame& frame) const;
  // --click, once the current view's full-resolution pass is shown: picks that pixel's walk
  // and writes --walk-out.
  void click(ViewState& state);
  // Counts the frame just run; true when the run is over: every step run, no load pending,
  // the current view's full-resolution pass shown (or no view at all: minimised since the
  // first frame), and the click made a few frames ago.
  bool frame_done(const ViewState& state, bool load_pending);

 private:
  const ViewJob& job_;
  std::vector<ScriptStep> steps_;
  size_t next_step_ = 0;
  int frames_done_ = 0, click_frame_ = 0;
  bool click_done_ = false;
};

}  // namespace gs::app
