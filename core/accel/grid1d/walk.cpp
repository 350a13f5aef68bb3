// The 1D grid's walk (§5): clip the ray to the scene box, go down to the cell where it
// enters (vertical traversal, §5.2), then step along the axis whose next wall is nearest
// (horizontal traversal, §5.3), climbing to the node above when a step leaves a 1D array.
// Each node tests its cells' content boxes against the ray at once (core/geometry/
// box_test.h), so a step goes straight to the next cell whose contents the ray meets: empty
// cells, and cells whose triangles lie off the ray, are crossed without a look, and a ray
// that meets nothing leaves the scene box after one such test per node it crosses
// (docs/design.md §1.9). The walk recorder is a template parameter: the timed path's records
// nothing, and the viewer's walk is this same code (docs/design.md §2).
#include <algorithm>
#include <bit>
#include <limits>

#include "core/accel/grid1d/records.h"
#include "core/base/check.h"

namespace gs {
namespace {

// The two axes other than a: kNextAxis[a] and kNextAxis[a + 1].
constexpr int kNextAxis[4] = {1, 2, 0, 1};

}  // namespace

// The timed path's recorder: every hook compiles to nothing.
struct Grid1D::NullRecorder {
  static constexpr bool kRecords = false;
  void descent(uint32_t /*node*/, int64_t /*cell*/, StateCase /*state_case*/) {}
  void discard_descents() {}
  void cell(uint32_t /*voxel*/, double /*t_enter*/, int /*axis*/, uint32_t /*climbed*/) {}
  void spanning(uint32_t /*voxel*/, double /*t_enter*/) {}
  void tested(uint32_t /*count*/) {}
  void rejected() {}
  void searched(int32_t /*best*/) {}
  void crossed(int64_t /*cells*/) {}
};

// Fills a Walk from the hooks the traversal calls: the cells the walk looked at, in order,
// each with the descents that led to it.
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
  // Descents into a node the ray met nothing in: they led to no cell.
  void discard_descents() { pending_.clear(); }
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
  // The spanning triangles of the voxel of the node the walk just went down into.
  void spanning(uint32_t voxel, double t_enter) {
    cell(voxel, t_enter, -1, 0);
    walk_.cells.back().spanning = true;
  }
  void tested(uint32_t count) { walk_.cells.back().tests += count; }
  void rejected() { ++walk_.cells.back().rejections; }
  void searched(int32_t best) { walk_.cells.back().hit = best; }
  void crossed(int64_t cells) { walk_.cells_crossed += uint64_t(cells); }

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
  double t_enter, t_leave;
  if (input_.clip.clip(ray, t_enter, t_leave)) walk.t_leave = t_leave;
  WalkRecorder recorder(*this, walk);
  walk.hit = trace<false>(ray, static_cast<Context&>(context), recorder);
  return walk;
}

