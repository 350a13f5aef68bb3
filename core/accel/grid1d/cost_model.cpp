#include "core/accel/grid1d/cost_model.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gs {
namespace {

struct FaceAreas {
  double along, across, sum;  // A_a, A_b + A_c, A_a + A_b + A_c
};

FaceAreas face_areas(const VoxelFigures& voxel, int axis) {
  const double ea = voxel.extent[axis];
  const double eb = voxel.extent[(axis + 1) % 3];
  const double ec = voxel.extent[(axis + 2) % 3];
  const double along = eb * ec;
  const double across = ea * ec + ea * eb;
  return {along, across, along + across};
}

}  // namespace

CutCost cut_cost(const AccelParams& params, const VoxelFigures& voxel, int axis, int g) {
  const FaceAreas area = face_areas(voxel, axis);
  CutCost cost;
  if (area.sum <= 0.0) return cost;
  const double width = voxel.extent[axis] / g;
  const double n = voxel.triangles;
  const double k = std::clamp(std::ceil(voxel.mean_size[axis] / width), 1.0, double(g));
  cost.spanned_cells = int(k);
  cost.int_cost = params.intcost * area.across * n * k / g / area.sum;
  cost.trav_cost = params.travcost * area.along * (g - 1) / area.sum;
  cost.rep_cost = params.repcost * area.along * (k - 1) * n / area.sum;
  cost.ver_cost = params.vertcost;
  cost.total = cost.int_cost + cost.trav_cost + cost.rep_cost + cost.ver_cost;
  return cost;
}

double no_split_cost(const AccelParams& params, const VoxelFigures& voxel, int axis) {
  const FaceAreas area = face_areas(voxel, axis);
  return area.sum > 0.0 ? params.intcost * area.across * voxel.triangles / area.sum : 0.0;
}

double along_axis_cost(const AccelParams& params, const VoxelFigures& voxel, int axis) {
  const FaceAreas area = face_areas(voxel, axis);
  return area.sum > 0.0 ? params.intcost * area.along * voxel.triangles / area.sum : 0.0;
}

AxisPlan plan_axis(const AccelParams& params, const VoxelFigures& voxel, int axis, int max_g) {
  AxisPlan plan;
  plan.axis = axis;
  plan.no_split = no_split_cost(params, voxel, axis);
  plan.keep_total = voxel.rays * plan.no_split;
  plan.cut_total = std::numeric_limits<double>::infinity();
  int best_g = 1;
  CutCost best;
  best.total = std::numeric_limits<double>::infinity();
  for (int g = 2; g <= max_g; ++g) {
    const CutCost cost = cut_cost(params, voxel, axis, g);
    if (cost.total < best.total) best = cost, best_g = g;
  }
  if (best_g == 1) return plan;
  // Subcost N + rays total against rays no_split (§6.5). rays may be infinite (no sampling
  // pass): then only the per-ray totals matter.
  const double sort_cost = params.subcost * voxel.triangles;
  const bool pays = std::isinf(voxel.rays) ? best.total < plan.no_split
                                           : sort_cost + voxel.rays * best.total < plan.keep_total;
  plan.cost = best;
  plan.cut_total = sort_cost + voxel.rays * best.total;
  if (pays) plan.granularity = best_g;
  return plan;
}

}  // namespace gs
