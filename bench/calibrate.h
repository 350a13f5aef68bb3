// The code timings of Jevans 1990, section 6.2 (Intcost, Repcost, Travcost, Vertcost,
// Subcost), measured on this machine by timing grid1d's own code paths through its public
// interface: synthetic scenes in which one kind of work dominates, traced warm on one
// thread (CPU time), and a least-squares fit of time per ray against the counts the
// traversal itself reports; Subcost from the eager build timed apart. The constants are
// relative (intcost = 1): the cost function only compares them with each other (§6.5).
// Intcost is what a triangle of a cell the ray searches costs it, as the cost function
// counts triangles: its box test, and the real test only for the share of triangles whose
// box real rays cross (most boxes are missed).
#pragma once
#include <array>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <span>
#include <string>

#include "core/accel/grid1d/cost_constants.h"

namespace gs {

struct CalibrateOptions {
  static constexpr double kDefaultBudget = 20.0;
  static constexpr double kQuickBudget = 5.0;
  double budget_seconds = kDefaultBudget;  // spent timing; setting scenes up comes on top
  uint64_t seed = 1;                       // the rays of the synthetic scenes
};

// One batch of rays: its work per ray, as counted by the traversal, and its time per ray.
struct WorkSample {
  std::string label;
  double rays = 0;
  double tests = 0, rejections = 0, steps = 0, descents = 0;  // per ray
  double leaf_triangles = 0;  // per ray: triangles of the leaves searched (each box-tested)
  double cells = 0;           // per ray: cells crossed, searched or passed by (Walk::cells_crossed)
  double seconds = 0;         // per ray, warm median
};

// One eager build: the triangles sorted into cells (the sum of N over the voxels cut,
// what §6.5 charges Subcost for) and the time it took.
struct BuildSample {
  std::string label;
  double triangles_sorted = 0;
  double seconds = 0;
  double voxels = 0;  // examined (reported, not fitted)
};

// The terms of time per ray = ray + a tests + b rejections + c steps + d descents
// + e leaf triangles + f cells crossed.
enum FitTerm {
  kRayTerm,
  kTestTerm,
  kRejectionTerm,
  kStepTerm,
  kDescentTerm,
  kLeafTriangleTerm,
  kCellTerm,
  kFitTerms
};

struct CostFit {
  std::array<double, kFitTerms> seconds{};  // per unit of each term
  // Of each coefficient, from the residual; +inf where it cannot be estimated (no more rows
  // than terms, or the term left out).
  std::array<double, kFitTerms> standard_error{};
  // False for a term no row varies independently of the others: left out of the fit.
  std::array<bool, kFitTerms> fitted{};
  double rms_relative_residual = 0.0;  // of the rows' times
};

// Least squares of the rows' seconds per ray against their counts, each row weighted by
// 1 / its time so that fast and slow rows count alike (relative residuals). Rows whose time
// is not positive are left out.
CostFit fit_costs(std::span<const WorkSample> rows);
double predicted_seconds(const CostFit& fit, const WorkSample& row);

// What real rays do with the cells they meet: of a searched leaf's triangles, the share
// tested for real (tests / leaf triangles, 0..1); per cell crossed, the cells searched
// (steps / cells crossed; it may exceed 1, a ray that goes down into a cell searches it
// without crossing a wall).
struct RealRayShares {
  double tested = 0.0, searched = 0.0;
};

// The constants from measurements: the fit's coefficients over the unit, Subcost from the
// builds' seconds per triangle sorted. The cost function counts cells and their triangles,
// not what the walk does with them, so two constants are made of two timings each: the unit
// (Intcost, a triangle of a searched cell) is a leaf triangle's box test plus the tested
// share of a real test, and Travcost (a cell crossed) is a cell crossed plus the searched
// share of a step into a cell searched. A coefficient that is left out, not positive, or
// whose standard error exceeds half its value keeps its default.
Calibration calibration_from_measurements(std::span<const WorkSample> rows,
                                          std::span<const BuildSample> builds,
                                          RealRayShares shares);

// Measures on this machine (one thread). Throws UsageError for a budget that is not a
// positive number of seconds.
Calibration calibrate(const CalibrateOptions& options);

}  // namespace gs
