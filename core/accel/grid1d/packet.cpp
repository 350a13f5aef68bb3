// Rays walked together (docs/design.md §6.9): a tile's primary rays, or their shadow rays
// toward one light, go down the 1D grid as one packet. In each subdivided voxel the packet
// takes the voxel's cells front to back along its axis (§4: a voxel is one 1D array, and the
// rays of a packet share their direction's signs, so this is every ray's own order of
// cells), four at a time: the packet's bounds rule out the groups no ray can meet, and in
// the others each ray not done is box-tested against each cell's content box, several rays
// at a time; those that meet it go in. In a leaf the rays test the triangles whose boxes
// they cross, rays in lanes, or one at a time as a single ray does when few rays are spread
// over the packet's lane groups (a dense mesh reached by part of the tile).
//
// Exact per ray: the point of a ray's nearest hit lies in one leaf's cell and in every cell
// above it, and each of their content boxes holds it (docs/design.md §6.7), so the ray
// meets them all and goes down to that leaf (perhaps to others too); the nearest hit
// (lowest id on equal t) does not depend on the order of tests, so each answer is the
// single-ray and brute-force answer bit for bit. Empty cells cost the packet one load,
// whatever its size; a cell is built lazily when the first ray goes into it, as a single
// ray builds it.
#include <algorithm>
#include <bit>
#include <cmath>

#include "core/accel/grid1d/records.h"
#include "core/base/bit_count.h"
#include "core/base/check.h"

