// The build progress bar: over the viewport while a structure build (what the first image
// waits for: core/render/progressive.h's BuildStatus) has run longer than half a second, with
// what the structure can tell of it (core/accel/build_progress.h): a bar filled by the share
// of the sampling pass done, voxels built and cut, triangles sorted; or, for a structure that
// cannot tell (every structure but grid1d), a sweeping bar and the seconds gone.
#pragma once
#include "core/render/progressive.h"

namespace gs::app {

struct ViewState;

// What the bar has shown, for --stats and the tests.
struct BuildBarRecord {
  bool shown = false;  // drawn in at least one frame
  BuildStatus last;    // the status it last drew
};

// Draws the bar when a build is running and has run long enough; records it in
// state.build_bar.
void draw_build_progress(ViewState& state);

}  // namespace gs::app
