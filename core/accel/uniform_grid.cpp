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

void UniformGrid::build(const Scene& scene) {
  const auto start = Clock::now();
  triangles_ = gather_triangles(scene);
  bounds_ = scene.bounds();
  box_ = ClipBox(bounds_);
  std::vector<uint32_t> usable;
  degenerate_ = 0;
  tri_box_ = box_.padded_boxes(triangles_);
  for (uint32_t id = 0; id < triangles_.size(); ++id) {
    if (scene.is_degenerate(id))
      ++degenerate_;
    else
      usable.push_back(id);
  }
  choose_resolution(usable.size());
  const uint64_t wanted = cell_count();
  fit_budget(usable);
  cells_over_budget_ = wanted - cell_count();
  sort_into_cells(usable, true);
  tri_box_ = {};
  build_seconds_ = seconds_since(start);
}

// The paper's setting (§7): cbrt(N) cells per side, i.e. about N cells, here as cubic as
// the box allows: side s with prod(extent / s) = target over the axes longer than s (a flat
// scene gets one cell across its thin axis instead of cells thinner than its padding).
void UniformGrid::choose_resolution(size_t triangles) {
  n_[0] = n_[1] = n_[2] = 1;
  if (box_.empty || triangles == 0) return;
  const double density = params_.density > 0.0 ? params_.density : 1.0;
  const double target = std::max(1.0, density * double(triangles));
  double extent[3];
  bool thin[3];
  for (int a = 0; a < 3; ++a) {
    extent[a] = box_.hi[a] - box_.lo[a];
    thin[a] = !(extent[a] > ClipBox::kMinCellPaddings * box_.padding);
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
    const double most = std::floor(extent[a] / (ClipBox::kMinCellPaddings * box_.padding));
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

// What the grid's arrays take with `refs` references: offsets, references and walls.
uint64_t UniformGrid::grid_bytes(uint64_t refs) const {
  return sizeof(uint32_t) * (cell_count() + 1 + refs) +
         sizeof(double) * (uint64_t(n_[0]) + n_[1] + n_[2] + 3);
}

// The grid must fit the memory budget: fewer cells until its arrays do (thousands of
// coincident or huge triangles make many references per cell), down to one cell, which is
// built whatever the budget. Also keeps the references countable in 32 bits.
void UniformGrid::fit_budget(const std::vector<uint32_t>& usable) {
  if (grid_bytes(0) > params_.memory_budget)  // the empty cells alone do not fit
    shrink_to(double(params_.memory_budget) / (sizeof(uint32_t) + 3 * sizeof(double)));
  for (;;) {
    set_walls();
    const uint64_t refs = sort_into_cells(usable, false);
    const bool coarsest = n_[0] == 1 && n_[1] == 1 && n_[2] == 1;
    if (coarsest || (grid_bytes(refs) <= params_.memory_budget && refs < UINT32_MAX)) return;
    for (uint32_t& n : n_) n = std::max<uint32_t>(1, n / 2);
  }
}

// Walls from their integer index, never accumulated (as grid1d's grid_wall): the t of a
// wall does not drift along a long walk, and build and walk see the same coordinates.
void UniformGrid::set_walls() {
  for (int a = 0; a < 3; ++a) {
    const double lo = box_.lo[a], extent = box_.hi[a] - box_.lo[a];
    walls_[a].resize(n_[a] + 1);
    for (uint32_t i = 0; i <= n_[a]; ++i) walls_[a][i] = lo + extent * (double(i) / double(n_[a]));
    scale_[a] = extent > 0.0 ? double(n_[a]) / extent : 0.0;
  }
}

// The cell holding coordinate p on an axis, clamped into the grid. Clamped first, then
// truncated: truncation is floor for what is left. Off by one only within rounding of a
// wall, which the triangles' padding covers.
uint32_t UniformGrid::locate(int axis, double p) const {
  const double cell = (p - box_.lo[axis]) * scale_[axis];
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

// Without `fill`: the number of references. With it: the CSR layout, counted per cell,
// summed to each cell's end, then filled backwards so that each cell lists ids ascending.
uint64_t UniformGrid::sort_into_cells(const std::vector<uint32_t>& usable, bool fill) {
  const uint64_t nx = n_[0], nxy = uint64_t(n_[0]) * n_[1];
  if (fill) offsets_.assign(cell_count() + 1, 0);
  uint64_t total = 0;
  for (int pass = fill ? 0 : 2; pass < 3; ++pass) {  // count, fill; or sum only
    if (pass == 1) {
      for (uint64_t c = 1; c <= cell_count(); ++c) offsets_[c] += offsets_[c - 1];
      tris_.resize(offsets_.back());
    }
    for (size_t k = 0; k < usable.size(); ++k) {
      const uint32_t id = pass == 1 ? usable[usable.size() - 1 - k] : usable[k];
      const double* box = &tri_box_[size_t(id) * 6];
      uint32_t first[3], last[3];
      for (int a = 0; a < 3; ++a) cell_range(a, box[a], box[a + 3], first[a], last[a]);
      if (pass == 2) {
        total +=
            uint64_t(last[0] - first[0] + 1) * (last[1] - first[1] + 1) * (last[2] - first[2] + 1);
        continue;
      }
      for (uint64_t z = first[2]; z <= last[2]; ++z)
        for (uint64_t y = first[1]; y <= last[1]; ++y)
          for (uint64_t x = first[0]; x <= last[0]; ++x) {
            const uint64_t c = x + nx * y + nxy * z;
            if (pass == 0)
              ++offsets_[c + 1];
            else
              tris_[--offsets_[c + 1]] = id;
          }
    }
  }
  if (fill) {  // offsets_[c + 1] now holds cell c's start: shift down one
    std::rotate(offsets_.begin(), offsets_.begin() + 1, offsets_.end());
    offsets_.back() = uint32_t(tris_.size());
    total = tris_.size();
  }
  return total;
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

// Amanatides & Woo's 3D DDA: clip to the box (exactly as brute), start in the cell where
// the ray enters, then step through the nearest wall. A hit may lie beyond the current cell,
// so the walk goes on until the cell's exit passes the nearest hit (plus the kernel's slack).
template <bool AnyHit>
Hit UniformGrid::trace(const Ray& ray, MailboxContext& context) const {
  Hit best;
  double t_enter, t_leave, inv_dir[3];
  if (!box_.clip(ray, t_enter, t_leave, inv_dir)) return best;
  const double slack = walk_slack(ray, box_.magnitude);
  const int64_t strides[3] = {1, int64_t(n_[0]), int64_t(n_[0]) * n_[1]};
  double origin[3], t_next[3];
  int step[3];
  uint32_t cell[3];
  int64_t index = 0, stride[3];
  for (int a = 0; a < 3; ++a) {
    origin[a] = ray.origin[a];
    step[a] = step_of(ray.dir[a]);
    cell[a] = locate(a, origin[a] + t_enter * double(ray.dir[a]));
    t_next[a] = step[a] == 0 ? kInf : (walls_[a][cell[a] + (step[a] > 0)] - origin[a]) * inv_dir[a];
    stride[a] = step[a] * strides[a];
    index += int64_t(cell[a]) * strides[a];
  }
  const PreparedRay<KernelReal> prepared(ray, t_enter);
  float tmax = ray.tmax;
  const uint64_t ray_id = context.next_ray();
  uint64_t steps = 0;
  for (;;) {
    const uint32_t begin = offsets_[index], count = offsets_[index + 1] - begin;
    if (test_triangles<AnyHit>(tris_.data() + begin, count, triangles_.data(), prepared, ray_id,
                               tmax, best, context) &&
        AnyHit)
      break;
    // Selects, not branches: which axis comes next is unpredictable.
    const bool y_first = t_next[1] < t_next[0];
    const double t_xy = y_first ? t_next[1] : t_next[0];
    const bool z_first = t_next[2] < t_xy;
    const int s = z_first ? 2 : int(y_first);
    const double t_exit = z_first ? t_next[2] : t_xy;
    if (t_exit > stop_distance(tmax, slack) || t_exit == kInf) break;
    cell[s] += uint32_t(step[s]);
    if (cell[s] >= n_[s]) break;  // left the grid (below 0 wraps around)
    index += stride[s];
    t_next[s] = (walls_[s][cell[s] + (step[s] > 0)] - origin[s]) * inv_dir[s];
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
  s.memory_bytes = triangles_.size() * sizeof(TriangleVerts) +
                   (offsets_.size() + tris_.size()) * sizeof(uint32_t) +
                   (walls_[0].size() + walls_[1].size() + walls_[2].size()) * sizeof(double);
  s.build_seconds = build_seconds_;
  s.voxels_over_budget = cells_over_budget_;
  return s;
}

}  // namespace gs
