// The bottom panel's walk tab: the picked walk as a timeline of its steps (tests and
// rejections per cell) over a table of its cells (depth, how each was entered, descents,
// tests, rejections) and, beside them, the §6 cost model of the inspected cell's parent voxel
// as the build evaluated it, drawn as a chart (cost_chart.h) with its numbers folded below.
#pragma once

namespace gs::app {

struct ViewState;

// Choosing another cell marks the overlays stale (the highlight and the cost change).
void walk_tab(ViewState& state);

}  // namespace gs::app
