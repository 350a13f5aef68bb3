// The cost function of Jevans 1990, section 6, as pure functions of a voxel's figures, so
// that the build, the tests and the viewer's inspector all evaluate the same formulas.
//
// For a voxel with N triangles of mean size m along the candidate axis a (each size clipped
// to the voxel), face areas A_a (perpendicular to a), A_b, A_c, cut into g cells of width
// w = extent_a / g, a triangle spans k = ceil(m / w) cells (1..g) and, with rays flowing
// through each face in proportion to its area and perpendicular to it (§6.1):
//   int  = Intcost  (A_b + A_c) N k / g     rays across a meet one cell
//   trav = Travcost A_a (g - 1)             rays along a walk every cell
//   rep  = Repcost  A_a (k - 1) N           ... and meet spanning triangles again
//   ver  = Vertcost (A_a + A_b + A_c)       every ray entering pays set-up
// no_split = Intcost (A_b + A_c) N: the §6.3 prose (rays along a test all N triangles either
// way, so that term is dropped; it is added back to compare axes, the option beyond the
// paper). Each figure here is divided by A_a + A_b + A_c: a cost per ray entering the voxel.
#pragma once
#include "core/accel/accelerator.h"

namespace gs {

struct CutCost {
  double int_cost = 0, trav_cost = 0, rep_cost = 0, ver_cost = 0;
  double total = 0;
  int spanned_cells = 1;  // k
};

struct VoxelFigures {
  double triangles = 0;  // N
  double extent[3] = {0, 0, 0};
  double mean_size[3] = {0, 0, 0};  // per axis, each triangle's size clipped to the voxel
  double rays = 0;                  // estimated rays of the run crossing the voxel (§6.5)
};

CutCost cut_cost(const AccelParams& params, const VoxelFigures& voxel, int axis, int g);
// Rays across `axis` in an uncut voxel: Intcost (A_b + A_c) N, per ray.
double no_split_cost(const AccelParams& params, const VoxelFigures& voxel, int axis);
// Rays along `axis` test all N triangles whatever g is: Intcost A_a N, per ray. Dropped by
// the paper within one axis, needed to compare axes.
double along_axis_cost(const AccelParams& params, const VoxelFigures& voxel, int axis);

struct AxisPlan {
  int axis = 0;
  int granularity = 1;  // 1: not worth cutting
  CutCost cost;         // at the chosen granularity
  double no_split = 0;
  // The §6.5 comparison, whole-voxel: Subcost N + rays total  against  rays no_split.
  double cut_total = 0, keep_total = 0;
};

// The granularity in 2..max_g minimising total on `axis`, and whether cutting pays off
// (granularity 1 when it does not).
AxisPlan plan_axis(const AccelParams& params, const VoxelFigures& voxel, int axis, int max_g);

}  // namespace gs
