// The §6 cost model of one voxel as a picture: for every granularity g the build tried on
// the cut axis, a bar of the cost per ray with its four terms stacked (intersection tests,
// traversal steps, mailbox rejections, vertical descents: Intcost, Travcost, Repcost,
// Vertcost of §6.2), the chosen g marked and the uncut voxel's cost as a horizontal line.
// Hovering a bar shows its numbers.
#pragma once
#include <imgui.h>

#include "core/accel/grid1d/grid1d.h"

namespace gs::app {

// A value axis from 0 to `top` with a tick every `step`.
struct ChartScale {
  double top = 1.0;
  double step = 0.2;
};

// The axis for values up to `largest`: about five ticks, each step 1, 2 or 5 times a power
// of ten, `top` the first tick at or above `largest` (1 with steps of 0.2 for nothing
// positive).
ChartScale nice_scale(double largest);

// The slot of `count` equal ones across [left, left + width) that holds x; -1 outside.
int slot_at(float x, float left, float width, int count);

// The chart of `report`'s chosen axis in a `size` box at the cursor.
void cost_chart(const VoxelCostReport& report, const ImVec2& size);

}  // namespace gs::app
