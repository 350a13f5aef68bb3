// The walk a click picked: the inspector's subject. Besides the walk itself, the cell being
// inspected, the walk's line set (that cell highlighted) and the §6 cost model of the
// cell's parent voxel, which the overlay cache reads while the structure is paused.
#pragma once
#include <array>
#include <cstdint>
#include <optional>

#include "core/accel/grid1d/grid1d.h"
#include "core/accel/walk.h"
#include "core/render/overlay.h"
#include "core/scene/camera.h"

namespace gs::app {

// What the walk did inside one voxel: the cells it visited there, tests and rejections.
struct RayInVoxel {
  int cells = 0;
  uint64_t tests = 0, rejections = 0;
};

// The build's cost figures for a cell's parent voxel (Grid1D::cost_report), beside what the
// walk did in that voxel.
struct CellCost {
  VoxelCostReport report;
  RayInVoxel ray_here;
};

// Cell `cell` of `walk`'s parent voxel's cost; nothing for a cell of the root (no parent).
std::optional<CellCost> parent_voxel_cost(const Grid1D& grid, const Walk& walk, int cell);

struct PickedWalk {
  std::optional<Walk> walk;  // none: nothing picked, or the structure has no cells
  std::array<int, 2> pixel{0, 0};
  std::array<int, 2> size{0, 0};  // the viewport the pixel was picked in
  Camera camera;                  // ... and its camera
  int cell = 0;                   // the cell inspected, an index into walk->cells
  LineSet lines;                  // empty while the walk overlay is off
  std::optional<CellCost> cost;   // of `cell`'s parent voxel
};

}  // namespace gs::app
