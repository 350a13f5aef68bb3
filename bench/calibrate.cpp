#include "bench/calibrate.h"

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <glm/geometric.hpp>
#include <limits>
#include <random>

#include "core/accel/grid1d/grid1d.h"
#include "core/base/error.h"
#include "core/base/timing.h"
#include "core/scene/camera.h"
#include "core/scene/scene.h"
#include "core/trace/run.h"
#include "core/trace/sampling.h"

namespace gs {
namespace {

using json = nlohmann::json;

// The five §6.2 constants, by name, in the calibration and in the structure parameters.
// The work each constant is the cost of, in kCostConstants' order (kRayTerm: Subcost,
// timed from the build; kTestTerm and kStepTerm: the unit and Travcost, each made of two
// timings, see composite()).
constexpr FitTerm kConstantTerms[] = {kTestTerm, kRejectionTerm, kStepTerm, kDescentTerm, kRayTerm};
static_assert(std::size(kConstantTerms) == std::size(kCostConstants));
constexpr const char* kTermNames[kFitTerms] = {"ray",     "test",          "rejection",   "step",
                                               "descent", "leaf triangle", "cell crossed"};

// A coefficient whose standard error is more than this share of it is noise, not a timing.
constexpr double kMaxRelativeError = 0.5;
// Below this pivot (of the equilibrated normal matrix, whose diagonal is 1) a column is a
// combination of the ones before it.
constexpr double kDependentPivot = 1e-9;

// ---------------------------------------------------------------------------------------
// The fit

std::array<double, kFitTerms> counts_of(const WorkSample& row) {
  return {1.0, row.tests, row.rejections, row.steps, row.descents, row.leaf_triangles, row.cells};
}

// The weighted normal equations (X^T W X) c = X^T W y over some of the terms, equilibrated
// (each column divided by its norm, so the matrix's diagonal is 1): `a` is p x p, row-major.
struct NormalEquations {
  size_t p = 0;
  std::vector<double> a, b, scale;
};

NormalEquations normal_equations(std::span<const WorkSample> rows, const std::vector<int>& terms) {
  const size_t p = terms.size();
  NormalEquations eq{p, std::vector<double>(p * p, 0.0), std::vector<double>(p, 0.0),
                     std::vector<double>(p, 0.0)};
  for (const WorkSample& row : rows) {
    if (!(row.seconds > 0.0)) continue;
    const std::array<double, kFitTerms> x = counts_of(row);
    const double w2 = 1.0 / (row.seconds * row.seconds);
    for (size_t i = 0; i < p; ++i) {
      eq.b[i] += w2 * x[terms[i]] * row.seconds;
      for (size_t j = 0; j < p; ++j) eq.a[i * p + j] += w2 * x[terms[i]] * x[terms[j]];
    }
  }
  for (size_t i = 0; i < p; ++i) eq.scale[i] = std::sqrt(eq.a[i * p + i]);
  for (size_t i = 0; i < p; ++i) {
    eq.b[i] /= eq.scale[i];
    for (size_t j = 0; j < p; ++j) eq.a[i * p + j] /= eq.scale[i] * eq.scale[j];
  }
  return eq;
}

// a = L L^T in place (L in the lower triangle). Returns the first column that is a
// combination of the ones before it, or -1.
int cholesky(std::vector<double>& a, size_t p) {
  for (size_t j = 0; j < p; ++j) {
    double d = a[j * p + j];
    for (size_t k = 0; k < j; ++k) d -= a[j * p + k] * a[j * p + k];
    if (!(d > kDependentPivot)) return int(j);
    a[j * p + j] = std::sqrt(d);
    for (size_t i = j + 1; i < p; ++i) {
      double s = a[i * p + j];
      for (size_t k = 0; k < j; ++k) s -= a[i * p + k] * a[j * p + k];
      a[i * p + j] = s / a[j * p + j];
    }
  }
  return -1;
}

// Solves L L^T z = rhs by forward then back substitution.
std::vector<double> cholesky_solve(const std::vector<double>& l, size_t p, std::vector<double> z) {
  for (size_t i = 0; i < p; ++i) {
    for (size_t k = 0; k < i; ++k) z[i] -= l[i * p + k] * z[k];
    z[i] /= l[i * p + i];
  }
  for (size_t i = p; i-- > 0;) {
    for (size_t k = i + 1; k < p; ++k) z[i] -= l[k * p + i] * z[k];
    z[i] /= l[i * p + i];
  }
  return z;
}

// Fits `terms`: fills fit.seconds and, in fit.standard_error, the diagonal of the inverse
// normal matrix (the caller scales it by the residual's variance). Returns the position in
// `terms` of a column dependent on the ones before it (nothing filled), or -1.
int fit_terms(std::span<const WorkSample> rows, const std::vector<int>& terms, CostFit& fit) {
  NormalEquations eq = normal_equations(rows, terms);
  if (const int dependent = cholesky(eq.a, eq.p); dependent >= 0) return dependent;
  const std::vector<double> z = cholesky_solve(eq.a, eq.p, eq.b);
  for (size_t i = 0; i < eq.p; ++i) {
    std::vector<double> unit(eq.p, 0.0);
    unit[i] = 1.0;
    fit.seconds[terms[i]] = z[i] / eq.scale[i];
    fit.standard_error[terms[i]] =
        cholesky_solve(eq.a, eq.p, unit)[i] / (eq.scale[i] * eq.scale[i]);
  }
  return -1;
}

// Why a fitted term cannot be trusted as a timing; empty when it can.
std::string why_unidentified(const CostFit& fit, int term) {
  const auto ns = [](double seconds) { return std::to_string(seconds * 1e9) + " ns"; };
  if (!fit.fitted[term])
    return "no measurement varies its count apart from the others, so it was left out of the fit";
  if (!(fit.seconds[term] > 0.0))
    return "the fit gives " + ns(fit.seconds[term]) + ", not positive";
  if (!(fit.standard_error[term] <= kMaxRelativeError * fit.seconds[term]))
    return "its standard error (" + ns(fit.standard_error[term]) +
           ") is more than half its value (" + ns(fit.seconds[term]) + ")";
  return "";
}

json row_json(const WorkSample& row, const CostFit& fit) {
  const double predicted = predicted_seconds(fit, row);
  return {{"label", row.label},
          {"rays", row.rays},
          {"tests", row.tests},
          {"rejections", row.rejections},
          {"steps", row.steps},
          {"descents", row.descents},
          {"leaf_triangles", row.leaf_triangles},
          {"cells_crossed", row.cells},
          {"nanoseconds_per_ray", row.seconds * 1e9},
          {"predicted_nanoseconds_per_ray", predicted * 1e9},
          {"relative_error", predicted / row.seconds - 1.0}};
}

// ---------------------------------------------------------------------------------------
// Synthetic scenes, each built so that one kind of work dominates and its count is known

void add_triangle(Scene& scene, glm::vec3 a, glm::vec3 b, glm::vec3 c) {
  const uint32_t first = uint32_t(scene.vertices.size());
  scene.vertices.insert(scene.vertices.end(), {a, b, c});
  scene.triangles.push_back({first, first + 1, first + 2});
}

// A row of unit cubes along x, [0, cells] x [0, 1] x [0, 1]: a small triangle inside every
// `stride`-th cell (and the last), in a corner of the yz square, so that cutting the row
// makes unit cells; and in every `panel_stride`-th cell (0: none) a panel across the cell's
// middle, x = i + 0.5, covering the half y + z <= 1 of the square; and `slivers` triangles
// in planes z = y - 0.1 - 0.02 k from x = 0 to the middle of the last cell but one: in every
// cell but the last (a triangle in every cell of a cut would be kept once at its node and
// met once). The rays of rays_along_row (at
// y in [0.55, 0.65], z - y in [0.04, 0.14], nearly along x) miss every triangle but cross
// the panels' and slivers' boxes: the walk looks at each cell holding one (a step), tests
// what it holds, and meets the slivers again in every cell after the first (rejections).
// The corner triangles' boxes lie off the rays.
Scene cell_row(int cells, int stride, int panel_stride, int slivers) {
  Scene scene;
  scene.name = "calibration row";
  for (int i = 0; i < cells; ++i) {
    const bool last = i == cells - 1;
    if (i % stride == 0 || last) {
      // The first and last triangles touch the row's ends, so the cells are unit cubes.
      const float x = i == 0 ? 0.0f : last ? float(cells) - 0.2f : float(i) + 0.4f;
      const float corner = last || i % 2 == 1 ? 1.0f : 0.0f;
      const float inward = corner == 0.0f ? 0.2f : -0.2f;
      add_triangle(scene, {x, corner, corner}, {x + 0.2f, corner, corner},
                   {x + 0.1f, corner + inward, corner + inward});
    }
    if (panel_stride > 0 && i % panel_stride == 0) {
      const float x = float(i) + 0.5f;
      add_triangle(scene, {x, 0.0f, 0.0f}, {x, 1.0f, 0.0f}, {x, 0.0f, 1.0f});
    }
  }
  for (int k = 0; k < slivers; ++k) {
    const float shift = -0.1f - 0.02f * float(k) / float(slivers);
    const float end = float(cells) - 1.5f;
    add_triangle(scene, {0.0f, 0.3f, 0.3f + shift}, {end, 0.3f, 0.3f + shift},
                 {end, 0.95f, 0.95f + shift});
  }
  return scene;
}

// Rays through the row end to end, half of them each way, nearly parallel to x (see
// cell_row): tilted by at most 0.01 over the row, not parallel, so that no triangle's
// projection onto the ray's plane collapses and every test is the kernel's ordinary one.
std::vector<Ray> rays_along_row(int cells, int count, std::mt19937_64& rng) {
  std::uniform_real_distribution<float> y_at(0.56f, 0.64f), above(0.06f, 0.12f),
      tilt(-0.01f, 0.01f);
  std::vector<Ray> rays(static_cast<size_t>(count));
  for (int i = 0; i < count; ++i) {
    const float sign = i % 2 == 0 ? 1.0f : -1.0f;
    const float y = y_at(rng);
    rays[i].origin = {sign > 0 ? -1.0f : float(cells) + 1.0f, y, y + above(rng)};
    rays[i].dir = {sign * (float(cells) + 2.0f), tilt(rng), tilt(rng)};
  }
  return rays;
}

// n^3 small triangles, one at the centre c of each unit cube of [0, n]^3 (n a power of two),
// in the plane z = c.z, covering the half x + y <= c.x + c.y of a 0.2-wide square. Cut in
// halves along x, y, z in turn, every voxel down to depth 3 log2(n) holds two or more.
Scene lattice(int n) {
  Scene scene;
  scene.name = "calibration lattice";
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const glm::vec3 c(float(i) + 0.5f, float(j) + 0.5f, float(k) + 0.5f);
        add_triangle(scene, c + glm::vec3(-0.1f, -0.1f, 0.0f), c + glm::vec3(0.1f, -0.1f, 0.0f),
                     c + glm::vec3(-0.1f, 0.1f, 0.0f));
      }
  return scene;
}

// Rays from random points inside the lattice's cubes, each through the uncovered half of
// its cube's triangle square and ending just past it: the walk goes down every level to the
// cube's leaf (the ray crosses its triangle's box), tests the triangle and misses it.
std::vector<Ray> short_rays_inside(int n, int count, std::mt19937_64& rng) {
  std::uniform_int_distribution<int> cube(0, n - 1);
  std::uniform_real_distribution<float> inside(0.05f, 0.95f);
  std::vector<Ray> rays(static_cast<size_t>(count));
  for (Ray& ray : rays) {
    const glm::vec3 corner(float(cube(rng)), float(cube(rng)), float(cube(rng)));
    ray.origin = corner + glm::vec3(inside(rng), inside(rng), inside(rng));
    ray.dir = corner + glm::vec3(0.55f, 0.55f, 0.5f) - ray.origin;
    ray.tmax = 1.01f;
  }
  return rays;
}

// Structure parameters that shape a scenario's structure (they do not touch the traversal
// being timed): with only Intcost non-zero, every voxel whose cut separates its triangles
// is cut as finely as max_granularity allows, down to max_depth.
AccelParams shaping_params(int max_granularity, int max_depth) {
  AccelParams params;
  params.repcost = params.travcost = params.vertcost = params.subcost = 0.0;
  params.max_granularity = params.max_root_granularity = max_granularity;
  params.max_depth = max_depth;
  return params;
}

struct Scenario {
  std::string label;
  Scene scene;
  AccelParams params;
  std::vector<Ray> rays;
  // The work the construction makes dominate and its count per ray, given the structure
  // built: confirmed against what the traversal counted.
  FitTerm designed_term;
  std::function<double(const Grid1D&)> designed;
};

constexpr int kRaysPerScenario = 2048;

std::vector<Scenario> make_scenarios(std::mt19937_64& rng) {
  std::vector<Scenario> scenarios;
  const auto root_cells = [](const Grid1D& grid) { return double(grid.voxel(0).granularity); };
  // One leaf (max granularity 1: nothing is cut) of n panels (and the two end triangles),
  // the root: n tests per ray. Panels, because the leaf loop tests only triangles whose box
  // the ray crosses: a test is a box test and a kernel test.
  for (const int n : {8, 64, 512})
    scenarios.push_back({"tests, leaf of " + std::to_string(n), cell_row(n, n, 1, 0),
                         shaping_params(1, 0), rays_along_row(n, kRaysPerScenario, rng), kTestTerm,
                         [n](const Grid1D&) { return double(n); }});
  // One leaf of n small triangles in the cells' corners, whose boxes lie off the rays: n box
  // tests per ray and no real test, so that the fit tells a triangle's box test from its
  // real test.
  for (const int n : {64, 512})
    scenarios.push_back({"box tests, leaf of " + std::to_string(n), cell_row(n, 1, 0, 0),
                         shaping_params(1, 0), rays_along_row(n, kRaysPerScenario, rng),
                         kLeafTriangleTerm, [n](const Grid1D&) { return double(n); }});
  // The row cut into its cells, every other one holding a panel: a step per panel.
  for (const int cells : {16, 64, 256})
    scenarios.push_back({"steps, " + std::to_string(cells) + " cells", cell_row(cells, 1, 2, 0),
                         shaping_params(cells, 1), rays_along_row(cells, kRaysPerScenario, rng),
                         kStepTerm, [=](const Grid1D& grid) { return root_cells(grid) / 2.0; }});
  // The row cut into its cells, a panel in every eighth (every 32nd) and in all of them a
  // corner triangle whose box the rays miss: 8 (32) cells crossed per step, so that the fit
  // tells a cell crossed (passed by its content box) from a step into a cell searched.
  for (const auto& [cells, panel_stride] : {std::pair{64, 8}, std::pair{256, 32}})
    scenarios.push_back({"cells, " + std::to_string(cells) + " cells, a panel in every " +
                             std::to_string(panel_stride) + "th",
                         cell_row(cells, 1, panel_stride, 0), shaping_params(cells, 1),
                         rays_along_row(cells, kRaysPerScenario, rng), kCellTerm,
                         [=](const Grid1D& grid) { return root_cells(grid) - 1.0; }});
  // Slivers along the row: met again, and rejected, in every cell holding them after the
  // first (all cells but the last).
  constexpr int kSliverRowCells = 32;
  for (const int slivers : {16, 64})
    scenarios.push_back({"rejections, " + std::to_string(slivers) + " slivers",
                         cell_row(kSliverRowCells, 1, 0, slivers),
                         shaping_params(kSliverRowCells, 1),
                         rays_along_row(kSliverRowCells, kRaysPerScenario, rng), kRejectionTerm,
                         [=](const Grid1D& grid) { return slivers * (root_cells(grid) - 2.0); }});
  // Halved on x, y, z in turn down to single triangles: 3 log2(n) descents per ray.
  for (const int levels : {1, 2, 3, 4}) {
    const int n = 1 << levels;
    scenarios.push_back({"descents, lattice of " + std::to_string(n) + "^3", lattice(n),
                         shaping_params(2, 0), short_rays_inside(n, kRaysPerScenario, rng),
                         kDescentTerm, [=](const Grid1D&) { return 3.0 * levels; }});
  }
  return scenarios;
}

// ---------------------------------------------------------------------------------------
// Timing

constexpr size_t kMinPasses = 5;
constexpr size_t kMaxPasses = 1001;

// CPU seconds of the calling thread: unlike wall time, not inflated while other processes
// have the core (the machine is shared), so repeated passes measure the code.
template <class Work>
double cpu_seconds_of(Work&& work) {
  timespec start, end;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &start);
  work();
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &end);
  return double(end.tv_sec - start.tv_sec) + 1e-9 * double(end.tv_nsec - start.tv_nsec);
}

