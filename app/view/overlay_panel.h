// The controls panel's overlays section: which line overlays are drawn (cells, states, the
// picked walk) and how (levels, near the walk), what the line cap left out, and the heatmap
// shown in place of the render with its range, legend and the figure under the cursor.
#pragma once

namespace gs {
struct OverlaySelection;
}

namespace gs::app {

class HeatMap;
class OverlayCache;
struct ViewState;

void overlay_controls(ViewState& state, OverlayCache& overlays);

// The overlays chosen outright (a script's `set overlay LIST`): drawn from the next frame.
void choose_overlays(ViewState& state, HeatMap& heat, const OverlaySelection& selection);

}  // namespace gs::app