// §5: the ray enters the scene box at t_enter. Each round goes down from the cell the ray
// is in to a cell worth a look (a leaf whose contents the ray meets), searches it, and
// steps on, until the ray leaves the box or the nearest hit lies before the next wall.
template <bool AnyHit, class Recorder>
Hit Grid1D::trace(const Ray& ray, Context& context, Recorder& recorder) const {
  RayWalk walk;
  const WalkLine& line = walk.line;
  if (!start_walk(input_.clip, ray, walk.line)) return Hit{};
  for (int a = 0; a < 3; ++a) walk.step[a] = step_of(ray.dir[a]);
  walk.ray_id = context.mailbox.next_ray();
  for (uint32_t a = 0; a < 3; ++a) {  // the box's states: the scene box on each axis
    Context::StateValues& box = context.states[a];
    box.stamp = walk.ray_id, box.index = 0, box.t_next = line.t_exit[a];
    walk.active[a] = kNone, walk.active_state[a] = a, walk.t_next[a] = box.t_next;
  }
  const PreparedRay<KernelReal> prepared(ray, line.shift, line.inv_dir);
  // Content boxes are tested on the ray's own line, in its own t, from its entry into the
  // scene box on (a cell ahead is entered later anyway); not at all from far away.
  const RayBoxes boxes(ray, !line.far);
  walk.prepared = &prepared;
  walk.boxes = &boxes;
  walk.tmax = ray.tmax;
  walk.best = Hit{};
  set_stop(line, walk.tmax, walk.stop, walk.t_hi);
  walk.t_lo = box_test_start(line);

  Cursor cursor{root_ref_.load(std::memory_order_acquire), line.t0, Cursor::kLocated, 0, kNone, 0};
  // A ray that starts inside the scene box is located at its start point, which content
  // boxes may hold (holds_start); one from outside enters at the box's wall, rarely inside one.
  if (line.shift == double(ray.tmin)) {
    cursor.entered = Cursor::kAtStart;
    for (int a = 0; a < 3; ++a)
      walk.start[a] = _mm_set1_ps(float(line.origin[a] + line.t0 * line.dir[a]));
  }
  do {
    if (!enter<AnyHit>(cursor, walk, context, recorder)) continue;
    if constexpr (Recorder::kRecords)
      recorder.cell(cursor_voxel(cursor), line.shift + cursor.t,
                    std::max(cursor.entered, int(Cursor::kLocated)), cursor.climbed);
    if (search<AnyHit>(leaf_of(cursor.ref, context), walk, context, recorder) && AnyHit)
      return walk.best;
  } while (next_cell(cursor, walk, context, recorder));
  return walk.best;
}

// The voxel of the cell the cursor stands in (for the recorder).
uint32_t Grid1D::cursor_voxel(const Cursor& cursor) const {
  if (child_ref::kind(cursor.ref) == child_ref::kUnbuilt) return child_ref::payload(cursor.ref);
  uint32_t id =
      cursor.node == kNone ? 0 : voxels_[node_voxels_[cursor.node]].first_child + cursor.local;
  // A chain's top refers to its bottom (settle): a leaf there is the chain's last one-cell cut's
  // cell holding the triangles.
  while (voxels_[id].status.load(std::memory_order_acquire) == kSplit) {
    const Voxel& chain = voxels_[id];
    uint32_t cell = 0;
    while (voxels_[chain.first_child + cell].tri_count == 0) ++cell;
    id = chain.first_child + cell;
  }
  return id;
}

// From the cell the cursor stands in at cursor.t, down through nodes (§5.2) to a cell worth
// a look: a leaf, or a voxel to search through its id list (cut by another thread, or left
// without a leaf block by the memory budget). In each node the cursor moves on to the first
// cell, from the one the ray is in, whose contents the ray meets. False when there is none
// before the ray leaves the node (or the cell is empty): the walk then goes on from the
// walls, which `seek` has set.
template <bool AnyHit, class Recorder>
bool Grid1D::enter(Cursor& cursor, RayWalk& walk, Context& context, Recorder& recorder) const {
  for (;;) {
    switch (child_ref::kind(cursor.ref)) {
      case child_ref::kUnbuilt: {
        const uint32_t built = examine(child_ref::payload(cursor.ref), context);
        if (built == cursor.ref) return true;
        cursor.ref = built;
        continue;
      }
      case child_ref::kLeaf:
        return true;
      case child_ref::kEmpty:
        return false;
      case child_ref::kNode:
        break;
    }
    const uint32_t id = child_ref::payload(cursor.ref);
    // A node whose summary (Node::boxes) the ray misses holds nothing it can hit: passed by
    // like an empty cell, without going down into it (its traversal state untouched). Not
    // asked of a ray located at its start: one that starts on a surface (a shadow ray) meets
    // the summaries of the nodes around its start, and the test would only cost it (dragon
    // shadow rays ran at 0.986 of the previous speed with it, 1.014 without).
    if (cursor.entered != Cursor::kAtStart &&
        walk.boxes->crossed_group(&child_boxes_[nodes_[id].summary()], walk.t_lo, walk.t_hi) == 0) {
      recorder.discard_descents();
      return false;
    }
    const int64_t local = descend(id, cursor.t, cursor.entered, walk, context, recorder);
    if (nodes_[id].spanning != Node::kNoSpanning &&
        test_spanning<AnyHit>(id, cursor.t, walk, context, recorder))
      return false;
    const int64_t cell = cursor.entered == Cursor::kAtStart && holds_start(id, local, walk)
                             ? local
                             : seek(id, local, true, cursor, walk, context, recorder);
    if (cell < 0) {
      recorder.discard_descents();
      return false;
    }
    cursor.node = id, cursor.local = uint32_t(cell);
    cursor.ref = refs_[nodes_[id].children + uint32_t(cell)].load(std::memory_order_acquire);
  }
}

