#include "core/accel/grid1d/grid1d.h"

#include <algorithm>
#include <cfloat>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/accel/grid1d/cost_model.h"
#include "core/base/error.h"
#include "core/base/timing.h"

namespace gs {
namespace {

// Absolute granularities stay exact integers in double (wall = x0 + E * (I / G)).
constexpr uint64_t kMaxAbsoluteGranularity = uint64_t{1} << 50;

// A wall of the global grid (origin, extent, granularity). Computed from the integer index
// so that one physical wall has bit-identical coordinates at every level: I / G is the
// correctly rounded quotient, the same for every (I, G) naming the same fraction.
double grid_wall(double origin, double extent, uint64_t index, uint64_t granularity) {
  return origin + extent * (double(index) / double(granularity));
}

double surface_area(const double extent[3]) {
  return 2.0 * (extent[0] * extent[1] + extent[1] * extent[2] + extent[2] * extent[0]);
}

}  // namespace

// Where a voxel is and what the build knows about it. Cold data: read only when the voxel
// is examined. Immutable once its parent is published.
struct Grid1D::Region {
  uint64_t cell[3];   // the voxel's slab on each axis's grid...
  uint64_t grid[3];   // ... of this granularity (1: the scene box)
  uint32_t above[3];  // nearest ancestor cut along each axis (kNone: the scene box)
  uint32_t depth;
  uint32_t sample_begin, sample_count;  // sample rays whose segments cross the voxel
  double area_rays;                     // rays estimated from the parent by surface area (§6.5)
};

// A ray of the sampling pass: its segment [t0, t1] inside the scene box; t1 shrinks to
// the ray's hit once the pass has traced it.
struct Grid1D::SampleRay {
  Ray ray;
  double origin[3], dir[3];
  double t0, t1;
};

// The outcome of the cost function for one voxel: the chosen axis and g, and the contents
// of each cell (offsets into the flat lists, g + 1 entries each).
struct Grid1D::Cut {
  int axis = 0;
  int granularity = 0;  // < 2: stays a leaf
  std::vector<uint32_t> tri_offsets, tris;
  std::vector<uint32_t> sample_offsets, samples;
  double rays = 0;
};

// A ray's per-thread traversal scratch. Mailboxes and state values belong to the thread:
// the paper's per-object stamp would race between threads (DESIGN.md §1). Ray ids are 64
// bits so that stamps never wrap.
// Cache-line aligned: two threads' contexts must not share a line (false sharing).
class alignas(64) Grid1D::Context final : public ThreadContext {
 public:
  // The ray's position on one global grid (the paper's dist, delta and index): its slab
  // and the distance to the slab's exit, valid for the ray `stamp` while t < t_next (the
  // ray moves monotonically). Wall distances are t_origin + I * t_width from the integer
  // wall index I, never accumulated, so they do not drift along a long walk.
  struct StateValues {
    uint64_t stamp = 0;
    int64_t index = 0;
    double t_next = 0.0;
    double t_origin = 0.0;  // distance to the grid's wall 0
    double t_width = 0.0;   // distance between walls (signed like the direction)
    uint64_t rays = 0;      // rays of this thread that used the state (for the states table)
    double exit_distance(int64_t slab, int step) const {
      return t_origin + double(step > 0 ? slab + 1 : slab) * t_width;
    }
  };

  explicit Context(const Grid1D& grid) : grid_(grid) {}
  ~Context() override {
    for (uint32_t id = 0; id < states.size(); ++id)
      if (states[id].rays)
        grid_.state_rays_[id].fetch_add(states[id].rays, std::memory_order_relaxed);
  }

  // Ray-id mailboxing (§6.4) in a small direct-mapped table rather than a stamp per
  // triangle: it stays in L1 whatever the scene's size. A collision only costs a repeated
  // test, whose answer is the same.
  bool already_tested(uint32_t triangle, uint64_t ray) {
    const size_t slot = triangle & (kMailboxSlots - 1);
    if (mailbox_ray[slot] == ray && mailbox_triangle[slot] == triangle) return true;
    mailbox_ray[slot] = ray, mailbox_triangle[slot] = triangle;
    return false;
  }
  // A state first met by this thread grows the table. The size is kept beside the vector:
  // vector::size() divides by the record's size on every descent.
  StateValues& state(uint32_t id) {
    if (id >= state_count) states.resize(state_count = size_t(id) + 64);
    return states[id];
  }

  static constexpr size_t kMailboxSlots = 256;
  uint64_t mailbox_ray[kMailboxSlots] = {};
  uint32_t mailbox_triangle[kMailboxSlots] = {};
  std::vector<StateValues> states;
  size_t state_count = 0;
  uint64_t ray_id = 0;

