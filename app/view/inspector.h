// The bottom panel's walk tab: the picked walk cell by cell (depth, how it was entered,
// descents, tests, rejections) and, beside it, the §6 cost model of the inspected cell's
// parent voxel as the build evaluated it.
#pragma once

namespace gs::app {

struct ViewState;

// Choosing another cell marks the overlays stale (the highlight and the cost change).
void walk_tab(ViewState& state);

}  // namespace gs::app