// The median of `pass` (which returns the seconds it timed), run at least kMinPasses times
// and until `share` seconds of wall time have gone.
double median_of_passes(const std::function<double()>& pass, double share) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(share);
  std::vector<double> times;
  while (times.size() < kMinPasses ||
         (std::chrono::steady_clock::now() < deadline && times.size() < kMaxPasses))
    times.push_back(pass());
  return median(times);
}

// Single-thread passes over the rays after one untimed pass (which builds what is lazy and
// warms the caches): their median, per ray. `counters` gets a warm pass's counts (each
// pass does the same work).
double warm_seconds_per_ray(const Accelerator& accel, const std::vector<Ray>& rays, double share,
                            TraceCounters& counters) {
  std::vector<Hit> hits(rays.size());
  const auto pass = [&] {
    return cpu_seconds_of([&] {
      counters = trace_chunks(accel, rays.size(), rays.size(), 1,
                              [&](ThreadContext& context, size_t begin, size_t end) {
                                for (size_t i = begin; i < end; ++i)
                                  hits[i] = accel.intersect(rays[i], context);
                              });
    });
  };
  pass();
  return median_of_passes(pass, share) / double(rays.size());
}

// Cells the rays crossed, per ray: from their recorded walks (the timed walk counts none).
double cells_crossed_per_ray(const Grid1D& grid, const std::vector<Ray>& rays) {
  const auto context = grid.make_context();
  double cells = 0.0;
  for (const Ray& ray : rays)
    if (const std::optional<Walk> walk = grid.record_walk(ray, *context))
      cells += double(walk->cells_crossed);
  return cells / double(rays.size());
}

