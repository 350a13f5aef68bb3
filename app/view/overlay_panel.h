// The controls panel's overlays section: which line overlays are drawn (cells, states, the
// picked walk) and how, and the heatmap shown in place of the render with its range, legend
// and the figure under the cursor.
#pragma once

namespace gs::app {

class HeatMap;
struct ViewState;

void overlay_controls(ViewState& state, HeatMap& heat);

}  // namespace gs::app
