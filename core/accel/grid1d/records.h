// The 1D grid's records, shared by its build (build.cpp) and its walk (walk.cpp); nothing
// outside the grid includes this file.
#pragma once
#include <bit>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/accel/grid1d/grid1d.h"
#include "core/accel/grid1d/packet_lanes.h"
#include "core/base/check.h"
#include "core/geometry/box_test.h"
#include "core/geometry/clip_box.h"

namespace gs {

// Where a voxel is and what the build knows about it. Cold data: read only when the voxel
// is examined, by the inspector and by the walk recorder. Immutable once its parent is
// published, but for mean_size, which the thread that examines the voxel writes.
struct Grid1D::Region {
  uint64_t cell[3];   // the voxel's slab on each axis's grid...
  uint64_t grid[3];   // ... of this granularity (1: the scene box)
  uint32_t above[3];  // node of the nearest ancestor cut along each axis (kNone: the scene box)
  uint32_t depth;
  uint32_t ref;                         // where its child reference is (kNone: the root's)
  uint32_t sample_begin, sample_count;  // sample rays whose segments cross the voxel
  // The scout's voxel in the same place (Grid1D::scout_), when each voxel above was cut the
  // way the scout cut its own: it then holds the same triangles, in the same order. kNone
  // otherwise.
  uint32_t scout_twin;
  double area_rays;  // rays estimated from the parent by surface area (§6.5)
  // Per axis, the mean clipped triangle size (§6.3) the voxel's plan computed; NaN where it
  // computed none (Grid1D::planned_mean_size).
  double mean_size[3];
};

// What the walk reads of a subdivided voxel (§5): one cache line.
struct alignas(64) Grid1D::Node {
  int64_t first_cell;  // J0: index of cell 0 on the state's global grid
  // Which cells hold triangles: bit i for cell i below 63, bit 63 for those from 63 on
  // (set when any of them does). A walk passes a run of empty cells with one bit scan
  // instead of a content box test per group of four, and a packet a group of four empty
  // cells without its bounds test; no answer can change, an empty cell holds nothing to hit.
  uint64_t occupied;
  uint32_t state;     // traversal state (axis, absolute granularity)
  uint32_t above[3];  // nearest ancestor node cut along each axis, or kNone (the box)
  // Per axis, the chain node (sole_cell) that above[] passes by, or kNone: its own above
  // entries on the other axes hold the ray's position while it crosses the chain's empty
  // cells after leaving this node (Grid1D::held_by_chain).
  uint32_t passed[3];
  uint32_t children;  // refs_ index of cell 0's reference
  // child_boxes_ index of the cells' content boxes (in groups of four cells,
  // core/geometry/box_test.h's grouped layout): where each cell's triangles can be hit, so that the
  // walk tests all of them at once and steps only into cells whose contents the ray meets.
  // The group before them (kSummaryFloats) is the node's summary: four boxes whose union
  // holds the cells' content boxes and the spanning triangles' box (write_summary), so that
  // a ray that meets none of them passes the node by as it passes an empty cell, with one
  // test instead of going down into it (docs/design.md §1.3).
  uint32_t boxes;
  // The voxel's triangles that span it along the cut axis (they would lie in every cell),
  // kept here once instead of in each cell: a LeafStore handle, or kNoSpanning. The walk
  // tests them as it goes down into the node, before it looks at the cells, so that the
  // cells' content boxes leave them out (a ground plane across a stadium no longer makes
  // every cell's box as large as the cell) and a hit on them stops the walk early. Never on
  // a chain voxel (sole_cell): the walk passes those without going down into them.
  uint32_t spanning;
  uint16_t granularity;
  // The one cell that holds triangles, or kManyCells. Its contents are all of the voxel's,
  // whose box the walk found the ray to meet when it chose the voxel (one level up, or
  // further up a chain of such voxels): the walk goes down into it without testing its box
  // again. Skipping a box test never changes an answer; the tests only pass over cells. This
  // is the paper's teapot in a stadium: a chain of voxels, each holding the whole cluster in
  // one cell, that every ray toward the cluster crosses.
  uint16_t sole_cell;
  uint8_t axis;
  static constexpr uint16_t kManyCells = UINT16_MAX;
  static constexpr uint32_t kNoSpanning = UINT32_MAX;

  static constexpr uint32_t kSummaryFloats = 24;  // one group of four boxes
  // child_boxes_ index of the node's summary (see `boxes`).
  uint32_t summary() const { return boxes - kSummaryFloats; }