// The rays' work per ray, as the traversal counted it, and warm time per ray.
WorkSample measure(const std::string& label, const Grid1D& grid, const std::vector<Ray>& rays,
                   double share) {
  TraceCounters counters;
  WorkSample row;
  row.label = label;
  row.seconds = warm_seconds_per_ray(grid, rays, share, counters);
  const double n = double(rays.size());
  row.rays = n;
  row.tests = double(counters.intersection_tests) / n;
  row.rejections = double(counters.mailbox_rejections) / n;
  row.steps = double(counters.traversal_steps) / n;
  row.descents = double(counters.descents) / n;
  row.leaf_triangles = double(counters.leaf_triangles) / n;
  row.cells = cells_crossed_per_ray(grid, rays);
  return row;
}

// How far a scenario's measured count may be from its design (a ray starting near a wall
// of the lattice steps once and goes down again).
constexpr double kDesignTolerance = 0.01;

WorkSample measure_scenario(const Scenario& scenario, double share, json& designs) {
  Grid1D grid(scenario.params);
  grid.build(scenario.scene);
  grid.build_all();
  const WorkSample row = measure(scenario.label, grid, scenario.rays, share);
  const double designed = scenario.designed(grid);
  const double measured = counts_of(row)[scenario.designed_term];
  designs.push_back(
      {{"label", scenario.label},
       {"count", kTermNames[scenario.designed_term]},
       {"designed", designed},
       {"measured", measured},
       {"as_designed", std::abs(measured - designed) <= kDesignTolerance * designed}});
  return row;
}