// A node's spanning triangles (Node::spanning), tested as the ray goes down into it (once:
// a ray goes down into a node at most once), before its cells: a hit moves the stop distance
// in, so that the cells beyond it are passed over. Testing them wherever the ray is in the
// node changes no answer: the hit is a hit, and the walk still searches every cell before it
// (docs/design.md §1.3). True when an any-hit ray has its answer: its stop distance is then
// -inf, so that the walk ends at the next wall.
template <bool AnyHit, class Recorder>
bool Grid1D::test_spanning(uint32_t id, double t_enter, RayWalk& walk, Context& context,
                           Recorder& recorder) const {
  if constexpr (Recorder::kRecords) recorder.spanning(node_voxels_[id], walk.line.shift + t_enter);
  if (!search<AnyHit>(leaves_.view(nodes_[id].spanning), walk, context, recorder) || !AnyHit)
    return false;
  walk.stop = -kInf;
  return true;
}

// Searches a leaf block for the ray (§5, step 4; a leaf's, or a node's spanning triangles):
// a nearer hit moves the stop distance in. True when the ray found a hit (an any-hit ray's
// answer).
template <bool AnyHit, class Recorder>
bool Grid1D::search(const LeafView& leaf, RayWalk& walk, Context& context,
                    Recorder& recorder) const {
  ++context.counters.traversal_steps;
  const bool found = test_leaf<AnyHit>(leaf, kernel_, *walk.prepared,
                                       {walk.boxes, walk.t_lo, walk.t_hi}, walk.ray_id, walk.tmax,
                                       walk.best, context.mailbox, context.counters, recorder);
  recorder.searched(walk.best.id);
  if (found && !AnyHit) set_stop(walk.line, walk.tmax, walk.stop, walk.t_hi);
  return found;
}

// Whether cell `cell` of node `id` has the ray's start point in its content box. The ray
// then meets the box where it starts, and seek's test of the cell's group would say so: a
// ray that starts on a surface deep in the structure (a shadow ray) goes down to it with a
// look at one box per node instead of a group test. The point is rounded to float, so the
// answer may be wrong by a rounding either way; that costs a look, never a hit (a skipped
// box test never changes an answer, it only passes over cells). The point is compared with
// all four boxes of the cell's group at once: no branch per face.
inline bool Grid1D::holds_start(uint32_t id, int64_t cell, const RayWalk& walk) const {
  const float* group = box_group(&child_boxes_[nodes_[id].boxes], uint32_t(cell));
  __m128 inside = _mm_castsi128_ps(_mm_set1_epi32(-1));
  for (int a = 0; a < 3; ++a)
    inside = _mm_and_ps(inside,
                        _mm_and_ps(_mm_cmple_ps(_mm_loadu_ps(group + 4 * a), walk.start[a]),
                                   _mm_cmple_ps(walk.start[a], _mm_loadu_ps(group + 4 * (3 + a)))));
  return _mm_movemask_ps(inside) >> box_lane(uint32_t(cell)) & 1;
}

// The traversal state of `node` on `axis`; kNone, the scene box, has the box's state there.
inline uint32_t Grid1D::state_of(uint32_t node, int axis) const {
  return node == kNone ? uint32_t(axis) : nodes_[node].state;
}

