// The 1D grid's walk (§5): clip the ray to the scene box, go down to the cell where it
// enters (vertical traversal, §5.2), then step cell by cell along the axis whose next wall
// is nearest (horizontal traversal, §5.3), climbing to the node above when a step leaves a
// 1D array. The walk recorder is a template parameter: the timed path's records nothing,
// and the viewer's walk is this same code (docs/design.md §2).
#include <algorithm>
#include <bit>
#include <cmath>

#include "core/accel/grid1d/records.h"

namespace gs {
namespace {

// The next occupied cell after `local` in direction `step` (+1 or -1) among g cells whose
// occupancy bits are `words`, or g (step +1) / -1 (step -1) when there is none: one bit
// scan per 32 cells.
int64_t next_occupied(const std::atomic<uint32_t>* words, int64_t local, int step, int64_t g) {
  if (step > 0) {
    for (int64_t i = local + 1; i < g; i = (i / 32 + 1) * 32) {
      const uint32_t bits = words[i / 32].load(std::memory_order_relaxed) >> (i % 32);
      if (bits != 0) return std::min(g, i + std::countr_zero(bits));
    }
    return g;
  }
  for (int64_t i = local - 1; i >= 0; i = (i / 32) * 32 - 1) {
    const uint32_t bits = words[i / 32].load(std::memory_order_relaxed) << (31 - i % 32);
    if (bits != 0) return i - std::countl_zero(bits);
  }
  return -1;
}

// Where the ray leaves the cell it is in: the nearest of the three walls, or the stop
// distance when that comes first.
double segment_end(const double t_next[3], double stop) {
  return std::min({t_next[0], t_next[1], t_next[2], stop});
}

}  // namespace

// The timed path's recorder: every hook compiles to nothing.
struct Grid1D::NullRecorder {
  static constexpr bool kRecords = false;
  void descent(uint32_t /*node*/, int64_t /*cell*/, StateCase /*state_case*/) {}
  void cell(uint32_t /*voxel*/, double /*t_enter*/, int /*axis*/, uint32_t /*climbed*/) {}
  void culled() {}
  void tested(uint32_t /*count*/) {}
  void rejected() {}
  void searched(int32_t /*best*/) {}
};

// Fills a Walk from the hooks the traversal calls.
class Grid1D::WalkRecorder {
 public:
  static constexpr bool kRecords = true;
  WalkRecorder(const Grid1D& grid, Walk& walk) : grid_(grid), walk_(walk) {}
  void descent(uint32_t node, int64_t cell, StateCase state_case) {
    const uint32_t voxel = grid_.node_voxels_[node];
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
  void culled() { walk_.cells.back().culled = true; }
  void tested(uint32_t count) { walk_.cells.back().tests += count; }
  void rejected() { ++walk_.cells.back().rejections; }
  void searched(int32_t best) { walk_.cells.back().hit = best; }

 private:
  const Grid1D& grid_;
  Walk& walk_;
  std::vector<WalkDescent> pending_;
};

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

// §5: the ray enters the scene box at t_enter; every iteration resolves the reference of
// the cell the ray is in (going down through nodes, building what is unbuilt), searches it,
// and steps through the nearest wall, unless the nearest hit lies before it.
template <bool AnyHit, class Recorder>
Hit Grid1D::trace(const Ray& ray, Context& context, Recorder& recorder) const {
  RayWalk walk;
  double t_enter, t_leave;
  if (!input_.clip.clip(ray, t_enter, t_leave, walk.inv_dir)) return Hit{};
  for (int a = 0; a < 3; ++a) {
    walk.origin[a] = ray.origin[a], walk.dir[a] = ray.dir[a];
    walk.step[a] = walk.dir[a] > 0.0 ? 1 : walk.dir[a] < 0.0 ? -1 : 0;
  }
  const double slack = walk_slack(ray, input_.clip.magnitude, walk.inv_dir);
  walk.ray_id = context.mailbox.next_ray();
  for (uint32_t a = 0; a < 3; ++a) {  // the box's states: the scene box on each axis
    Context::StateValues& box = context.state(a);
    box.stamp = walk.ray_id, box.index = 0;
    const double exit_wall = walk.step[a] > 0 ? input_.clip.hi[a] : input_.clip.lo[a];
    box.t_next = walk.step[a] == 0 ? kInf : (exit_wall - walk.origin[a]) * walk.inv_dir[a];
    walk.active[a] = kNone, walk.active_state[a] = a, walk.t_next[a] = box.t_next;
  }
  const PreparedRay<KernelReal> prepared(ray, t_enter, walk.inv_dir);
  const RayBoxTest box_test(walk.origin, walk.inv_dir);
  walk.prepared = &prepared;
  walk.box_test = &box_test;
  walk.tmax = ray.tmax;
  walk.best = Hit{};
  // Changes only with tmax: computed per hit rather than per step.
  double stop = stop_distance(walk.tmax, slack);
  TraceCounters& counters = context.counters;

  uint32_t ref = root_ref_.load(std::memory_order_acquire);
  uint32_t parent = kNone, local = 0;  // the node whose cell the ray is in, and the cell
  double t_cur = t_enter;
  int entered = -1;
  uint32_t climbed = 0;
  for (;;) {
    // Down to a leaf, an empty cell, a node whose contents the ray misses, or a voxel to
    // search through its id list. The ray's segment in the current cell ends at the nearest
    // of the three walls (or at the stop distance).
    bool culled = false;
    for (;;) {
      const child_ref::Kind kind = child_ref::kind(ref);
      if (kind == child_ref::kNode) {
        const uint32_t node = child_ref::payload(ref);
        if (!box_test.crosses(nodes_[node].box, nodes_[node].box + 3, t_cur,
                              segment_end(walk.t_next, stop))) {
          culled = true;
          if constexpr (Recorder::kRecords)
            recorder.cell(node_voxels_[node], t_cur, entered, climbed);
          break;
        }
        parent = node;
        local = descend(parent, t_cur, entered, walk, context, recorder);
        ref = refs_[nodes_[parent].children + local].load(std::memory_order_acquire);
      } else if (kind == child_ref::kUnbuilt) {
        const uint32_t built = examine(child_ref::payload(ref), context);
        if (built == ref) break;
        ref = built;
      } else {
        break;
      }
    }
    bool found = false;
    if (culled) {
      recorder.culled();
    } else {
      if constexpr (Recorder::kRecords)
        recorder.cell(parent == kNone ? 0 : voxels_[node_voxels_[parent]].first_child + local,
                      t_cur, entered, climbed);
      switch (child_ref::kind(ref)) {
        case child_ref::kLeaf: {
          const LeafView leaf = leaves_.view(child_ref::payload(ref));
          if (box_test.crosses(leaf.box, leaf.box + 3, t_cur, segment_end(walk.t_next, stop)))
            found = test_leaf<AnyHit>(leaf, kernel_, prepared, walk.ray_id, walk.tmax, walk.best,
                                      context.mailbox, counters, recorder);
          else
            recorder.culled();
          break;
        }
        case child_ref::kUnbuilt:
          found = search_unbuilt<AnyHit>(child_ref::payload(ref), walk, context, recorder);
          break;
        default:  // empty: no test; a run of empty cells is crossed in one go
          if (parent != kNone) skip_empty(parent, local, walk, context, recorder);
          break;
      }
    }
    recorder.searched(walk.best.id);
    if (AnyHit && found) return walk.best;
    if (found) stop = stop_distance(walk.tmax, slack);
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
    int64_t next_local = 0;
    climbed = 0;
    for (;; id = nodes_[id].above[s], ++climbed) {
      if (id == kNone) return walk.best;  // left the scene
      const Node& up = nodes_[id];
      Context::StateValues& values = context.states[up.state];
      const int64_t next = values.index + walk.step[s];
      next_local = next - up.first_cell;
      if (uint64_t(next_local) < up.granularity) {
        values.index = next;
        values.t_next = walk.t_next[s] = values.exit_distance(next, walk.step[s]);
        break;
      }
    }
    ++counters.traversal_steps;
    const Node& moved = nodes_[id];
    walk.active[s] = id, walk.active_state[s] = moved.state;
    // The other axes' positions come from the nodes above the one the step moved in;
    // usually they already are (the step happened in the deepest node).
    for (int c = 0; c < 3; ++c) {
      if (c == s || walk.active[c] == moved.above[c]) continue;
      walk.active[c] = moved.above[c];
      walk.active_state[c] = moved.above[c] == kNone ? uint32_t(c) : nodes_[moved.above[c]].state;
      walk.t_next[c] = context.states[walk.active_state[c]].t_next;
    }
    parent = id, local = uint32_t(next_local);
    ref = refs_[moved.children + local].load(std::memory_order_acquire);
    t_cur = t_exit, entered = s;
  }
  return walk.best;
}

// §5.2: into node `id`, which the ray occupies at t_cur, setting its traversal state, and
// returns the cell the ray is in. The §5.2.2 cases: a state this ray used and has not yet
// left needs nothing; entering through a wall on the node's own axis puts the ray in the
// first or last cell (figure 7); otherwise the cell comes from the point. A state is
// initialised only when a ray first needs it (its stamp is another ray's).
template <class Recorder>
[[gnu::always_inline]] inline uint32_t Grid1D::descend(uint32_t id, double t_cur, int entered_axis,
                                                       RayWalk& walk, Context& context,
                                                       Recorder& recorder) const {
  const Node& node = nodes_[id];
  const uint32_t b = node.axis;
  const int64_t g = node.granularity;
  const int64_t first = node.first_cell;
  Context::StateValues& values = context.state(node.state);
  int64_t local = values.index - first;
  const bool used_by_ray = values.stamp == walk.ray_id;
  StateCase state_case = StateCase::reused;
  if (!used_by_ray || values.t_next <= t_cur || local < 0 || local >= g || int(b) == entered_axis) {
    state_case = used_by_ray ? StateCase::index_only : StateCase::reinitialised;
    const StateInfo& info = states_[node.state];
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
  walk.active[b] = id, walk.active_state[b] = node.state, walk.t_next[b] = values.t_next;
  recorder.descent(id, local, state_case);
  return uint32_t(local);
}

// The ray is in empty cell `local` of node `id`: it crosses the run of empty cells that
// follows along the node's axis in one go, found by one bit scan of the occupancy words. If
// the ray reaches the run's end (the next occupied cell, or the array's end) before a wall
// of another axis, the node's state moves to the run's last cell as the cell-by-cell walk
// would have; otherwise the ray leaves the node through that other wall first, and the state
// stays truthful as it is (its slab holds until its t_next). Either way the walk's next wall
// on this axis is the run's end. The cells crossed count as steps, one each, as the
// cell-by-cell walk would count them.
template <class Recorder>
void Grid1D::skip_empty(uint32_t id, uint32_t local, RayWalk& walk, Context& context,
                        Recorder& recorder) const {
  const Node& node = nodes_[id];
  const uint32_t b = node.axis;
  const int d = walk.step[b];
  if (d == 0) return;  // never leaves the cell along this axis
  const int64_t g = node.granularity;
  const int64_t end =
      next_occupied(&refs_[node.children - occupancy_words(node.granularity)], local, d, g);
  if (end == int64_t(local) + d) return;  // the next cell is occupied: nothing to skip
  Context::StateValues& values = context.states[node.state];
  const int64_t last_empty = node.first_cell + end - d;
  const double t_end = values.exit_distance(last_empty, d);
  const double other = std::min(walk.t_next[(b + 1) % 3], walk.t_next[(b + 2) % 3]);
  // Where the ray enters cell k of the node (k after `local` in direction d).
  const auto entry = [&](int64_t k) { return values.exit_distance(node.first_cell + k - d, d); };
  int64_t last = end - d;  // the last cell the ray enters before leaving the node
  if (t_end <= other) {
    values.index = last_empty, values.t_next = t_end;
  } else {
    // Located from the point where the ray meets the other wall, then corrected by the
    // walls' own distances so that the count is exact.
    const StateInfo& info = states_[node.state];
    const double p = walk.origin[b] + other * walk.dir[b];
    const double at = std::floor((p - info.origin) * info.scale) - double(node.first_cell);
    last = d > 0 ? int64_t(std::clamp(at, double(local), double(end - d)))
                 : int64_t(std::clamp(at, double(end - d), double(local)));
    while (last != end - d && entry(last + d) < other) last += d;
    while (last != int64_t(local) && entry(last) >= other) last -= d;
  }
  if constexpr (Recorder::kRecords) {
    const uint32_t first_child = voxels_[node_voxels_[id]].first_child;
    for (int64_t k = int64_t(local) + d; k != last + d; k += d)
      recorder.cell(first_child + uint32_t(k), entry(k), int(b), 0);
  }
  walk.t_next[b] = t_end;
  context.counters.traversal_steps += uint64_t((last - int64_t(local)) * d);
}

// A voxel another thread is still cutting, or a leaf the memory budget left without its
// leaf block: its triangles, copied into the kernel's form, tested by the one leaf loop.
template <bool AnyHit, class Recorder>
bool Grid1D::search_unbuilt(uint32_t id, RayWalk& walk, Context& context,
                            Recorder& recorder) const {
  const Voxel& voxel = voxels_[id];
  const uint32_t n = voxel.tri_count;
  context.scratch_ids.assign(&tri_indices_[voxel.tri_begin], &tri_indices_[voxel.tri_begin] + n);
  context.scratch_coords.resize(size_t(n) * 9);
  for (uint32_t i = 0; i < n; ++i) {
    const TriangleVerts& t = input_.triangles[context.scratch_ids[i]];
    const glm::vec3* corners[3] = {&t.v0, &t.v1, &t.v2};
    for (int k = 0; k < 3; ++k)
      for (int a = 0; a < 3; ++a)
        context.scratch_coords[size_t(3 * k + a) * n + i] = (*corners[k])[a];
  }
  const LeafView leaf{context.scratch_coords.data(), context.scratch_ids.data(), n};
  return test_leaf<AnyHit>(leaf, kernel_, *walk.prepared, walk.ray_id, walk.tmax, walk.best,
                           context.mailbox, context.counters, recorder);
}

}  // namespace gs