// Real scenes: Subcost's builds, the share of a searched leaf's triangles that real rays
// test for real, and the check of the fit on rays it was not fitted on.
constexpr const char* kBuiltinScenes[] = {"pyramid", "lumpy"};

// The structure the real scenes are built as: fixed constants (the defaults before a unit was
// a searched leaf's triangle), not the defaults, so that what calibrate measures does not
// depend on the defaults it may become. The tested share falls as leaves grow (0.137 on this
// structure, 0.042 on the defaults' coarser one), and taken on the defaults' own structure it
// would feed back into ever coarser constants.
AccelParams reference_params() {
  AccelParams params;
  params.repcost = 0.35, params.travcost = 12.0, params.vertcost = 10.0, params.subcost = 13.0;
  return params;
}

// Subcost: eager builds of built-in scenes with the reference parameters (no sampling pass:
// every voxel is examined), each a fresh structure: the build_all seconds' median against
// the triangles of the voxels that were cut.
std::vector<BuildSample> measure_builds(double share) {
  std::vector<BuildSample> builds;
  for (const std::string name : kBuiltinScenes) {
    const Scene scene = make_builtin_scene(name);
    BuildSample build{"builtin:" + name};
    const auto pass = [&] {
      Grid1D grid{reference_params()};
      grid.build(scene);
      const double seconds = cpu_seconds_of([&] { grid.build_all(); });
      build.voxels = double(grid.voxel_count());
      build.triangles_sorted = 0.0;
      for (uint32_t id = 0; id < grid.voxel_count(); ++id)
        if (grid.voxel(id).status.load() == Grid1D::kSplit)
          build.triangles_sorted += grid.voxel(id).tri_count;
      return seconds;
    };
    build.seconds = median_of_passes(pass, share / double(std::size(kBuiltinScenes)));
    builds.push_back(build);
  }
  return builds;
}

