#include "core/accel/grid3d.h"

#include <algorithm>
#include <cfloat>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/base/timing.h"

namespace gs {
namespace {

// Most cells per side of one grid.
constexpr int kMaxResolution = 1024;
// A grid whose cells would hold more than this many references per triangle (thousands
// of coincident triangles, large triangles spanning a whole layer of cells) is retried at
// half the resolution, and a sub-grid that still does is not built: it would cost memory
// and separate nothing. Bounds a grid's references by 8x its triangles.
constexpr double kMaxRefsPerTriangle = 8.0;

// The cell of a grid axis holding coordinate x, clamped to the grid. Clamped first, then
// truncated: truncation is floor for what is left.
int32_t locate(double x, double lo, double inv_width, int32_t res) {
  return int32_t(std::clamp((x - lo) * inv_width, 0.0, double(res - 1)));
}

}  // namespace

// A grid being planned: its box, resolution, each triangle's cell range and the
// references that makes.
struct NestedGrid::Plan {
  double lo[3], hi[3];
  std::array<int32_t, 3> res{1, 1, 1};
  std::vector<std::array<int32_t, 6>> ranges;  // per triangle first xyz, last xyz
  std::vector<uint32_t> ids;
  uint64_t refs = 0;
};

// One ray's walk, shared by every level: the ray in double, the kernel's prepared ray and
// the nearest hit so far.
struct NestedGrid::RayWalk {
  WalkLine line;  // the line the kernel tests (start_walk); t is measured along it
  int step[3];
  double stop;  // the stop distance of the nearest hit so far (or of tmax)
  float tmax;
  uint64_t ray_id;
  const PreparedRay<KernelReal>* prepared;
  BoxFilter filter;  // the leaf loop's triangle box test
  Hit best;
};

NestedGrid::NestedGrid(const AccelParams& params)
    : params_(params),
      leaf_size_(params.leaf_size_or(kDefaultLeafSize)),
      max_depth_(std::min(params.depth_or(kDefaultMaxDepth), kMaxDepthCap)),
      // Address space only (committed as touched); at least 4 GiB each so that the root
      // grid, which is built whatever the budget, always fits.
      kernel_(kernel_for(kernel_isa())),
      grids_(std::max(params.memory_budget, uint64_t{1} << 32)),
      cells_(std::max(params.memory_budget, uint64_t{1} << 32)),
      leaves_(std::max(params.memory_budget, uint64_t{1} << 32)) {}

NestedGrid::~NestedGrid() = default;

void NestedGrid::build(const Scene& scene) {
  const auto start = Clock::now();
  input_ = BuildInput(scene);
  const ClipBox& root = input_.clip;
  has_root_ = !input_.usable.empty() && !root.empty;
  if (has_root_) {
    // The root grid is built up front, whatever the budget: there must be one.
    Plan plan;
    plan_grid(root.lo, root.hi, input_.usable, 1, plan);
    uint32_t root_id = 0;
    if (!commit(plan, 1, root_id))
      throw std::runtime_error("grid3d: the root grid does not fit in 32-bit indices");
  }
  build_seconds_ = seconds_since(start);
}

void NestedGrid::build_all() {
  const auto start = Clock::now();
  MailboxContext context;
  // Sub-grids append their cells at the end, so one pass in order reaches them all.
  for (size_t id = 0; id < cells_.size(); ++id)
    if (cells_[id].status.load(std::memory_order_acquire) == kUnexamined)
      examine(uint32_t(id), context);
  build_seconds_ += seconds_since(start);
}

std::unique_ptr<ThreadContext> NestedGrid::make_context() const {
  return std::make_unique<MailboxContext>();
}

Hit NestedGrid::intersect(const Ray& ray, ThreadContext& context) const {
  return trace<false>(ray, static_cast<MailboxContext&>(context));
}

Hit NestedGrid::any_hit(const Ray& ray, ThreadContext& context) const {
  return trace<true>(ray, static_cast<MailboxContext&>(context));
}

// Clips the ray to the scene box exactly as brute does, then walks the root grid along
// the line the kernel tests (start_walk).
template <bool AnyHit>
Hit NestedGrid::trace(const Ray& ray, MailboxContext& context) const {
  RayWalk w;
  if (!has_root_ || !start_walk(input_.clip, ray, w.line)) return Hit{};
  for (int a = 0; a < 3; ++a) w.step[a] = step_of(ray.dir[a]);
  w.tmax = ray.tmax;
  w.stop = w.line.stop(w.tmax);
  w.ray_id = context.mailbox.next_ray();
  const PreparedRay<KernelReal> prepared(ray, w.line.shift, w.line.inv_dir);
  w.prepared = &prepared;
  const RayBoxes boxes(ray, !w.line.far);
  w.filter = BoxFilter::up_to_tmax(boxes, w.line, ray.tmax);
  walk<AnyHit>(0, w.line.t0, -1, w, context);
  return w.best;
}

// The 3D DDA over one grid from the ray's point at t_cur (entered through a wall on
// `entered_axis`, or -1 when located by its point). Returns true when the whole walk is
// over (the nearest hit lies before the current cell's exit, or any-hit found one), false
// when the ray has left this grid and the parent's DDA resumes.
template <bool AnyHit>
bool NestedGrid::walk(uint32_t grid_id, double t_cur, int entered_axis, RayWalk& w,
                      MailboxContext& context) const {
  const GridNode& g = grids_[grid_id];
  int32_t index[3];
  double t_origin[3] = {0, 0, 0}, t_width[3] = {0, 0, 0}, t_next[3];
  for (int a = 0; a < 3; ++a) {
    if (a == entered_axis)
      index[a] = w.step[a] > 0 ? 0 : g.res[a] - 1;
    else
      index[a] =
          locate(w.line.origin[a] + t_cur * w.line.dir[a], g.lo[a], g.inv_width[a], g.res[a]);
    if (w.step[a] == 0) {
      t_next[a] = kInf;
      continue;
    }
    // Wall I lies at lo + I * width: its distance comes from the integer index.
    t_origin[a] = (g.lo[a] - w.line.origin[a]) * w.line.inv_dir[a];
    t_width[a] = g.width[a] * w.line.inv_dir[a];
    t_next[a] = t_origin[a] + double(index[a] + (w.step[a] > 0)) * t_width[a];
  }
  for (;;) {
    const uint32_t id =
        g.first_cell + uint32_t((index[2] * g.res[1] + index[1]) * g.res[0] + index[0]);
    const Cell& cell = cells_[id];
    uint8_t status = cell.status.load(std::memory_order_acquire);
    if (status == kUnexamined) status = examine(id, context);
    if (status == kSplit) {
      if (walk<AnyHit>(cell.child, t_cur, entered_axis, w, context)) return true;
    } else if (test_cell<AnyHit>(cell, w, context)) {
      if (AnyHit) return true;
      w.stop = w.line.stop(w.tmax);
    }
    const int s =
        t_next[1] < t_next[0] ? (t_next[2] < t_next[1] ? 2 : 1) : (t_next[2] < t_next[0] ? 2 : 0);
    const double t_exit = t_next[s];
    if (t_exit > w.stop) return true;
    index[s] += w.step[s];
    if (index[s] < 0 || index[s] >= g.res[s]) return false;
    t_next[s] = t_origin[s] + double(index[s] + (w.step[s] > 0)) * t_width[s];
    t_cur = t_exit, entered_axis = s;
    ++context.counters.traversal_steps;
  }
}

// Tests the cell's triangles not yet tested by this ray, keeping the nearest hit (lowest
// id among equal t) wherever it lies; true when one was hit.
template <bool AnyHit>
bool NestedGrid::test_cell(const Cell& cell, RayWalk& w, MailboxContext& context) const {
  return cell.ref_count > 0 &&
         test_leaf<AnyHit>(leaves_.view(cell.leaf), kernel_, *w.prepared, w.filter, w.ray_id,
                           w.tmax, w.best, context.mailbox, context.counters);
}

// The lazy build of one cell (docs/design.md §1.7): the thread that wins the CAS
// builds the sub-grid and publishes it with a release store; others meanwhile search the
// cell as the leaf it still is, so nobody waits.
uint8_t NestedGrid::examine(uint32_t cell_id, MailboxContext& context) const {
  Cell& cell = cells_[cell_id];
  uint8_t expected = kUnexamined;
  if (!cell.status.compare_exchange_strong(expected, kBuilding, std::memory_order_acquire))
    return expected;
  const auto start = Clock::now();
  const uint8_t status = subdivide(cell_id) ? kSplit : kLeaf;
  cell.status.store(status, std::memory_order_release);
  ++context.counters.voxels_built;
  context.counters.lazy_build_seconds += seconds_since(start);
  return status;
}

// Builds the cell's sub-grid; false (the cell stays a leaf) when no grid pays or the
// memory budget is spent. A pure function of the cell (its box and triangles) and the
// parameters, so lazy, eager and any number of threads build the same grids.
bool NestedGrid::subdivide(uint32_t cell_id) const {
  Cell& cell = cells_[cell_id];
  const GridNode& owner = grids_[cell.child];  // before kSplit, `child` names the owner
  double lo[3], hi[3];
  cell_box(owner, cell_id - owner.first_cell, lo, hi);
  std::vector<uint32_t> ids(cell.ref_count);
  const LeafView leaf = leaves_.view(cell.leaf);
  for (uint32_t i = 0; i < cell.ref_count; ++i) ids[i] = leaf.id(i);
  Plan plan;
  if (!plan_grid(lo, hi, ids, 2, plan)) return false;
  uint32_t grid_id = 0;
  if (!commit(plan, owner.depth + 1, grid_id)) {
    ++over_budget_;
    return false;
  }
  cell.child = grid_id;
  ++subdivided_;
  return true;
}

// Resolution: about cbrt(n) cells on the longest side (at least `min_long_side`), the
// other sides in proportion so that cells are as cubic as the box allows (the uniform grid
// of Jevans 1990 §7, applied again inside each crowded cell as Jevans & Wyvill 1989 do).
// Halved while the triangles would make too many references; false when a sub-grid
// (min_long_side 2) cannot be had.
bool NestedGrid::plan_grid(const double lo[3], const double hi[3], const std::vector<uint32_t>& ids,
                           int min_long_side, Plan& plan) const {
  double extent[3], longest = 0.0;
  for (int a = 0; a < 3; ++a) {
    extent[a] = hi[a] - lo[a];
    longest = std::max(longest, extent[a]);
  }
  const double min_width = input_.clip.min_cell_width(lo, hi);
  int r =
      std::clamp(int(std::lround(std::cbrt(double(ids.size())))), min_long_side, kMaxResolution);
  for (;;) {
    std::array<int32_t, 3> res{};
    int64_t cells = 1;
    for (int a = 0; a < 3; ++a) {
      const double thin_limit = min_width > 0.0 ? std::floor(extent[a] / min_width) : 1.0;
      const double wanted = longest > 0.0 ? std::round(extent[a] * r / longest) : 1.0;
      res[a] = int32_t(std::clamp(std::min(wanted, thin_limit), 1.0, double(r)));
      cells *= res[a];
    }
    if (cells < 2 && min_long_side >= 2) return false;
    sort_into(lo, hi, res, ids, plan);
    if (double(plan.refs) <= kMaxRefsPerTriangle * double(ids.size()) || cells == 1) return true;
    if (r <= min_long_side) return false;
    r = std::max(min_long_side, r / 2);
  }
}

// Each triangle's range of cells by its padded box (closed intervals, so a triangle on a
// wall goes into both cells), and the references they make.
void NestedGrid::sort_into(const double lo[3], const double hi[3],
                           const std::array<int32_t, 3>& res, const std::vector<uint32_t>& ids,
                           Plan& plan) const {
  std::copy(lo, lo + 3, plan.lo);
  std::copy(hi, hi + 3, plan.hi);
  plan.res = res;
  plan.ids = ids;
  plan.ranges.resize(ids.size());
  plan.refs = 0;
  for (size_t i = 0; i < ids.size(); ++i) {
    const TriangleBox box = input_.box(ids[i]);
    uint64_t count = 1;
    for (int a = 0; a < 3; ++a) {
      const double inv_width = double(res[a]) / (hi[a] - lo[a]);
      plan.ranges[i][a] = locate(box[a], lo[a], inv_width, res[a]);
      plan.ranges[i][a + 3] = locate(box[a + 3], lo[a], inv_width, res[a]);
      count *= uint64_t(plan.ranges[i][a + 3] - plan.ranges[i][a] + 1);
    }
    plan.refs += count;
  }
}

namespace {

// Offsets (cells + 1) of each cell's references in cell order, and the flat list of
// triangle ids, in the plan's triangle order within each cell.
void fill_cells(const std::vector<std::array<int32_t, 6>>& ranges, const std::vector<uint32_t>& ids,
                const std::array<int32_t, 3>& res, std::vector<uint32_t>& offsets,
                std::vector<uint32_t>& flat) {
  const size_t cells = size_t(res[0]) * res[1] * res[2];
  offsets.assign(cells + 1, 0);
  const auto each_cell = [&](const std::array<int32_t, 6>& r, auto&& f) {
    for (int32_t z = r[2]; z <= r[5]; ++z)
      for (int32_t y = r[1]; y <= r[4]; ++y)
        for (int32_t x = r[0]; x <= r[3]; ++x) f((size_t(z) * res[1] + y) * res[0] + x);
  };
  for (const auto& r : ranges) each_cell(r, [&](size_t c) { ++offsets[c + 1]; });
  for (size_t c = 0; c < cells; ++c) offsets[c + 1] += offsets[c];
  flat.resize(offsets[cells]);
  std::vector<uint32_t> cursor(offsets.begin(), offsets.end() - 1);
  for (size_t i = 0; i < ids.size(); ++i)
    each_cell(ranges[i], [&](size_t c) { flat[cursor[c]++] = ids[i]; });
}

}  // namespace

// Appends the planned grid, its cells and their packed triangles; false (nothing
// published) when they do not fit the memory budget or the 32-bit indices.
bool NestedGrid::commit(const Plan& plan, uint32_t depth, uint32_t& grid_id) const {
  const size_t cells = size_t(plan.res[0]) * plan.res[1] * plan.res[2];
  const uint64_t bytes = sizeof(GridNode) + cells * (sizeof(Cell) + LeafStore::bytes_for(0)) +
                         plan.refs * (LeafStore::bytes_for(1) - LeafStore::bytes_for(0));
  const bool root = depth == 1;
  if (cells_.size() + cells >= UINT32_MAX) return false;
  if (root)
    bytes_used_ += bytes;
  else if (!reserve_bytes(bytes))
    return false;
  std::vector<uint32_t> offsets, flat;
  fill_cells(plan.ranges, plan.ids, plan.res, offsets, flat);
  const size_t g = grids_.append(1), first_cell = cells_.append(cells);
  if (g == SIZE_MAX || first_cell == SIZE_MAX) return false;
  GridNode& grid = grids_[g];
  for (int a = 0; a < 3; ++a) {
    grid.lo[a] = plan.lo[a], grid.hi[a] = plan.hi[a], grid.res[a] = plan.res[a];
    grid.width[a] = (plan.hi[a] - plan.lo[a]) / plan.res[a];
    grid.inv_width[a] = plan.res[a] / (plan.hi[a] - plan.lo[a]);
  }
  grid.first_cell = uint32_t(first_cell);
  grid.depth = depth;
  raise_to(deepest_, depth - 1);
  const bool may_split = int(depth) < max_depth_;
  for (size_t c = 0; c < cells; ++c) {
    Cell& cell = cells_[first_cell + c];
    cell.ref_count = offsets[c + 1] - offsets[c];
    cell.child = uint32_t(g);  // the owner, until the cell gets a sub-grid
    const bool crowded = may_split && cell.ref_count > uint32_t(leaf_size_);
    cell.status.store(crowded ? kUnexamined : kLeaf, std::memory_order_relaxed);
    if (cell.ref_count == 0) continue;
    double lo[3], hi[3];
    cell_box(grid, uint32_t(c), lo, hi);
    std::vector<uint32_t> ids(flat.begin() + offsets[c], flat.begin() + offsets[c + 1]);
    for (uint32_t& id : ids) {
      const TriangleBox box = input_.box(id);
      bool inside = true;
      for (int a = 0; a < 3; ++a) inside &= box[a] >= lo[a] && box[a + 3] <= hi[a];
      if (inside) id |= kOnlyHere;
    }
    cell.leaf = leaves_.add(ids, input_);
    if (cell.leaf == LeafStore::kFull) return false;
  }
  grid_id = uint32_t(g);
  return true;
}

// A cell's box from its integer position (the last cell ends exactly on the grid's wall).
void NestedGrid::cell_box(const GridNode& grid, uint32_t local, double lo[3], double hi[3]) const {
  const uint32_t index[3] = {local % uint32_t(grid.res[0]),
                             (local / uint32_t(grid.res[0])) % uint32_t(grid.res[1]),
                             local / uint32_t(grid.res[0] * grid.res[1])};
  for (int a = 0; a < 3; ++a) {
    lo[a] = grid.lo[a] + double(index[a]) * grid.width[a];
    hi[a] = int32_t(index[a]) + 1 == grid.res[a]
                ? grid.hi[a]
                : grid.lo[a] + double(index[a] + 1) * grid.width[a];
  }
}

// Counts `bytes` against the memory budget; false (nothing counted) when they do not fit.
bool NestedGrid::reserve_bytes(uint64_t bytes) const {
  uint64_t used = bytes_used_.load(std::memory_order_relaxed);
  do {
    if (used + bytes > params_.memory_budget) return false;
  } while (!bytes_used_.compare_exchange_weak(used, used + bytes, std::memory_order_relaxed));
  return true;
}

StructureStats NestedGrid::stats() const {
  StructureStats s;
  s.nodes = grids_.size() + cells_.size();
  s.voxels_subdivided = subdivided_.load();
  s.leaves = cells_.size() - subdivided_.load();
  s.traversal_states = std::nullopt;
  s.depth = deepest_.load();
  s.memory_bytes = bytes_used_.load() + input_.triangles.size() * sizeof(TriangleVerts);
  s.build_seconds = build_seconds_;
  s.voxels_over_budget = over_budget_.load();
  return s;
}

}  // namespace gs