  // The first cell from `cell` on that holds triangles, or `none`.
  int64_t occupied_from(int64_t cell, int64_t none) const {
    if (cell >= 63) return cell;
    const uint64_t ahead = occupied >> cell;
    return ahead != 0 ? cell + std::countr_zero(ahead) : none;
  }
  // The last cell up to `cell` that holds triangles, or -1.
  int64_t occupied_to(int64_t cell) const {
    if (cell >= 63) return cell;
    const uint64_t behind = occupied << (63 - cell);  // cell's bit on top, those past it gone
    return behind != 0 ? cell - std::countl_zero(behind) : -1;
  }
  // Whether a cell of the group of four from `first` (a multiple of 4) holds triangles.
  bool group_occupied(uint32_t first) const {
    return (first < 64 ? occupied >> first & 15u : occupied >> 63) != 0;
  }
};

// A cell's child reference: its kind in the top two bits, so that the walk knows what it
// steps into before loading anything. Published with a release store when the cell is
// examined, read with an acquire load.
namespace child_ref {
enum Kind : uint32_t {
  kUnbuilt = 0u << 30,  // not examined yet (or searched through its id list): payload voxel
  kEmpty = 1u << 30,    // no triangle: payload voxel (for the recorder)
  kLeaf = 2u << 30,     // payload: LeafStore handle
  kNode = 3u << 30,     // subdivided: payload node
};
constexpr uint32_t kPayload = (1u << 30) - 1;
constexpr uint32_t kMaxPayload = kPayload;
inline Kind kind(uint32_t ref) { return Kind(ref & ~kPayload); }
inline uint32_t payload(uint32_t ref) { return ref & kPayload; }
inline uint32_t make(Kind kind, uint32_t payload) {
  GRIDSCOPE_CHECK(payload <= kMaxPayload);
  return uint32_t(kind) | payload;
}
}  // namespace child_ref

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
  std::vector<uint32_t> spanning;  // triangles spanning all g cells: kept at the node
  std::vector<uint32_t> sample_offsets, samples;
  double rays = 0;
  // The scout's node and its first cell's voxel when the scout made this very cut
  // (Grid1D::scout_node): the cells' triangle lists are then the scout's cells' (in
  // tri_indices_, tri_offsets from the first one's tri_begin), their content boxes and the
  // spanning triangles' leaf block the scout's node's, and `tris` stays empty.
  uint32_t scout_node = kNone;
  uint32_t scout_cells = kNone;
};

// Where a ray's search may stop (in its walk line's t): the stop distance of its nearest
// hit so far, or of tmax; and the end of the segment its box tests cover.
inline void set_stop(const WalkLine& line, float tmax, double& stop, __m128& box_test_end_t) {
  stop = line.stop(tmax);
  box_test_end_t = box_test_end(line, stop);
}

// A ray's per-thread traversal scratch. Mailbox and state values belong to the thread: the
// paper's per-object stamp would race between threads (docs/design.md §5). Cache-line
// aligned: two threads' contexts must not share a line.
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
  static_assert(sizeof(StateValues) == 48);

  // The scene box's states (0, 1, 2) are there from the start: every walk sets them.
  explicit Context(const Grid1D& grid) : grid_(grid) { state(2); }
  ~Context() override {
    for (uint32_t id = 0; id < state_count; ++id)
      if (states[id].rays)
        grid_.state_rays_[id].fetch_add(states[id].rays, std::memory_order_relaxed);
  }
  // A state first met by this thread grows the table. The size is kept beside the vector:
  // vector::size() divides by the record's size on every descent.
  StateValues& state(uint32_t id) {
    if (id >= state_count) states.resize(state_count = size_t(id) + 64);
    return states[id];
  }

  Mailbox mailbox;
  std::vector<StateValues> states;
  size_t state_count = 0;
  // A leaf's triangles copied into the kernel's form, for a voxel searched through its id
  // list (being cut by another thread, or left without a leaf block by the memory budget).
  std::vector<float> scratch_coords;
  std::vector<uint32_t> scratch_ids;
  // The rays of the packet being traced (packet_lanes.h), its mailbox, and the rays
  // searching a leaf in the rays-in-lanes forms of the kernel and the box test.
  PacketLines packet_lines;
  PacketMailbox packet_mailbox;
  RayLanes ray_lanes;
  RayBoxLanes ray_box_lanes;
  RayHits ray_hits;

 private:
  const Grid1D& grid_;
};

// One ray's walk: its origin and direction in double and, per axis, the node whose
// traversal state gives the ray's current slab on that axis (§5.3: the current node's own
// axis and the "voxels above" on the two others).
struct Grid1D::RayWalk {
  WalkLine line;       // the line walked (start_walk)
  int step[3];         // +1, -1, or 0 where the direction component is zero
  uint32_t active[3];  // node, or kNone: the scene box
  uint32_t active_state[3];
  double t_next[3];  // the active states' t_next, kept at hand for choosing the step axis
  uint64_t ray_id;
  const PreparedRay<KernelReal>* prepared;
  const RayBoxes* boxes;
  double stop;        // stop_distance of the nearest hit so far (or of tmax)
  __m128 t_lo, t_hi;  // the content boxes' test interval: the box entry to `stop`, in float
  float tmax;
  // Where a ray starting inside the box starts (t0), in float, per axis in all four lanes:
  // holds_start.
  __m128 start[3];
  Hit best;
};

// Where the walk stands: the cell the ray is in and how it got there.
struct Grid1D::Cursor {
  // `entered` when the ray came through no wall: located by its point, and located at the
  // start of a ray that starts inside the scene box (holds_start).
  static constexpr int kLocated = -1;
  static constexpr int kAtStart = -2;
  uint32_t ref;      // the cell's child reference
  double t;          // where the ray entered it (or was located in it)
  int entered;       // the axis of the wall it came through, or kLocated, kAtStart
  uint32_t climbed;  // levels the step into it climbed (§5.3)
  uint32_t node;     // the node whose cell it is (kNone: the root voxel)
  uint32_t local;    // which of the node's cells
};

}  // namespace gs