// Camera rays of the built-in scenes' default views through grid1d built as the reference
// (sampling pass, lazy): real rays' work, which the fit was not fitted on.
std::vector<WorkSample> measure_views(double share) {
  constexpr int kSide = 128;
  std::vector<WorkSample> rows;
  for (const std::string name : kBuiltinScenes) {
    const Scene scene = make_builtin_scene(name);
    const Camera camera = frame_box(scene.bounds());
    const PrimaryRays primary_ray(camera, kSide, kSide);
    std::vector<Ray> rays;
    for (int y = 0; y < kSide; ++y)
      for (int x = 0; x < kSide; ++x) rays.push_back(primary_ray(x, y));
    Grid1D grid{reference_params()};
    grid.build(scene);
    sample_run(grid, image_sample(rays, kSide, kSide), rays.size(), 1);
    rows.push_back(measure("builtin:" + name + ", default view", grid, rays, share));
  }
  return rows;
}

// Real tests per leaf triangle and steps per cell crossed over the rows (each row's rays
// alike); 0 without leaf triangles or cells.
RealRayShares shares_of(std::span<const WorkSample> rows) {
  double tests = 0.0, leaf_triangles = 0.0, steps = 0.0, cells = 0.0;
  for (const WorkSample& row : rows)
    tests += row.tests, leaf_triangles += row.leaf_triangles, steps += row.steps,
        cells += row.cells;
  return {leaf_triangles > 0.0 ? std::min(1.0, tests / leaf_triangles) : 0.0,
          cells > 0.0 ? steps / cells : 0.0};
}

