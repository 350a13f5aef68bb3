#include "core/accel/uniform_grid.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "core/base/timing.h"

namespace gs {
namespace {

// Most cells the grid makes whatever --density asks (4 bytes of offsets each).
constexpr uint64_t kMaxCells = uint64_t{1} << 26;

}  // namespace

UniformGrid::UniformGrid(const AccelParams& params)
    : params_(params), kernel_(kernel_for(kernel_isa())) {}

void UniformGrid::build(const Scene& scene) {
  const auto start = Clock::now();
  input_ = BuildInput(scene);
  choose_resolution(input_.usable.size());
  const uint64_t wanted = cell_count();
  fit_budget();
  cells_over_budget_ = wanted - cell_count();
  fill_cells();
  input_.release_triangles();
  build_seconds_ = seconds_since(start);
}

// The paper's setting (§7): cbrt(N) cells per side, i.e. about N cells, here as cubic as
// the box allows: side s with prod(extent / s) = target over the axes longer than s (a flat
// scene gets one cell across its thin axis instead of cells thinner than its padding).
void UniformGrid::choose_resolution(size_t triangles) {
  n_[0] = n_[1] = n_[2] = 1;
  if (input_.clip.empty || triangles == 0) return;
  const double density = params_.density > 0.0 ? params_.density : 1.0;
  const double target = std::max(1.0, density * double(triangles));
  double extent[3];
  bool thin[3];
  for (int a = 0; a < 3; ++a) {
    extent[a] = input_.clip.hi[a] - input_.clip.lo[a];
    thin[a] = !(extent[a] > ClipBox::kMinCellPaddings * input_.clip.padding);
  }
  double side = 0.0;
  for (bool changed = true; changed;) {
    double volume = 1.0;
    int axes = 0;
    for (int a = 0; a < 3; ++a)
      if (!thin[a]) volume *= extent[a], ++axes;
    if (axes == 0) return;
    side = std::pow(volume / target, 1.0 / axes);
    changed = false;
    for (int a = 0; a < 3; ++a)
      if (!thin[a] && extent[a] < side) thin[a] = true, changed = true;
  }
  double cells = 1.0;
  for (int a = 0; a < 3; ++a) {
    const double most = std::floor(extent[a] / (ClipBox::kMinCellPaddings * input_.clip.padding));
    const double n = thin[a] ? 1.0 : std::clamp(std::round(extent[a] / side), 1.0, most);
    n_[a] = uint32_t(std::min(n, double(kMaxCells)));
    cells *= n_[a];
  }
  if (cells > double(kMaxCells)) shrink_to(double(kMaxCells));
}

// Every side of more than one cell scaled by the same factor so that about `cells` cells
// remain (at least one a side). A flat or long scene's grid has one or two such sides: a
// cube root would leave it far too fine (found by tests/fuzz: 10^7 walls for a 16 MB budget).
void UniformGrid::shrink_to(double cells) {
  int sides = 0;
  for (const uint32_t n : n_) sides += n > 1 ? 1 : 0;
  if (sides == 0) return;
  const double shrink = std::pow(cells / double(cell_count()), 1.0 / sides);
  for (uint32_t& n : n_) n = std::max<uint32_t>(1, uint32_t(n * shrink));
}

// What the grid's arrays take with `counts[c]` references in cell c: a leaf handle per
// cell, a leaf per occupied cell, and the walls.
uint64_t UniformGrid::grid_bytes(const std::vector<uint32_t>& counts) const {
  uint64_t bytes =
      sizeof(uint32_t) * cell_count() + sizeof(double) * (uint64_t(n_[0]) + n_[1] + n_[2] + 3);
  for (const uint32_t count : counts)
    if (count > 0) bytes += LeafStore::bytes_for(count);
  return bytes;
}

// The grid must fit the memory budget: fewer cells until its arrays do (thousands of
// coincident or huge triangles make many references per cell), down to one cell, which is
// built whatever the budget. Also keeps the references countable in 32 bits.
void UniformGrid::fit_budget() {
  if (grid_bytes({}) > params_.memory_budget)  // the empty cells alone do not fit
    shrink_to(double(params_.memory_budget) / (sizeof(uint32_t) + 3 * sizeof(double)));
  for (;;) {
    set_walls();
    const std::vector<uint32_t> counts = count_references();
    uint64_t refs = 0;
    for (const uint32_t count : counts) refs += count;
    const bool coarsest = n_[0] == 1 && n_[1] == 1 && n_[2] == 1;
    if (coarsest || (grid_bytes(counts) <= params_.memory_budget && refs < UINT32_MAX)) return;
    for (uint32_t& n : n_) n = std::max<uint32_t>(1, n / 2);
  }
}

// Walls from their integer index, never accumulated (as grid1d's grid_wall): the t of a
// wall does not drift along a long walk, and build and walk see the same coordinates.
void UniformGrid::set_walls() {
  for (int a = 0; a < 3; ++a) {
    const double lo = input_.clip.lo[a], extent = input_.clip.hi[a] - input_.clip.lo[a];
    walls_[a].resize(n_[a] + 1);
    for (uint32_t i = 0; i <= n_[a]; ++i) walls_[a][i] = lo + extent * (double(i) / double(n_[a]));
    scale_[a] = extent > 0.0 ? double(n_[a]) / extent : 0.0;
  }
}

// The cell holding coordinate p on an axis, clamped into the grid. Clamped first, then
// truncated: truncation is floor for what is left. Off by one only within rounding of a
// wall, which the triangles' padding covers.
uint32_t UniformGrid::locate(int axis, double p) const {
  const double cell = (p - input_.clip.lo[axis]) * scale_[axis];
  return uint32_t(std::clamp(cell, 0.0, double(n_[axis] - 1)));
}

// The cells whose closed extent [wall i, wall i+1] meets [lo, hi]: a box touching a wall
// goes into both cells.
void UniformGrid::cell_range(int axis, double lo, double hi, uint32_t& first,
                             uint32_t& last) const {
  const std::vector<double>& w = walls_[axis];
  const uint32_t n = n_[axis];
  first = locate(axis, lo);
  while (first > 0 && w[first] >= lo) --first;
  while (first + 1 < n && w[first + 1] < lo) ++first;
  last = locate(axis, hi);
  while (last + 1 < n && w[last + 1] <= hi) ++last;
  while (last > first && w[last] > hi) --last;
}

// Calls visit(cell) for every cell triangle `id`'s padded box meets.
template <class Visit>
void UniformGrid::each_cell(uint32_t id, Visit&& visit) const {
  const uint64_t nx = n_[0], nxy = uint64_t(n_[0]) * n_[1];
  const TriangleBox box = input_.box(id);
  uint32_t first[3], last[3];
  for (int a = 0; a < 3; ++a) cell_range(a, box[a], box[a + 3], first[a], last[a]);
  for (uint64_t z = first[2]; z <= last[2]; ++z)
    for (uint64_t y = first[1]; y <= last[1]; ++y)
      for (uint64_t x = first[0]; x <= last[0]; ++x) visit(x + nx * y + nxy * z);
}

std::vector<uint32_t> UniformGrid::count_references() const {
  std::vector<uint32_t> counts(cell_count(), 0);
  for (const uint32_t id : input_.usable) each_cell(id, [&](uint64_t c) { ++counts[c]; });
  return counts;
}

// Each cell's triangles, ids ascending, stored as its leaf; a triangle met in one cell only
// skips the mailbox there.
void UniformGrid::fill_cells() {
  const std::vector<uint32_t> counts = count_references();
  std::vector<uint64_t> offsets(counts.size() + 1, 0);
  for (size_t c = 0; c < counts.size(); ++c) offsets[c + 1] = offsets[c] + counts[c];
  std::vector<uint32_t> flat(offsets.back());
  std::vector<uint64_t> cursor(offsets.begin(), offsets.end() - 1);
  for (const uint32_t id : input_.usable) {
    uint64_t cells = 0;
    each_cell(id, [&](uint64_t) { ++cells; });
    const uint32_t entry = cells == 1 ? id | kOnlyHere : id;
    each_cell(id, [&](uint64_t c) { flat[cursor[c]++] = entry; });
  }
  references_ = flat.size();
  leaves_.reset(grid_bytes(counts));
  cell_leaf_.assign(counts.size(), kEmptyCell);
  std::vector<uint32_t> ids;
  for (size_t c = 0; c < counts.size(); ++c) {
    if (counts[c] == 0) continue;
    ids.assign(flat.begin() + int64_t(offsets[c]), flat.begin() + int64_t(offsets[c + 1]));
    cell_leaf_[c] = leaves_.add(ids, input_);
  }
}

std::unique_ptr<ThreadContext> UniformGrid::make_context() const {
  return std::make_unique<MailboxContext>();
}

Hit UniformGrid::intersect(const Ray& ray, ThreadContext& context) const {
  return trace<false>(ray, static_cast<MailboxContext&>(context));
}

Hit UniformGrid::any_hit(const Ray& ray, ThreadContext& context) const {
  return trace<true>(ray, static_cast<MailboxContext&>(context));
}

// Amanatides & Woo's 3D DDA along the line the kernel tests (start_walk): start in the cell
// where it enters the box, then step through the nearest wall. A hit may lie beyond the
// current cell, so the walk goes on until the cell's exit passes the nearest hit (plus the
// kernel's slack).
template <bool AnyHit>
Hit UniformGrid::trace(const Ray& ray, MailboxContext& context) const {
  Hit best;
  WalkLine line;
  if (!start_walk(input_.clip, ray, line)) return best;
  const RayBoxes boxes(ray, !line.far);
  const BoxFilter filter = BoxFilter::up_to_tmax(boxes, line, ray.tmax);
  const int64_t strides[3] = {1, int64_t(n_[0]), int64_t(n_[0]) * n_[1]};
  double t_next[3];
  int step[3];
  uint32_t cell[3];
  int64_t index = 0, stride[3];
  for (int a = 0; a < 3; ++a) {
    step[a] = step_of(ray.dir[a]);
    cell[a] = locate(a, line.origin[a] + line.t0 * line.dir[a]);
    t_next[a] = step[a] == 0
                    ? kInf
                    : (walls_[a][cell[a] + (step[a] > 0)] - line.origin[a]) * line.inv_dir[a];
    stride[a] = step[a] * strides[a];
    index += int64_t(cell[a]) * strides[a];
  }
  const PreparedRay<KernelReal> prepared(ray, line.shift, line.inv_dir);
  float tmax = ray.tmax;
  double stop = line.stop(tmax);
  const uint64_t ray_id = context.mailbox.next_ray();
  uint64_t steps = 0;
  for (;;) {
    const uint32_t leaf = cell_leaf_[index];
    if (leaf != kEmptyCell &&
        test_leaf<AnyHit>(leaves_.view(leaf), kernel_, prepared, filter, ray_id, tmax, best,
                          context.mailbox, context.counters)) {
      if (AnyHit) break;
      stop = line.stop(tmax);
    }
    // Selects, not branches: which axis comes next is unpredictable.
    const bool y_first = t_next[1] < t_next[0];
    const double t_xy = y_first ? t_next[1] : t_next[0];
    const bool z_first = t_next[2] < t_xy;
    const int s = z_first ? 2 : int(y_first);
    const double t_exit = z_first ? t_next[2] : t_xy;
    if (t_exit > stop || t_exit == kInf) break;
    cell[s] += uint32_t(step[s]);
    if (cell[s] >= n_[s]) break;  // left the grid (below 0 wraps around)
    index += stride[s];
    t_next[s] = (walls_[s][cell[s] + (step[s] > 0)] - line.origin[s]) * line.inv_dir[s];
    ++steps;
  }
  context.counters.traversal_steps += steps;
  return best;
}

StructureStats UniformGrid::stats() const {
  StructureStats s;
  s.nodes = cell_count();
  s.leaves = cell_count();
  s.voxels_subdivided = 0;
  s.traversal_states = std::nullopt;
  s.depth = 0;  // one level of cells
  s.memory_bytes = cell_leaf_.size() * sizeof(uint32_t) + leaves_.bytes() +
                   (walls_[0].size() + walls_[1].size() + walls_[2].size()) * sizeof(double);
  s.build_seconds = build_seconds_;
  s.voxels_over_budget = cells_over_budget_;
  return s;
}

}  // namespace gs