 private:
  const Grid1D& grid_;
};

// One ray's walk: its origin and direction in double and, per axis, the voxel whose
// traversal state gives the ray's current slab on that axis (§5.3: the current voxel's own
// axis and the "voxels above" on the two others).
struct Grid1D::RayWalk {
  double origin[3], dir[3], inv_dir[3];
  int step[3];  // +1, -1, or 0 where the direction component is zero
  uint32_t active[3];
  uint32_t active_state[3];
  double t_next[3];  // the active states' t_next, kept at hand for choosing the step axis
  uint64_t ray_id;
};

// The timed path's recorder: every hook compiles to nothing.
struct NullRecorder {
  void descent(uint32_t /*voxel*/, int64_t /*cell*/, StateCase /*state_case*/) {}
  void cell(uint32_t /*voxel*/, double /*t_enter*/, int /*axis*/, uint32_t /*climbed*/) {}
  void tested() {}
  void rejected() {}
  void searched(int32_t /*best*/) {}
};

// Fills a Walk from the hooks the traversal calls (DESIGN.md §2: the viewer's walk is the
// same code that renders).
class Grid1D::WalkRecorder {
 public:
  WalkRecorder(const Grid1D& grid, Walk& walk) : grid_(grid), walk_(walk) {}
  void descent(uint32_t voxel, int64_t cell, StateCase state_case) {
    const Voxel& v = grid_.voxels_[voxel];
    pending_.push_back({voxel, grid_.regions_[voxel].depth, v.axis, v.granularity,
                        grid_.states_[v.state].granularity, v.state, cell, state_case});
  }
  void cell(uint32_t voxel, double t_enter, int axis, uint32_t climbed) {
    WalkCell cell;
    cell.voxel = voxel;
    cell.depth = grid_.regions_[voxel].depth;
    grid_.voxel_box(voxel, cell.lo, cell.hi);
    cell.t_enter = t_enter;
    cell.entered_axis = axis;
    cell.climbed = climbed;
    cell.descents = std::move(pending_);
    pending_.clear();
    cell.hit = walk_.cells.empty() ? -1 : walk_.cells.back().hit;
    walk_.cells.push_back(std::move(cell));
  }
  void tested() { ++walk_.cells.back().tests; }
  void rejected() { ++walk_.cells.back().rejections; }
  void searched(int32_t best) { walk_.cells.back().hit = best; }