// Parts of the budget: traced rows (the synthetic scenes and the validation), builds.
constexpr double kTraceShare = 0.85;

}  // namespace

CostFit fit_costs(std::span<const WorkSample> rows) {
  CostFit fit;
  std::vector<int> terms;
  for (int t = 0; t < kFitTerms; ++t) {
    fit.standard_error[t] = kInf;
    for (const WorkSample& row : rows)
      if (row.seconds > 0.0 && counts_of(row)[t] != 0.0) {
        terms.push_back(t);
        break;
      }
  }
  // Drop dependent columns one at a time until the rest can be solved. The per-ray term
  // comes first, so when it and a count cannot be told apart the count is the one dropped.
  for (int dependent; !terms.empty() && (dependent = fit_terms(rows, terms, fit)) >= 0;)
    terms.erase(terms.begin() + dependent);
  for (const int t : terms) fit.fitted[t] = true;
  for (int t = 0; t < kFitTerms; ++t)
    if (!fit.fitted[t]) fit.seconds[t] = 0.0, fit.standard_error[t] = kInf;

  double squares = 0.0;
  size_t used = 0;
  for (const WorkSample& row : rows) {
    if (!(row.seconds > 0.0)) continue;
    const double relative = predicted_seconds(fit, row) / row.seconds - 1.0;
    squares += relative * relative;
    ++used;
  }
  fit.rms_relative_residual = used > 0 ? std::sqrt(squares / double(used)) : 0.0;
  const double variance = used > terms.size() ? squares / double(used - terms.size()) : kInf;
  for (const int t : terms) fit.standard_error[t] = std::sqrt(variance * fit.standard_error[t]);
  return fit;
}

