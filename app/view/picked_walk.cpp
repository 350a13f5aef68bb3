#include "app/view/picked_walk.h"

#include <algorithm>
#include <vector>

namespace gs::app {

namespace {

// The voxel (by depth) the walk had gone down through when it reached cell `upto`: a
// descent rewrites its level and every deeper one, a step within an array keeps them.
std::optional<uint32_t> parent_voxel(const Walk& walk, size_t upto) {
  std::vector<uint32_t> path;  // path[d]: the subdivided voxel at depth d
  for (size_t i = 0; i <= upto && i < walk.cells.size(); ++i)
    for (const WalkDescent& d : walk.cells[i].descents) {
      path.resize(std::max<size_t>(path.size(), d.depth + 1), Grid1D::kNone);
      path[d.depth] = d.voxel;
      path.resize(d.depth + 1);
    }
  const uint32_t depth = walk.cells[upto].depth;
  if (depth == 0 || path.size() < depth || path[depth - 1] == Grid1D::kNone) return std::nullopt;
  return path[depth - 1];
}

RayInVoxel ray_in_voxel(const Walk& walk, uint32_t voxel) {
  RayInVoxel here;
  for (size_t i = 0; i < walk.cells.size(); ++i) {
    if (parent_voxel(walk, i) != std::optional<uint32_t>(voxel)) continue;
    ++here.cells;
    here.tests += walk.cells[i].tests;
    here.rejections += walk.cells[i].rejections;
  }
  return here;
}

}  // namespace

std::optional<CellCost> parent_voxel_cost(const Grid1D& grid, const Walk& walk, int cell) {
  if (walk.cells.empty()) return std::nullopt;
  const std::optional<uint32_t> parent = parent_voxel(walk, size_t(cell));
  if (!parent) return std::nullopt;
  return CellCost{grid.cost_report(*parent), ray_in_voxel(walk, *parent)};
}

}  // namespace gs::app