// A climb on axis s that passed chain node `chain` by to `up` (kNone: the scene box): the
// ray has left the chain's one cell holding triangles and crosses its empty cells up to the
// wall of up's cell, inside the cells of the chain's own nodes above on the other axes (the
// nearest that are no chains), whose other cells may hold triangles. When it reaches a wall
// of theirs first, the walk must step there: `up` keeps axis s with its cell's wall, those
// nodes the other axes, and the function returns true. False when up's wall comes first: the
// ray leaves their cells with up's (or they lie above up), and the climb goes on as ever.
bool Grid1D::held_by_chain(uint32_t chain, uint32_t up, int s, RayWalk& walk,
                           Context& context) const {
  const uint32_t up_state = state_of(up, s);
  const double t_wall = context.states[up_state].t_next;
  const Node& passed = nodes_[chain];
  const int b = kNextAxis[s], c = kNextAxis[s + 1];
  const uint32_t b_state = state_of(passed.above[b], b), c_state = state_of(passed.above[c], c);
  GRIDSCOPE_CHECK(context.states[b_state].stamp == walk.ray_id &&
                  context.states[c_state].stamp == walk.ray_id);
  if (!(std::min(context.states[b_state].t_next, context.states[c_state].t_next) < t_wall))
    return false;
  activate(s, up, up_state, walk);
  activate(b, passed.above[b], b_state, walk);
  activate(c, passed.above[c], c_state, walk);
  walk.t_next[s] = t_wall;
  walk.t_next[b] = context.states[b_state].t_next;
  walk.t_next[c] = context.states[c_state].t_next;
  return true;
}

// Leaves the cursor's cell through its nearest wall (§5.3): on that axis, the node the ray's
// position comes from steps to its next cell whose contents the ray meets, climbing to the
// node above when the array ends. False when the ray leaves the scene box, or the nearest
// hit lies before the wall. Inlined into trace, its one caller: a call cost each step some
// 18 instructions of register saves (bunny-sibenik: 5.5% of a ray's instructions).
template <class Recorder>
[[gnu::always_inline]] inline bool Grid1D::next_cell(Cursor& cursor, RayWalk& walk,
                                                     Context& context, Recorder& recorder) const {
  for (;;) {
    // Written as selects, not branches: which axis comes next is unpredictable.
    const bool y_first = walk.t_next[1] < walk.t_next[0];
    const double t_xy = y_first ? walk.t_next[1] : walk.t_next[0];
    const bool z_first = walk.t_next[2] < t_xy;
    const int s = z_first ? 2 : int(y_first);
    const double t_exit = z_first ? walk.t_next[2] : t_xy;
    if (t_exit > walk.stop) return false;
    uint32_t id = walk.active[s];
    int64_t from = 0;
    cursor.climbed = 0;
    bool held = false;
    for (;; ++cursor.climbed) {
      if (id == kNone) return false;  // left the scene
      const Node& up = nodes_[id];
      GRIDSCOPE_CHECK(context.states[up.state].stamp == walk.ray_id);
      from = context.states[up.state].index + walk.step[s] - up.first_cell;
      if (uint64_t(from) < up.granularity) break;
      id = up.above[s];
      if (up.passed[s] != kNone && (held = held_by_chain(up.passed[s], id, s, walk, context)))
        break;
    }
    if (held) continue;  // on to the wall the chain's nodes on the other axes put first
    // The step happens in node `id`: the other axes' positions come from the nodes above
    // it; usually they already are (the step happened in the deepest node).
    const Node& moved = nodes_[id];
    activate(s, id, moved.state, walk);
    for (int c = 0; c < 3; ++c) {
      if (c == s || walk.active[c] == moved.above[c]) continue;
      const uint32_t above = moved.above[c];
      activate(c, above, state_of(above, c), walk);
      walk.t_next[c] = context.states[walk.active_state[c]].t_next;
    }
    cursor.t = t_exit, cursor.entered = s;
    const int64_t cell = seek(id, from, false, cursor, walk, context, recorder);
    if (cell < 0) continue;  // the ray meets nothing more in this node: on to the next wall
    cursor.node = id, cursor.local = uint32_t(cell);
    cursor.ref = refs_[moved.children + uint32_t(cell)].load(std::memory_order_acquire);
    return true;
  }
}

// The triangles of a cell worth a look: its leaf, or (kUnbuilt) its voxel's id list.
LeafView Grid1D::leaf_of(uint32_t ref, Context& context) const {
  return child_ref::kind(ref) == child_ref::kLeaf ? leaves_.view(child_ref::payload(ref))
                                                  : unbuilt_leaf(child_ref::payload(ref), context);
}