double predicted_seconds(const CostFit& fit, const WorkSample& row) {
  const std::array<double, kFitTerms> x = counts_of(row);
  double seconds = 0.0;
  for (int t = 0; t < kFitTerms; ++t) seconds += fit.seconds[t] * x[t];
  return seconds;
}

// A constant made of two timings, `base` + share x `shared` (the unit: a leaf triangle's box
// test and the tested share of a real test; Travcost: a cell crossed and the searched
// share of a step into a cell searched): its seconds and standard error, or why it cannot
// be measured (both must be timings).
struct Composite {
  double seconds = 0.0, standard_error = 0.0;
  std::string problem;
};
Composite composite(const CostFit& fit, FitTerm base, FitTerm shared, double share) {
  for (const FitTerm term : {base, shared})
    if (std::string problem = why_unidentified(fit, term); !problem.empty())
      return {0.0, 0.0, std::string("the ") + kTermNames[term] + "'s cost: " + problem};
  return {fit.seconds[base] + share * fit.seconds[shared],
          std::hypot(fit.standard_error[base], share * fit.standard_error[shared]), ""};
}

Calibration calibration_from_measurements(std::span<const WorkSample> rows,
                                          std::span<const BuildSample> builds,
                                          RealRayShares shares) {
  const CostFit fit = fit_costs(rows);
  Calibration calibration;
  json constants = json::object(), unidentified = json::object();
  // Intcost, the unit: what one triangle of a searched cell costs a real ray (§6.4 counts
  // every triangle of the cell the ray crosses), its box test and, for the share of them
  // whose box the ray crosses, a real test.
  const Composite unit = composite(fit, kLeafTriangleTerm, kTestTerm, shares.tested);
  // Travcost: what one cell crossed costs a real ray (§6.4 counts every cell a ray crosses),
  // passing it by and, for the share of cells a ray searches, the step into it.
  const Composite travel = composite(fit, kCellTerm, kStepTerm, shares.searched);

  double build_seconds = 0.0, triangles_sorted = 0.0;
  json build_rows = json::array();
  for (const BuildSample& build : builds) {
    build_seconds += build.seconds;
    triangles_sorted += build.triangles_sorted;
    build_rows.push_back(
        {{"label", build.label},
         {"voxels", build.voxels},
         {"triangles_sorted", build.triangles_sorted},
         {"seconds", build.seconds},
         {"nanoseconds_per_triangle", build.triangles_sorted > 0
                                          ? json(build.seconds / build.triangles_sorted * 1e9)
                                          : json(nullptr)}});
  }
  const double sort_seconds = triangles_sorted > 0.0 ? build_seconds / triangles_sorted : 0.0;

  for (size_t k = 0; k < std::size(kCostConstants); ++k) {
    const CostConstant& constant = kCostConstants[k];
    const FitTerm term = kConstantTerms[k];
    const bool from_build = term == kRayTerm;
    const Composite* made_of = term == kTestTerm ? &unit : term == kStepTerm ? &travel : nullptr;
    const double seconds = from_build ? sort_seconds
                           : made_of  ? made_of->seconds
                                      : fit.seconds[term];
    std::string problem =
        !unit.problem.empty() ? "intcost, the unit, is not measured: " + unit.problem
        : from_build
            ? (sort_seconds > 0.0 ? ""
                                  : "the builds sorted no triangle into cells in measurable time")
        : made_of ? made_of->problem
                  : why_unidentified(fit, term);
    if (problem.empty())
      calibration.*constant.calibrated = seconds / unit.seconds;
    else
      unidentified[constant.name] = problem + "; kept the default";
    constants[constant.name] = {
        {"value", calibration.*constant.calibrated},
        {"default", AccelParams{}.*constant.parameter},
        {"measured", problem.empty()},
        {"nanoseconds", seconds * 1e9},
        {"standard_error_nanoseconds",
         from_build ? json(nullptr)
                    : json((made_of ? made_of->standard_error : fit.standard_error[term]) * 1e9)},
        {"work", from_build          ? "triangle sorted into cells (eager build)"
                 : term == kTestTerm ? "triangle of a searched leaf: its box test, and a test "
                                       "for the tested share"
                 : term == kStepTerm ? "cell crossed: passed by, or for the searched share a "
                                       "step into it"
                                     : kTermNames[term]}};
  }
  calibration.nanoseconds_per_unit = unit.seconds * 1e9;

  json fit_rows = json::array();
  for (const WorkSample& row : rows) fit_rows.push_back(row_json(row, fit));
  calibration.detail = {
      {"constants", constants},
      {"per_ray_nanoseconds", fit.seconds[kRayTerm] * 1e9},
      {"tested_share", shares.tested},
      {"test_nanoseconds", fit.seconds[kTestTerm] * 1e9},
      {"leaf_triangle_nanoseconds", fit.seconds[kLeafTriangleTerm] * 1e9},
      {"searched_per_cell", shares.searched},
      {"step_nanoseconds", fit.seconds[kStepTerm] * 1e9},
      {"cell_nanoseconds", fit.seconds[kCellTerm] * 1e9},
      {"fit",
       {{"model",
         "seconds per ray = ray + a tests + b leaf triangles + c steps + e cells crossed + "
         "repcost rejections + vertcost descents, least squares weighted by 1 / time; intcost "
         "= b + tested_share a, travcost = e + searched_per_cell c"},
        {"rms_relative_residual", fit.rms_relative_residual},
        {"rows", fit_rows}}},
      {"build", {{"triangles_sorted", triangles_sorted}, {"rows", build_rows}}},
      {"unidentified", unidentified}};
  return calibration;
}

