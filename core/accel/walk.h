// One ray's walk through the 1D grid, cell by cell, as the traversal itself records it
// (Grid1D::record_walk runs the same code that renders, with a recorder instead of the
// null one). Feeds `trace --walk` and, later, the viewer's inspector.
#pragma once
#include <cstdint>
#include <limits>
#include <nlohmann/json_fwd.hpp>
#include <vector>

#include "core/geometry/ray.h"

namespace gs {

// What a voxel's traversal state needed when the walk went down into it (§5.2.2).
enum class StateCase {
  reused,         // this ray's values were still valid: nothing computed (figure 5)
  index_only,     // this ray used the state before: only the slab index (figures 6, 7)
  reinitialised,  // first use by this ray: distances, steps and index
};

// Going down through a subdivided voxel (vertical traversal, §5.2).
struct WalkDescent {
  uint32_t voxel = 0;
  uint32_t depth = 0;
  int axis = 0;
  uint32_t granularity = 0;           // g of its 1D array
  uint64_t absolute_granularity = 0;  // G of its global grid
  uint32_t state = 0;                 // the traversal state (axis, G)
  int64_t cell = 0;                   // which of its cells the ray is in
  StateCase state_case = StateCase::reinitialised;
};

// One cell (leaf voxel) the ray was in, in walk order.
struct WalkCell {
  uint32_t voxel = 0;
  uint32_t depth = 0;
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};  // its box
  double t_enter = 0.0;                         // where the ray entered it
  int entered_axis = -1;              // the axis of the wall it came through; -1 for the first cell
  uint32_t climbed = 0;               // levels climbed to make the step into it (§5.3)
  std::vector<WalkDescent> descents;  // levels gone down to reach it
  // Not a leaf but a subdivided voxel's spanning triangles (those that lie in each of its
  // cells, kept once at the voxel), searched as the walk went down into it.
  bool spanning = false;
  bool culled = false;      // the ray's segment in it missed its contents' box: nothing looked at
  uint32_t tests = 0;       // ray/triangle tests made in it
  uint32_t rejections = 0;  // triangles the mailbox skipped (tested in an earlier cell)
  int32_t hit = -1;         // the nearest hit so far once the cell was searched
};

struct Walk {
  Ray ray;
  Hit hit;
  // Where the ray leaves the scene box (no further than tmax); +inf when it never enters it.
  double t_leave = std::numeric_limits<double>::infinity();
  std::vector<WalkCell> cells;
  // Walls the walk crossed along the axes of the subdivided voxels it stepped in: every cell
  // it passed, looked at or passed by (what §6.2's Travcost prices: the cost function charges
  // it for each cell a ray crosses).
  uint64_t cells_crossed = 0;
};

nlohmann::json to_json(const Walk& walk);

}  // namespace gs