// Makes `node` the one whose state gives the ray's position on axis a.
inline void Grid1D::activate(int a, uint32_t node, uint32_t state, RayWalk& walk) const {
  walk.active[a] = node, walk.active_state[a] = state;
}

// In node `id`, the first cell from cell `from` on (in the ray's direction along the node's
// axis) whose contents the ray meets, if the ray enters it before leaving the node and before
// the stop distance: the node's state moves there and the cursor's t and entered axis
// become where and how the ray enters it (`from` itself with `from_is_current` is the cell
// the ray is in: nothing moves). Cells are tested four at a time, nearest first, as long as
// the ray reaches them before that limit. Otherwise -1, and the walk's next wall on the
// node's axis becomes where the ray would meet that cell or leave the node's array, so that
// the next step takes whichever wall comes first. The state moves to the array's last cell
// only when the ray leaves the array through its end: a state always tells where the ray is,
// until its t_next.
template <class Recorder>
[[gnu::always_inline]] inline int64_t Grid1D::seek(uint32_t id, int64_t from, bool from_is_current,
                                                   Cursor& cursor, RayWalk& walk, Context& context,
                                                   Recorder& recorder) const {
  const Node& node = nodes_[id];
  const int b = node.axis, d = walk.step[b];
  const int64_t g = node.granularity;
  Context::StateValues& values = context.states[node.state];
  const double other = std::min(walk.t_next[kNextAxis[b]], walk.t_next[kNextAxis[b + 1]]);
  const double limit = std::min(other, walk.stop);
  const float* boxes = &child_boxes_[node.boxes];
  // Where the ray enters cell `cell` (a wall of the state's grid).
  const auto entry = [&](int64_t cell) {
    return values.exit_distance(node.first_cell + cell - d, d);
  };
  // Groups of four cells (box_group), from the one holding `from`, whose cells before
  // `from` are masked off; the last group's cells past g have empty boxes. Groups of empty
  // cells are passed over without a test (Node::occupied): a bit scan finds the group of the
  // next cell that holds triangles, and the walk stops where the tests would have stopped,
  // at a group the ray enters beyond the limit (the tests would have found nothing before
  // it: an empty cell's box is empty).
  const int64_t from_group = from & ~int64_t{3};
  int64_t cell = -1;
  if (d > 0) {
    uint32_t ahead = ~0u << (from & 3);
    for (int64_t group = from_group; group < g; group += 4, ahead = ~0u) {
      const int64_t next = node.occupied_from(std::max(group, from), g);
      if (next >= g) break;
      if (next >= group + 4) {
        group = next & ~int64_t{3}, ahead = ~0u;
        if (entry(group) > limit) break;
      }
      const uint32_t met =
          walk.boxes->crossed_group(boxes + 6 * group, walk.t_lo, walk.t_hi) & ahead;
      if (met != 0) {
        cell = group + std::countr_zero(met);
        break;
      }
      if (group + 4 < g && entry(group + 4) > limit) break;
    }
  } else if (d < 0) {
    uint32_t ahead = (2u << (from & 3)) - 1u;
    for (int64_t group = from_group; group >= 0; group -= 4, ahead = 15u) {
      const int64_t next = node.occupied_to(std::min(group + 3, from));
      if (next < 0) break;
      if (next < group) {
        group = next & ~int64_t{3}, ahead = 15u;
        if (entry(group + 3) > limit) break;
      }
      const uint32_t met =
          walk.boxes->crossed_group(boxes + 6 * group, walk.t_lo, walk.t_hi) & ahead;
      if (met != 0) {
        cell = group + std::bit_width(met) - 1;
        break;
      }
      if (group > 0 && entry(group - 1) > limit) break;
    }
  } else if (walk.boxes->crossed_group(boxes + 6 * from_group, walk.t_lo, walk.t_hi) >> (from & 3) &
             1u) {
    cell = from;
  }
  // The recorder counts the walls crossed on the node's axis (Walk::cells_crossed): from the
  // ray's slab to `slab`.
  const auto cross_to = [&](int64_t slab) {
    if constexpr (Recorder::kRecords) recorder.crossed(std::abs(slab - values.index));
  };
  if (cell >= 0) {
    GRIDSCOPE_CHECK(cell < g);
    if (cell == from && from_is_current) return cell;
    const double t_in = entry(cell);
    if (t_in <= limit) {
      cross_to(node.first_cell + cell);
      values.index = node.first_cell + cell;
      values.t_next = walk.t_next[b] = values.exit_distance(values.index, d);
      cursor.t = t_in, cursor.entered = b;
      return cell;
    }
    walk.t_next[b] = t_in;  // the ray leaves the node through another wall first
    if constexpr (Recorder::kRecords) cross_to(slab_at(node, limit, walk));
    return -1;
  }
  const int64_t end = node.first_cell + (d > 0 ? g - 1 : 0);
  const double t_end = d == 0 ? kInf : values.exit_distance(end, d);
  if constexpr (Recorder::kRecords)
    if (d != 0) cross_to(t_end <= limit ? end : slab_at(node, limit, walk));
  if (t_end <= other) values.index = end, values.t_next = t_end;
  walk.t_next[b] = t_end;
  return -1;
}