Calibration calibrate(const CalibrateOptions& options) {
  if (!(options.budget_seconds > 0.0) || !std::isfinite(options.budget_seconds))
    throw UsageError("calibrate: the time budget must be a positive number of seconds");
  const auto start = Clock::now();
  std::mt19937_64 rng(options.seed);
  const std::vector<Scenario> scenarios = make_scenarios(rng);
  const double share =
      options.budget_seconds * kTraceShare / double(scenarios.size() + std::size(kBuiltinScenes));
  std::vector<WorkSample> rows;
  json designs = json::array();
  for (const Scenario& scenario : scenarios)
    rows.push_back(measure_scenario(scenario, share, designs));
  const std::vector<BuildSample> builds =
      measure_builds(options.budget_seconds * (1.0 - kTraceShare));
  const std::vector<WorkSample> views = measure_views(share);
  Calibration calibration = calibration_from_measurements(rows, builds, shares_of(views));
  calibration.detail["designs"] = designs;
  const CostFit fit = fit_costs(rows);
  json validation = json::array();
  for (const WorkSample& view : views) validation.push_back(row_json(view, fit));
  calibration.detail["validation"] = validation;
  calibration.detail["budget_seconds"] = options.budget_seconds;
  calibration.detail["seed"] = options.seed;
  calibration.detail["seconds"] = seconds_since(start);
  return calibration;
}

}  // namespace gs