 private:
  const Grid1D& grid_;
  Walk& walk_;
  std::vector<WalkDescent> pending_;
};

Grid1D::Grid1D(const AccelParams& params)
    : params_(params),
      voxels_(params.memory_budget),
      regions_(params.memory_budget),
      tri_indices_(params.memory_budget),
      packed_(params.memory_budget),
      sample_indices_(params.memory_budget),
      states_(std::min<uint64_t>(params.memory_budget, uint64_t{64} << 20)),
      state_rays_(std::min<uint64_t>(params.memory_budget, uint64_t{64} << 20)) {}

Grid1D::~Grid1D() = default;

uint32_t Grid1D::voxel_depth(uint32_t id) const { return regions_[id].depth; }

uint64_t Grid1D::state_rays(uint32_t state) const {
  return state_rays_[state].load(std::memory_order_relaxed);
}

void Grid1D::voxel_box(uint32_t id, double lo[3], double hi[3]) const {
  const Region& region = regions_[id];
  for (int a = 0; a < 3; ++a) {
    const double origin = root_.lo[a], extent = root_.hi[a] - root_.lo[a];
    lo[a] = grid_wall(origin, extent, region.cell[a], region.grid[a]);
    hi[a] = grid_wall(origin, extent, region.cell[a] + 1, region.grid[a]);
  }
}

// The root voxel's records and triangle list (and the sample's index list) are the least the
// structure can be: a budget that cannot hold them is a usage error, not a silent leaf.
size_t Grid1D::fits_budget(size_t first, const char* what) const {
  if (first == SIZE_MAX)
    throw UsageError("--memory-budget " + std::to_string(params_.memory_budget) +
                     " bytes cannot hold grid1d's root voxel (" + what + ")");
  return first;
}

void Grid1D::build(const Scene& scene) {
  const auto start = Clock::now();
  triangles_ = gather_triangles(scene);
  bounds_ = scene.bounds();
  root_ = ClipBox(bounds_);
  std::vector<uint32_t> usable;
  tri_box_ = root_.padded_boxes(triangles_);
  for (uint32_t id = 0; id < triangles_.size(); ++id) {
    if (scene.is_degenerate(id))
      ++degenerate_;
    else
      usable.push_back(id);
  }
  for (uint32_t a = 0; a < 3; ++a) state_for(a, 1);  // states 0, 1, 2: the box on each axis
  const auto root = uint32_t(fits_budget(voxels_.append(1), "its record"));
  if (!regions_.construct(root, 1)) fits_budget(SIZE_MAX, "its region");
  Voxel& voxel = voxels_[root];
  voxel.tri_begin = uint32_t(fits_budget(tri_indices_.append(usable.size()), "its triangle list"));
  voxel.tri_count = uint32_t(usable.size());
  std::copy(usable.begin(), usable.end(), &tri_indices_[voxel.tri_begin]);
  Region& region = regions_[root];
  for (int a = 0; a < 3; ++a) region.cell[a] = 0, region.grid[a] = 1, region.above[a] = kNone;
  region.area_rays = kInf;  // no sampling pass: assume plenty of rays
  bytes_used_ = sizeof(Voxel) + sizeof(Region) + usable.size() * sizeof(uint32_t);
  build_seconds_ = seconds_since(start);
}

void Grid1D::sample(std::span<const Ray> sample_rays, double rays_in_run) {
  if (voxels_[0].status.load() != kUnexamined)
    throw std::logic_error("Grid1D::sample must come before any tracing or build_all");
  const auto start = Clock::now();
  for (const Ray& ray : sample_rays) {
    SampleRay s{};
    s.ray = ray;
    if (!root_.clip(ray, s.t0, s.t1)) continue;
    for (int a = 0; a < 3; ++a) s.origin[a] = ray.origin[a], s.dir[a] = ray.dir[a];
    sample_.push_back(s);
  }
  sampled_ = true;
  rays_per_sample_ = sample_rays.empty() ? 0.0 : rays_in_run / double(sample_rays.size());
  Region& root = regions_[0];
  root.area_rays = rays_in_run;  // used only if no sample segment crosses the box
  root.sample_count = uint32_t(sample_.size());
  root.sample_begin =
      uint32_t(fits_budget(sample_indices_.append(sample_.size()), "the sampling pass's rays"));
  for (uint32_t j = 0; j < sample_.size(); ++j) sample_indices_[root.sample_begin + j] = j;
  bytes_used_ += sample_.size() * sizeof(uint32_t);

  // The breadth of the paper's pass is the sample; its order is fixed (ray order, one
  // thread), so every cut it makes is a function of the sample alone.
  Context context(*this);
  for (SampleRay& s : sample_) {
    NullRecorder none;
    const Hit hit = trace<false>(s.ray, context, none);
    if (hit.found()) s.t1 = std::min(s.t1, double(hit.t));
  }
  build_seconds_ += seconds_since(start);
}

void Grid1D::build_all() {
  const auto start = Clock::now();
  Context context(*this);
  std::vector<uint32_t> stack{0};
  while (!stack.empty()) {
    const uint32_t id = stack.back();
    stack.pop_back();
    uint8_t status = voxels_[id].status.load(std::memory_order_acquire);
    if (status == kUnexamined) status = examine(id, context);
    if (status != kSplit) continue;
    const Voxel& voxel = voxels_[id];
    for (uint32_t i = 0; i < voxel.granularity; ++i) stack.push_back(voxel.first_child + i);
  }
  build_seconds_ += seconds_since(start);
}

std::unique_ptr<ThreadContext> Grid1D::make_context() const {
  return std::make_unique<Context>(*this);
}

Hit Grid1D::intersect(const Ray& ray, ThreadContext& context) const {
  NullRecorder none;
  return trace<false>(ray, static_cast<Context&>(context), none);
}

Hit Grid1D::any_hit(const Ray& ray, ThreadContext& context) const {
  NullRecorder none;
  return trace<true>(ray, static_cast<Context&>(context), none);
}

std::optional<Walk> Grid1D::record_walk(const Ray& ray, ThreadContext& context) const {
  Walk walk;
  walk.ray = ray;
  WalkRecorder recorder(*this, walk);
  walk.hit = trace<false>(ray, static_cast<Context&>(context), recorder);
  return walk;
}

// §5: clip the ray to the scene box, descend to the leaf where it enters (vertical
// traversal), then step cell by cell along the axis whose next wall is nearest
// (horizontal traversal), climbing to the voxel above when a step leaves a 1D array.
template <bool AnyHit, class Recorder>
Hit Grid1D::trace(const Ray& ray, Context& context, Recorder& recorder) const {
  Hit best;
  double t_enter, t_leave;
  RayWalk walk;
  if (!root_.clip(ray, t_enter, t_leave, walk.inv_dir)) return best;
  for (int a = 0; a < 3; ++a) {
    walk.origin[a] = ray.origin[a], walk.dir[a] = ray.dir[a];
    walk.step[a] = walk.dir[a] > 0.0 ? 1 : walk.dir[a] < 0.0 ? -1 : 0;
  }
  const double slack = walk_slack(ray, root_.magnitude);
  walk.ray_id = ++context.ray_id;
  for (uint32_t a = 0; a < 3; ++a) {
    Context::StateValues& box = context.state(a);
    box.stamp = walk.ray_id, box.index = 0;
    const double exit_wall = walk.step[a] > 0 ? root_.hi[a] : root_.lo[a];
    box.t_next = walk.step[a] == 0 ? kInf : (exit_wall - walk.origin[a]) * walk.inv_dir[a];
    walk.active[a] = kNone, walk.active_state[a] = a, walk.t_next[a] = box.t_next;
  }

  const PreparedRay<KernelReal> prepared(ray, t_enter);
  float tmax = ray.tmax;
  // Changes only with tmax: computed per hit rather than per step (nextafter is a libm call).
  double stop = stop_distance(tmax, slack);
  TraceCounters& counters = context.counters;
  uint8_t status;
  uint32_t leaf = descend(0, t_enter, -1, walk, context, status, recorder);
  recorder.cell(leaf, t_enter, -1, 0);
  for (;;) {
    const bool found =
        test_leaf<AnyHit>(leaf, status, prepared, walk.ray_id, tmax, best, context, recorder);
    recorder.searched(best.id);
    if (AnyHit && found) return best;
    if (found) stop = stop_distance(tmax, slack);
    // Leave the cell through its nearest wall, unless the nearest hit lies before it.
    // Written as selects, not branches: which axis comes next is unpredictable.
    const bool y_first = walk.t_next[1] < walk.t_next[0];
    const double t_xy = y_first ? walk.t_next[1] : walk.t_next[0];
    const bool z_first = walk.t_next[2] < t_xy;
    const int s = z_first ? 2 : int(y_first);
    const double t_exit = z_first ? walk.t_next[2] : t_xy;
    if (t_exit > stop) break;
    // Step one cell on axis s; climb while the step leaves the current 1D array (§5.3).
    uint32_t id = walk.active[s];
    uint64_t local = 0;
    uint32_t climbed = 0;
    for (;; id = voxels_[id].above[s], ++climbed) {
      if (id == kNone) return best;  // left the scene
      const Voxel& up = voxels_[id];
      Context::StateValues& values = context.states[up.state];
      const int64_t next = values.index + walk.step[s];
      local = uint64_t(next - int64_t(up.first_cell));
      if (local < up.granularity) {
        values.index = next;
        values.t_next = walk.t_next[s] = values.exit_distance(next, walk.step[s]);
        break;
      }
    }
    ++counters.traversal_steps;
    const Voxel& moved = voxels_[id];
    walk.active[s] = id, walk.active_state[s] = moved.state;
    // The other axes' positions come from the voxels above the one the step moved in;
    // usually they already are (the step happened in the deepest voxel).
    for (int c = 0; c < 3; ++c) {
      if (c == s || walk.active[c] == moved.above[c]) continue;
      walk.active[c] = moved.above[c];
      walk.active_state[c] = moved.above[c] == kNone ? uint32_t(c) : voxels_[moved.above[c]].state;
      walk.t_next[c] = context.states[walk.active_state[c]].t_next;
    }
    leaf = moved.first_child + uint32_t(local);
    status = voxels_[leaf].status.load(std::memory_order_acquire);
    const bool stepped_into_leaf = status == kLeaf;
    if (!stepped_into_leaf) leaf = descend(leaf, t_exit, s, walk, context, status, recorder);
    recorder.cell(leaf, t_exit, s, climbed);
    if (stepped_into_leaf && voxels_[leaf].tri_count == 0)
      leaf = cross_empty_run(leaf, s, moved.state, walk, context, recorder);
  }
  return best;
}

// Tests the leaf's triangles not yet tested by this ray; true when one is hit. A finished
// leaf is read from its packed run; a leaf another thread is still cutting (kBuilding), or
// one the memory budget left unpacked, through its id list.
template <bool AnyHit, class Recorder>
bool Grid1D::test_leaf(uint32_t id, uint8_t status, const PreparedRay<KernelReal>& prepared,
                       uint64_t ray_id, float& tmax, Hit& best, Context& context,
                       Recorder& recorder) const {
  const Voxel& voxel = voxels_[id];
  TraceCounters& counters = context.counters;
  bool found = false;
  // One triangle: mailbox (unless it lies in this leaf only), then the kernel.
  const auto test = [&](const TriangleVerts& tri, uint32_t tri_id, bool only_here) {
    if (!only_here && context.already_tested(tri_id, ray_id)) {
      ++counters.mailbox_rejections;
      recorder.rejected();
      return false;
    }
    ++counters.intersection_tests;
    recorder.tested();
    float t, u, v;
    if (!intersect_triangle(prepared, tri.v0, tri.v1, tri.v2, tmax, t, u, v) ||
        !closer(t, int32_t(tri_id), best))
      return false;
    best = {int32_t(tri_id), t, u, v};
    tmax = t;
    return found = true;
  };
  if (status == kLeaf && voxel.first_packed != kNone) {
    const PackedTriangle* record = &packed_[voxel.first_packed];
    for (const PackedTriangle* end = record + voxel.tri_count; record != end; ++record)
      if (test(record->verts, record->id, record->only_here) && AnyHit) return true;
    return found;
  }
  for (uint32_t i = 0; i < voxel.tri_count; ++i) {
    const uint32_t tri_id = tri_indices_[voxel.tri_begin + i];
    if (test(triangles_[tri_id], tri_id, false) && AnyHit) return true;
  }
  return found;
}

// The walk has just stepped along axis s into an empty cell of a 1D array: it crosses the
// following empty cells of the same array in one go, up to the last one it enters before
// reaching a wall on another axis. Nothing in them can be hit, and the ray's slab on each
// grid stays what the cell-by-cell walk would have made it (an acceleration of §5.3's
// horizontal traversal that leaves the structure as the paper's).
template <class Recorder>
uint32_t Grid1D::cross_empty_run(uint32_t cell, int s, uint32_t state, RayWalk& walk,
                                 Context& context, Recorder& recorder) const {
  const Voxel& empty = voxels_[cell];
  const uint32_t run = empty.empty_run[walk.step[s] > 0 ? 0 : 1];
  const double other_wall = std::min(walk.t_next[s == 0 ? 1 : 0], walk.t_next[s == 2 ? 1 : 2]);
  Context::StateValues& values = context.states[state];
  uint32_t crossed = 0;
  while (crossed + 1 < run && walk.t_next[s] < other_wall) {
    ++crossed;
    recorder.cell(walk.step[s] > 0 ? cell + crossed : cell - crossed, walk.t_next[s], s, 0);
    values.index += walk.step[s];
    values.t_next = walk.t_next[s] = values.exit_distance(values.index, walk.step[s]);
  }
  context.counters.traversal_steps += crossed;
  return walk.step[s] > 0 ? cell + crossed : cell - crossed;
}

// §5.2: from `id`, which the ray occupies at t_cur, down to the leaf containing the ray,
// setting each passed voxel's traversal state. The §5.2.2 cases: a state this ray used
// and has not yet left needs nothing; entering through a wall on the voxel's own axis puts
// the ray in the first or last cell (figure 7); otherwise the cell comes from the point.
// Inlined into the walk: called on about half the steps, and a call's register saving
// cost as much as a one-level descent.
template <class Recorder>
[[gnu::always_inline]] inline uint32_t Grid1D::descend(uint32_t id, double t_cur, int entered_axis,
                                                       RayWalk& walk, Context& context,
                                                       uint8_t& status, Recorder& recorder) const {
  for (;;) {
    const Voxel& voxel = voxels_[id];
    status = voxel.status.load(std::memory_order_acquire);
    if (status == kUnexamined) status = examine(id, context);
    // A voxel another thread is cutting is searched as the leaf it still is.
    if (status != kSplit) return id;
    const uint32_t b = voxel.axis;
    const int64_t g = voxel.granularity;
    const int64_t first = int64_t(voxel.first_cell);
    Context::StateValues& values = context.state(voxel.state);
    int64_t local = values.index - first;
    const bool used_by_ray = values.stamp == walk.ray_id;
    StateCase state_case = StateCase::reused;
    if (!used_by_ray || values.t_next <= t_cur || local < 0 || local >= g ||
        int(b) == entered_axis) {
      state_case = used_by_ray ? StateCase::index_only : StateCase::reinitialised;
      const StateInfo& info = states_[voxel.state];
      if (!used_by_ray) {
        ++values.rays;
        values.stamp = walk.ray_id;
        values.t_origin = (info.origin - walk.origin[b]) * walk.inv_dir[b];
        values.t_width = info.width * walk.inv_dir[b];
      }
      if (int(b) == entered_axis) {
        local = walk.step[b] > 0 ? 0 : g - 1;
      } else {
        // Clamped first, then truncated: truncation is floor for what is left, and much
        // cheaper than std::floor on baseline x86-64 (no SSE4.1 round instruction).
        const double p = walk.origin[b] + t_cur * walk.dir[b];
        const double cell = (p - info.origin) * info.scale - double(first);
        local = int64_t(std::clamp(cell, 0.0, double(g - 1)));
      }
      values.index = first + local;
      values.t_next = walk.step[b] == 0 ? kInf : values.exit_distance(values.index, walk.step[b]);
    }
    walk.active[b] = id, walk.active_state[b] = voxel.state, walk.t_next[b] = values.t_next;
    recorder.descent(id, local, state_case);
    id = voxel.first_child + uint32_t(local);
  }
}

uint8_t Grid1D::examine(uint32_t id, Context& context) const {
  uint8_t expected = kUnexamined;
  if (!voxels_[id].status.compare_exchange_strong(expected, kBuilding, std::memory_order_acquire))
    return expected;
  const auto start = Clock::now();
  const Cut cut = plan_cut(id);
  const uint8_t status = (cut.granularity >= 2 && commit_cut(id, cut)) ? kSplit : kLeaf;
  if (status == kLeaf) voxels_[id].first_packed = pack_leaf(id);
  voxels_[id].status.store(status, std::memory_order_release);
  ++context.counters.voxels_built;
  context.counters.lazy_build_seconds += seconds_since(start);
  return status;
}

// Copies a finished leaf's triangles into one contiguous run; kNone when the memory
// budget is spent (the leaf is then read through its id list).
uint32_t Grid1D::pack_leaf(uint32_t id) const {
  const Voxel& voxel = voxels_[id];
  if (!reserve_bytes(uint64_t(voxel.tri_count) * sizeof(PackedTriangle))) return kNone;
  const size_t first = packed_.append(voxel.tri_count);
  if (first == SIZE_MAX || first + voxel.tri_count >= kNone) return kNone;
  double lo[3], hi[3];
  voxel_box(id, lo, hi);
  for (uint32_t i = 0; i < voxel.tri_count; ++i) {
    const uint32_t tri_id = tri_indices_[voxel.tri_begin + i];
    const double* box = &tri_box_[size_t(tri_id) * 6];
    bool inside = true;
    for (int a = 0; a < 3; ++a) inside &= box[a] >= lo[a] && box[a + 3] <= hi[a];
    packed_[first + i] = {triangles_[tri_id], tri_id, inside};
  }
  return uint32_t(first);
}

// Rays of the run crossing the voxel: the sample's segments that cross it, scaled to the
// run; a voxel no segment crosses gets the area estimate from its parent (§6.5).
double Grid1D::estimated_rays(uint32_t id) const {
  const Region& region = regions_[id];
  if (!sampled_) return region.area_rays;
  double lo[3], hi[3];
  voxel_box(id, lo, hi);
  uint32_t crossing = 0;
  for (uint32_t i = 0; i < region.sample_count; ++i) {
    const SampleRay& s = sample_[sample_indices_[region.sample_begin + i]];
    double t0 = s.t0, t1 = s.t1;
    crossing += clip_segment(s.origin, s.dir, lo, hi, t0, t1);
  }
  return crossing > 0 ? crossing * rays_per_sample_ : region.area_rays;
}

namespace {

// Which cell of a cut a coordinate falls in, clamped to the voxel's own cells.
struct CellLocator {
  double origin, scale, first_cell, last_local;
  int64_t operator()(double x) const {
    return int64_t(std::clamp(std::floor((x - origin) * scale) - first_cell, 0.0, last_local));
  }
};

// Spreads items over g cells given each item's first and last cell: offsets (g + 1) and a
// flat list, items in their original order within each cell.
void fill_cells(const std::vector<std::pair<int64_t, int64_t>>& ranges,
                const std::vector<uint32_t>& items, int g, std::vector<uint32_t>& offsets,
                std::vector<uint32_t>& flat) {
  offsets.assign(size_t(g) + 1, 0);
  for (const auto& [c0, c1] : ranges)
    for (int64_t c = c0; c <= c1; ++c) ++offsets[size_t(c) + 1];
  for (int c = 0; c < g; ++c) offsets[c + 1] += offsets[c];
  flat.resize(offsets[g]);
  std::vector<uint32_t> cursor(offsets.begin(), offsets.end() - 1);
  for (size_t i = 0; i < items.size(); ++i)
    for (int64_t c = ranges[i].first; c <= ranges[i].second; ++c) flat[cursor[c]++] = items[i];
}

}  // namespace

// N, extents, mean triangle sizes (each clipped to the voxel, §6.3) and estimated rays.
VoxelFigures Grid1D::figures_of(uint32_t id, const double lo[3], const double hi[3]) const {
  const Voxel& voxel = voxels_[id];
  VoxelFigures figures;
  figures.triangles = voxel.tri_count;
  for (int a = 0; a < 3; ++a) figures.extent[a] = hi[a] - lo[a];
  for (uint32_t i = 0; i < voxel.tri_count; ++i) {
    const double* box = &tri_box_[size_t(tri_indices_[voxel.tri_begin + i]) * 6];
    for (int a = 0; a < 3; ++a)
      figures.mean_size[a] += std::max(0.0, std::min(box[a + 3], hi[a]) - std::max(box[a], lo[a]));
  }
  if (voxel.tri_count > 0)
    for (double& size : figures.mean_size) size /= voxel.tri_count;
  figures.rays = estimated_rays(id);
  return figures;
}

// The most cells each axis may take: max granularity, the minimum cell width, and the
// absolute granularity cap; 0 for an axis that cannot be cut.
std::array<int, 3> Grid1D::granularity_limits(uint32_t id, const VoxelFigures& figures,
                                              const double lo[3], const double hi[3]) const {
  const Region& region = regions_[id];
  const double min_width = root_.min_cell_width(lo, hi);
  std::array<int, 3> limits{};
  for (int a = 0; a < 3; ++a) {
    const double thin_limit = min_width > 0.0 ? figures.extent[a] / min_width : 0.0;
    const double max_g = std::min({double(params_.max_granularity), std::floor(thin_limit),
                                   double(kMaxAbsoluteGranularity / region.grid[a])});
    limits[a] = max_g < 2.0 ? 0 : int(max_g);
  }
  return limits;
}

// The §6 decision for one voxel, a pure function of the voxel, the sample and the
// parameters (never of which ray arrived first), so lazy, eager and any number of threads
// build the same structure. Candidate axes: the paper's alternation by depth, or all axes
// by cost (the paper's future work, comparing with the along-axis term added back). An
// axis that cannot be cut (too thin) or whose cut separates nothing (every cell would keep
// all the voxel's triangles: coincident or spanning triangles) gives way to the next
// candidate. A cut that leaves all triangles in one cell and the others empty is kept: it
// is how a small cluster in large extents ("teapot in a stadium") gets isolated, and the
// depth cap and the minimum cell width bound it on degenerate input.
Grid1D::Cut Grid1D::plan_cut(uint32_t id) const {
  Cut cut;
  const Voxel& voxel = voxels_[id];
  const Region& region = regions_[id];
  if (voxel.tri_count < 2 || region.depth >= uint32_t(params_.depth_or(kDefaultMaxDepth)))
    return cut;
  double lo[3], hi[3];
  voxel_box(id, lo, hi);
  const VoxelFigures figures = figures_of(id, lo, hi);
  cut.rays = figures.rays;
  const std::array<int, 3> limits = granularity_limits(id, figures, lo, hi);
  std::vector<AxisPlan> plans;
  for (int k = 0; k < 3; ++k) {
    const int a = (int(region.depth) + k) % 3;
    if (limits[a] == 0) continue;
    const AxisPlan plan = plan_axis(params_, figures, a, limits[a]);
    if (params_.axis == AxisRule::alternate && plans.empty() && plan.granularity < 2) return cut;
    if (plan.granularity >= 2) plans.push_back(plan);
  }
  if (params_.axis == AxisRule::cost) {
    const auto whole = [&](const AxisPlan& p) {
      return p.cut_total + figures.rays * along_axis_cost(params_, figures, p.axis);
    };
    std::stable_sort(plans.begin(), plans.end(),
                     [&](const AxisPlan& x, const AxisPlan& y) { return whole(x) < whole(y); });
  }
  for (const AxisPlan& plan : plans)
    if (sort_into_cells(id, plan.axis, plan.granularity, lo, hi, cut)) return cut;
  return Cut{};
}

VoxelCostReport Grid1D::cost_report(uint32_t id) const {
  VoxelCostReport report;
  report.voxel = id;
  report.depth = regions_[id].depth;
  const Voxel& voxel = voxels_[id];
  if (voxel.status.load(std::memory_order_acquire) == kSplit)
    report.axis = voxel.axis, report.granularity = voxel.granularity;
  double lo[3], hi[3];
  voxel_box(id, lo, hi);
  report.figures = figures_of(id, lo, hi);
  report.subdivision_cost = params_.subcost * report.figures.triangles;
  const std::array<int, 3> limits = granularity_limits(id, report.figures, lo, hi);
  for (int a = 0; a < 3; ++a) {
    if (limits[a] == 0) continue;
    report.plans.push_back(plan_axis(params_, report.figures, a, limits[a]));
    for (int g = 2; g <= limits[a]; ++g)
      report.alternatives.push_back({a, g, cut_cost(params_, report.figures, a, g)});
  }
  return report;
}

bool Grid1D::sort_into_cells(uint32_t id, int axis, int g, const double lo[3], const double hi[3],
                             Cut& cut) const {
  const Voxel& voxel = voxels_[id];
  const Region& region = regions_[id];
  const StateInfo& grid = states_[axis];  // the scene box on this axis
  const uint64_t granularity = region.grid[axis] * uint64_t(g);
  const CellLocator locate{grid.origin, double(granularity) / grid.extent,
                           double(region.cell[axis] * uint64_t(g)), double(g - 1)};

  std::vector<uint32_t> items(&tri_indices_[voxel.tri_begin],
                              &tri_indices_[voxel.tri_begin] + voxel.tri_count);
  std::vector<std::pair<int64_t, int64_t>> ranges(items.size());
  bool separates = false;
  for (size_t i = 0; i < items.size(); ++i) {
    const double* box = &tri_box_[size_t(items[i]) * 6];
    ranges[i] = {locate(std::max(box[axis], lo[axis])), locate(std::min(box[axis + 3], hi[axis]))};
    separates |= ranges[i].first > 0 || ranges[i].second < g - 1;
  }
  if (!separates) return false;
  cut.axis = axis;
  cut.granularity = g;
  fill_cells(ranges, items, g, cut.tri_offsets, cut.tris);

  items.assign(&sample_indices_[region.sample_begin],
               &sample_indices_[region.sample_begin] + region.sample_count);
  ranges.clear();
  std::vector<uint32_t> crossing;
  for (const uint32_t j : items) {
    const SampleRay& s = sample_[j];
    double t0 = s.t0, t1 = s.t1;
    if (!clip_segment(s.origin, s.dir, lo, hi, t0, t1)) continue;
    const int64_t c0 = locate(s.origin[axis] + t0 * s.dir[axis]);
    const int64_t c1 = locate(s.origin[axis] + t1 * s.dir[axis]);
    ranges.emplace_back(std::min(c0, c1), std::max(c0, c1));
    crossing.push_back(j);
  }
  fill_cells(ranges, crossing, g, cut.sample_offsets, cut.samples);
  return true;
}

// Counts `bytes` against the memory budget; false (and nothing counted) when they do not
// fit. Under a tight budget which voxels get cut depends on which thread comes first; the
// answers do not.
bool Grid1D::reserve_bytes(uint64_t bytes) const {
  uint64_t used = bytes_used_.load(std::memory_order_relaxed);
  do {
    if (used + bytes > params_.memory_budget) return false;
  } while (!bytes_used_.compare_exchange_weak(used, used + bytes, std::memory_order_relaxed));
  return true;
}

uint32_t Grid1D::state_for(uint32_t axis, uint64_t granularity) const {
  std::lock_guard lock(state_mutex_);
  const uint64_t key = granularity << 2 | axis;
  const auto found = state_ids_.find(key);
  if (found != state_ids_.end()) return found->second;
  const auto id = uint32_t(fits_budget(states_.append(1), "its traversal states"));
  if (!state_rays_.construct(id, 1)) fits_budget(SIZE_MAX, "its traversal states");
  const double extent = root_.hi[axis] - root_.lo[axis];
  states_[id] = {root_.lo[axis], extent, double(granularity) / extent, extent / double(granularity),
                 granularity,    axis};
  state_ids_.emplace(key, id);
  return id;
}

// Publishes the cut's cells as new voxels. Runs under the build lock; the caller's release
// store of kSplit makes all of it visible to the threads that then walk into the voxel.
bool Grid1D::commit_cut(uint32_t id, const Cut& cut) const {
  const size_t g = size_t(cut.granularity);
  const uint64_t bytes = g * (sizeof(Voxel) + sizeof(Region)) +
                         (cut.tris.size() + cut.samples.size()) * sizeof(uint32_t);
  if (voxels_.size() + g >= size_t(kNone) || !reserve_bytes(bytes)) {
    ++over_budget_;
    return false;
  }
  const Region& parent = regions_[id];
  const int axis = cut.axis;
  const uint32_t state = state_for(uint32_t(axis), parent.grid[axis] * g);
  // Each array holds at most the budget, which reserve_bytes has checked: these appends
  // fail only if one array alone outgrows it, and then the voxel stays a leaf.
  const size_t first_voxel = voxels_.append(g);
  const size_t tri_base = tri_indices_.append(cut.tris.size());
  const size_t sample_base = sample_indices_.append(cut.samples.size());
  if (first_voxel == SIZE_MAX || tri_base == SIZE_MAX || sample_base == SIZE_MAX ||
      !regions_.construct(first_voxel, g)) {
    ++over_budget_;
    return false;
  }
  const uint32_t first_child = uint32_t(first_voxel);
  std::copy(cut.tris.begin(), cut.tris.end(), &tri_indices_[tri_base]);
  std::copy(cut.samples.begin(), cut.samples.end(), &sample_indices_[sample_base]);

  double parent_extent[3], child_extent[3];
  double lo[3], hi[3];
  voxel_box(id, lo, hi);
  for (int a = 0; a < 3; ++a) parent_extent[a] = child_extent[a] = hi[a] - lo[a];
  child_extent[axis] /= double(g);
  const double parent_area = surface_area(parent_extent);
  const double area_share = parent_area > 0.0 ? surface_area(child_extent) / parent_area : 1.0;
  for (size_t i = 0; i < g; ++i) {
    Voxel& child = voxels_[first_child + i];
    child.tri_begin = uint32_t(tri_base + cut.tri_offsets[i]);
    child.tri_count = cut.tri_offsets[i + 1] - cut.tri_offsets[i];
    if (child.tri_count == 0) {  // nothing to cut, ever: a leaf from birth
      child.status.store(kLeaf, std::memory_order_relaxed);
      child.first_packed = kNone;
      child.empty_run[1] = i > 0 && voxels_[first_child + i - 1].tri_count == 0
                               ? voxels_[first_child + i - 1].empty_run[1] + 1
                               : 1;
    }
    Region& region = regions_[first_child + i];
    region = parent;
    region.cell[axis] = parent.cell[axis] * g + i;
    region.grid[axis] = parent.grid[axis] * g;
    region.above[axis] = id;
    region.depth = parent.depth + 1;
    region.sample_begin = uint32_t(sample_base + cut.sample_offsets[i]);
    region.sample_count = cut.sample_offsets[i + 1] - cut.sample_offsets[i];
    region.area_rays = cut.rays * area_share;
  }
  for (size_t i = g; i-- > 0;) {
    Voxel& child = voxels_[first_child + i];
    if (child.tri_count == 0)
      child.empty_run[0] = i + 1 < g && voxels_[first_child + i + 1].tri_count == 0
                               ? voxels_[first_child + i + 1].empty_run[0] + 1
                               : 1;
  }
  Voxel& voxel = voxels_[id];
  voxel.axis = uint8_t(axis);
  voxel.granularity = uint16_t(g);
  voxel.state = state;
  voxel.first_child = first_child;
  std::copy(parent.above, parent.above + 3, voxel.above);
  voxel.first_cell = parent.cell[axis] * g;
  ++subdivided_;
  raise_to(deepest_, parent.depth + 1);
  return true;
}

StructureStats Grid1D::stats() const {
  StructureStats s;
  s.nodes = voxels_.size();
  s.voxels_subdivided = subdivided_.load();
  s.leaves = voxels_.size() - subdivided_.load();
  s.traversal_states = states_.size();
  s.depth = deepest_.load();
  s.memory_bytes = bytes_used_ + triangles_.size() * sizeof(TriangleVerts) +
                   tri_box_.size() * sizeof(double) + sample_.size() * sizeof(SampleRay) +
                   states_.size() * sizeof(StateInfo);
  s.build_seconds = build_seconds_;
  s.voxels_over_budget = over_budget_.load();
  return s;
}

}  // namespace gs