// The slab of node `node`'s grid the ray is in at t, clamped to the node's cells (the first
// for a t that gives no position): how far a ray that leaves the node through another axis's
// wall, or stops, has got along the node's axis (for the recorder). descend locates a point
// the same way; one shared helper cost the timed walk 0.8% more instructions per ray (pyramid
// 1,650 -> 1,664, bunny-sibenik 6,009 -> 6,072), so the formula stays in both.
int64_t Grid1D::slab_at(const Node& node, double t, const RayWalk& walk) const {
  const StateInfo& info = states_[node.state];
  const double p = walk.line.origin[node.axis] + t * walk.line.dir[node.axis];
  const double cell = (p - info.origin) * info.scale - double(node.first_cell);
  // max(0, NaN) is 0: both comparisons are false for NaN.
  return node.first_cell + int64_t(std::max(0.0, std::min(cell, double(node.granularity - 1))));
}

// §5.2: into node `id`, which the ray occupies at t_cur, setting its traversal state, and
// returns the cell the ray is in. The §5.2.2 cases: a state this ray used and has not yet
// left needs nothing; entering through a wall on the node's own axis puts the ray in the
// first or last cell (figure 7); otherwise the cell comes from the point. A state is
// initialised only when a ray first needs it (its stamp is another ray's).
template <class Recorder>
[[gnu::always_inline]] inline int64_t Grid1D::descend(uint32_t id, double t_cur, int entered_axis,
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
      values.t_origin = (info.origin - walk.line.origin[b]) * walk.line.inv_dir[b];
      values.t_width = info.width * walk.line.inv_dir[b];
    }
    if (int(b) == entered_axis) {
      local = walk.step[b] > 0 ? 0 : g - 1;
    } else {
      // Clamped first, then truncated: truncation is floor for what is left, and much
      // cheaper than std::floor on baseline x86-64 (no SSE4.1 round instruction).
      const double p = walk.line.origin[b] + t_cur * walk.line.dir[b];
      const double cell = (p - info.origin) * info.scale - double(first);
      local = int64_t(std::clamp(cell, 0.0, double(g - 1)));
    }
    values.index = first + local;
    values.t_next = walk.step[b] == 0 ? kInf : values.exit_distance(values.index, walk.step[b]);
  }
  GRIDSCOPE_CHECK(local >= 0 && local < g);
  activate(int(b), id, node.state, walk);
  walk.t_next[b] = values.t_next;
  ++context.counters.descents;
  recorder.descent(id, local, state_case);
  return local;
}

// A voxel another thread is still cutting, or a leaf the memory budget left without its
// leaf block: its triangles, copied into the kernel's form in the thread's scratch, for
// the one leaf loop.
LeafView Grid1D::unbuilt_leaf(uint32_t id, Context& context) const {
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
  return {context.scratch_coords.data(), context.scratch_ids.data(), n};
}

}  // namespace gs