namespace gs {

// The packet: its rays, the direction its cells are taken in on each axis, and the rays
// that are done (any-hit rays that found a blocker).
struct Grid1D::PacketWalk {
  Context& context;
  Hit* best;       // per ray: its nearest hit so far
  uint32_t count;  // rays walking together
  uint64_t id;     // the packet's number, for its mailbox
  int step[3];     // +1 or -1: the order of cells along each axis
  uint64_t done = 0;
};

namespace {

constexpr size_t kMaxRays = Accelerator::kMaxPacketRays;
static_assert(kMaxRays <= 64, "a packet's rays are the bits of a 64-bit mask");

// Fewer rays than this going the same way are traced one by one: a packet's walk costs
// more per ray than a single ray's when it carries almost nobody.
constexpr size_t kMinPacketRays = 2;

template <class Each>
void for_each_ray(uint64_t rays, Each&& each) {
  for (; rays != 0; rays &= rays - 1) each(uint32_t(std::countr_zero(rays)));
}

}  // namespace

// Keys matter only to structures that answer by key (the oracle).
void Grid1D::trace_packet(std::span<const Ray> rays, std::span<const uint64_t> /*keys*/,
                          std::span<Hit> hits, bool any_hit, ThreadContext& context) const {
  GRIDSCOPE_CHECK(rays.size() <= kMaxRays && hits.size() == rays.size());
  Context& own = static_cast<Context&>(context);
  if (any_hit)
    trace_together<true>(rays, hits, own);
  else
    trace_together<false>(rays, hits, own);
}

// Rays going the same way (the same octant and dominant axis, so the same order of cells
// and the same kernel axes) walk together: one group per way, in the order of their first
// rays, so that a tile astride the boundary of two ways walks as two packets. A way taken by
// fewer than kMinPacketRays rays is traced a ray at a time by the single-ray walk, and so is
// a ray from far away (WalkLine::far): it tests no content box, so in a packet it would go
// into every cell; its single walk crosses only the cells on its line. A ray keeps its
// number in the packet: masks and lanes are indexed by it.
template <bool AnyHit>
void Grid1D::trace_together(std::span<const Ray> rays, std::span<Hit> hits,
                            Context& context) const {
  PacketLines& lines = context.packet_lines;
  const auto count = uint32_t(rays.size());
  for (uint32_t i = 0; i < count; ++i) lines.set_ray(i, rays[i]);
  const uint64_t started = lane_ops_.start(input_.clip, count, lines);
  uint64_t single = started & lines.far;
  for (uint64_t left = started & ~lines.far; left != 0;) {
    const int32_t kind = lines.kind[std::countr_zero(left)];  // octant and kz
    uint64_t group = 0;
    for_each_ray(left, [&](uint32_t i) { group |= uint64_t(lines.kind[i] == kind) << i; });
    left &= ~group;
    if (count_ones(group) < kMinPacketRays) {
      single |= group;
      continue;
    }
    walk_together<AnyHit>(group, kind, hits.data(), context);
  }
  context.counters.packet_fallback_rays += count_ones(single);
  for_each_ray(single, [&](uint32_t i) {
    hits[i] = AnyHit ? any_hit(rays[i], context) : intersect(rays[i], context);
  });
  const uint64_t all = count == 64 ? ~uint64_t{0} : (uint64_t{1} << count) - 1;
  for_each_ray(all & ~started, [&](uint32_t i) { hits[i] = Hit{}; });
}

// Walks `rays` (started, all of one kind) as one packet from the root, leaving each ray's
// answer in best[ray].
template <bool AnyHit>
void Grid1D::walk_together(uint64_t rays, int32_t kind, Hit* best, Context& context) const {
  // The kernel's axes (PreparedRay: kz the largest component, then kx, ky, swapped to keep
  // the winding when the ray runs down kz) and the box test's face order, from the kind.
  RayLanes& lanes = context.ray_lanes;
  lanes.kz = kind >> 3;
  shear_axes(lanes.kz, kind >> lanes.kz & 1, lanes.kx, lanes.ky);
  RayBoxLanes& box_lanes = context.ray_box_lanes;
  for (uint32_t a = 0; a < 3; ++a) {
    const bool toward_lo = kind >> a & 1;
    box_lanes.near_array[a] = near_face_array(a, toward_lo);
    box_lanes.far_array[a] = far_face_array(a, toward_lo);
  }
  PacketLines& lines = context.packet_lines;
  const int axes[3] = {lanes.kx, lanes.ky, lanes.kz};
  lane_ops_.prepare(lines, rays, axes, lanes, box_lanes);
  PacketWalk walk{context, best, count_ones(rays), context.packet_mailbox.next_packet(), {}, 0};
  for (int a = 0; a < 3; ++a) walk.step[a] = kind >> a & 1 ? -1 : 1;
  for_each_ray(rays, [&](uint32_t i) { best[i] = Hit{}; });
  visit<AnyHit>(root_ref_.load(std::memory_order_acquire), rays, walk);
  ++context.counters.packets;
  context.counters.packet_rays += walk.count;
}

// Takes `rays` (a mask of the packet's rays, each meeting the content box of the cell
// `ref`, or starting in the scene box for the root) into the cell: builds it if no ray has,
// and searches or walks it.
template <bool AnyHit>
void Grid1D::visit(uint32_t ref, uint64_t rays, PacketWalk& walk) const {
  for (;;) {
    switch (child_ref::kind(ref)) {
      case child_ref::kUnbuilt: {
        const uint32_t built = examine(child_ref::payload(ref), walk.context);
        if (built != ref) {
          ref = built;
          continue;
        }
        search_leaf<AnyHit>(unbuilt_leaf(child_ref::payload(ref), walk.context), rays, walk);
        return;
      }
      case child_ref::kLeaf:
        search_leaf<AnyHit>(leaves_.view(child_ref::payload(ref)), rays, walk);
        return;
      case child_ref::kEmpty:
        return;
      case child_ref::kNode:
        visit_node<AnyHit>(child_ref::payload(ref), rays, walk);
        return;
    }
  }
}

// The cells of node `id`, front to back along its axis in the packet's direction (§5.3's
// order for every ray of the packet), four at a time. A group whose four content boxes the
// packet's bounds rule out (RayBoxBounds) costs one test for the whole packet; an empty cell
// one load. Otherwise the rays not done are box-tested against the cell's content box
// several at a time, and those that meet it go in.
template <bool AnyHit>
void Grid1D::visit_node(uint32_t id, uint64_t rays, PacketWalk& walk) const {
  const Node& node = nodes_[id];
  const uint32_t g = node.granularity;
  const bool ascending = walk.step[node.axis] > 0;
  const float* boxes = &child_boxes_[node.boxes];
  const RayBoxLanes& box_lanes = walk.context.ray_box_lanes;
  TraceCounters& counters = walk.context.counters;
  // No ray of the packet's bounds meets the node's summary: nothing here for any of them.
  if (box_lanes.may_cross4(&child_boxes_[node.summary()], 4, 0) == 0) return;
  // The node's spanning triangles first (Node::spanning): their hits move the rays' stop
  // distances in before the cells are tested.
  if (node.spanning != Node::kNoSpanning)
    search_leaf<AnyHit>(leaves_.view(node.spanning), rays, walk);
  const uint32_t groups = (g + 3) / 4;
  for (uint32_t k = 0; k < groups; ++k) {
    const uint32_t first = 4 * (ascending ? k : groups - 1 - k);
    if (!node.group_occupied(first)) continue;  // four empty cells: not even the bounds test
    const float* group = box_group(boxes, first);
    const uint32_t cells = g - first < 4 ? (1u << (g - first)) - 1 : 15u;  // none past g
    for (uint32_t left = box_lanes.may_cross4(group, 4, 0) & cells; left != 0;) {
      // The group's nearest cell left, in the packet's direction.
      const uint32_t lane =
          ascending ? uint32_t(std::countr_zero(left)) : 31u - uint32_t(std::countl_zero(left));
      left &= ~(1u << lane);
      const uint32_t ref = refs_[node.children + first + lane].load(std::memory_order_acquire);
      if (child_ref::kind(ref) == child_ref::kEmpty) continue;
      const uint64_t candidates = rays & ~walk.done;
      if (candidates == 0) return;
      uint64_t meeting = 0;
      if (!kernel_.rays_crossed(box_lanes, group, 4, lane, 1, candidates, &meeting)) continue;
      ++counters.packet_steps;
      counters.packet_step_rays += count_ones(meeting);
      counters.packet_step_slots += walk.count;
      visit<AnyHit>(ref, meeting, walk);
    }
  }
}

// Each of `rays` not done searches the leaf (docs/design.md §6.9): the rays that cross a
// triangle's box (as the single-ray leaf loop filters, docs/design.md §6.7) test it. The box
// tests of a run of triangles are made together, with the segments the rays had on entering
// the leaf (those change only after the search): first the packet's bounds against several
// boxes at a time, which rules out the boxes no ray can cross, then each group of rays,
// loaded once, against the boxes left; or, when that costs more (searches_alone), each ray
// against the run's boxes, several at a time, as the single walk tests them.
template <bool AnyHit>
void Grid1D::search_leaf(const LeafView& leaf, uint64_t rays, PacketWalk& walk) const {
  Context& context = walk.context;
  RayBoxLanes& box_lanes = context.ray_box_lanes;
  uint64_t searching = rays & ~walk.done, improved = 0;
  context.counters.traversal_steps += count_ones(searching);
  context.counters.leaf_triangles += uint64_t(count_ones(searching)) * leaf.count;
  constexpr uint32_t kRun = 64;
  uint64_t crossing[kRun];
  for (uint32_t base = 0; base < leaf.count && searching != 0; base += kRun) {
    const uint32_t run = std::min(kRun, leaf.count - base);
    uint64_t crossed = run == kRun ? ~uint64_t{0} : (uint64_t{1} << run) - 1;
    if (leaf.boxes != nullptr) {
      const uint32_t stride = box_stride(leaf.count);
      // The bounds test first: it rules out whole boxes.
      const uint64_t may_cross = kernel_.bounds_crossed(box_lanes, leaf.boxes, stride, base, run);
      if (searches_alone(searching, may_cross, run, kernel_.box_lanes)) {
        search_alone<AnyHit>(leaf, base, run, may_cross, searching, improved, walk);
        continue;
      }
      crossed =
          kernel_.rays_crossed(box_lanes, leaf.boxes, stride, base, may_cross, searching, crossing);
    } else {
      std::fill(crossing, crossing + run, searching);
    }
    for (; crossed != 0 && searching != 0; crossed &= crossed - 1)
      test_crossers<AnyHit>(leaf, base + uint32_t(std::countr_zero(crossed)),
                            searching & crossing[std::countr_zero(crossed)], searching, improved,
                            walk);
  }
  if (AnyHit) return;
  PacketLines& lines = context.packet_lines;
  const RayLanes& lanes = context.ray_lanes;
  for_each_ray(improved, [&](uint32_t r) {
    lines.stop[r] = walk_stop(lanes.tmax[r], lines.slack[r], lines.shift[r]);
    box_lanes.set_end(r, box_test_end(false, lines.shift[r], lines.stop[r]));
  });
}

// One ray of a packet as the single-ray leaf search sees the packet's mailbox.
struct PacketRayMailbox {
  PacketMailbox& mailbox;
  uint64_t packet, ray;
  bool already_tested(uint32_t triangle, uint64_t /*ray_id*/) {
    return mailbox.mark(triangle, packet, ray) != 0;
  }
};

// The rays of `searching`, one at a time, search boxes base .. base + run - 1 of the leaf
// (those of `may_cross`) as the single walk does: the same box test and triangle test lane
// by lane, so each ray's answer is the one it has in the packet's search (bit for bit).
template <bool AnyHit>
void Grid1D::search_alone(const LeafView& leaf, uint32_t base, uint32_t run, uint64_t may_cross,
                          uint64_t& searching, uint64_t& improved, PacketWalk& walk) const {
  Context& context = walk.context;
  const RayBoxLanes& box_lanes = context.ray_box_lanes;
  RayLanes& lanes = context.ray_lanes;
  const uint32_t stride = box_stride(leaf.count);
  NoLeafRecord record;
  for_each_ray(searching, [&](uint32_t r) {
    const uint64_t bit = uint64_t{1} << r;
    const uint64_t crossed =
        may_cross & kernel_.boxes_crossed(box_lanes.single(r), leaf.boxes, stride, base, run,
                                          _mm_set1_ps(box_lanes.t0[r]),
                                          _mm_set1_ps(box_lanes.t1[r]));
    PacketRayMailbox mailbox{context.packet_mailbox, walk.id, bit};
    if (!test_crossed<AnyHit>(leaf, kernel_, lanes.prepared(r), base, crossed, 0, lanes.tmax[r],
                              walk.best[r], mailbox, context.counters, record))
      return;
    improved |= bit;
    if (AnyHit) walk.done |= bit, searching &= ~bit;
  });
}

// Triangle i of the leaf against `crossers`, the searching rays that cross its box: those
// that have not tested it yet (the packet's mailbox) are tested several at a time, rays in
// lanes, each up to its own nearest hit; a hit moves the ray's stop distance in.
template <bool AnyHit>
[[gnu::always_inline]] inline void Grid1D::test_crossers(const LeafView& leaf, uint32_t i,
                                                         uint64_t crossers, uint64_t& searching,
                                                         uint64_t& improved,
                                                         PacketWalk& walk) const {
  if (crossers == 0) return;
  Context& context = walk.context;
  TraceCounters& counters = context.counters;
  const uint32_t id = leaf.ids[i];
  const uint64_t already = id & kOnlyHere ? 0 : context.packet_mailbox.mark(id, walk.id, crossers);
  counters.mailbox_rejections += count_ones(already);
  const uint64_t testing = crossers & ~already;
  if (testing == 0) return;
  counters.intersection_tests += count_ones(testing);
  const auto triangle = int32_t(leaf.id(i));
  RayLanes& lanes = context.ray_lanes;
  RayHits& out = context.ray_hits;
  for_each_ray(kernel_.test_rays(leaf, i, lanes, testing, out), [&](uint32_t r) {
    if (!closer(out.t[r], triangle, walk.best[r])) return;
    walk.best[r] = {triangle, out.t[r], out.u[r], out.v[r]};
    lanes.tmax[r] = out.t[r];
    improved |= uint64_t{1} << r;
    if (!AnyHit) return;
    walk.done |= uint64_t{1} << r;
    searching &= ~(uint64_t{1} << r);
  });
}

}  // namespace gs
