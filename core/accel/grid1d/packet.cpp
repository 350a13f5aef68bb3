// Rays walked together (docs/design.md §6.9): a tile's primary rays, or their shadow rays
// toward one light, go down the 1D grid as one packet. In each subdivided voxel the packet
// takes the cells its rays' segments cover, front to back along the voxel's axis (§4: a
// voxel is one 1D array, so a packet's part of it is one interval of cells); each cell is
// stepped into by the rays whose own segment crosses it (walls in double, widened by the
// ray's slack) and whose own content-box test says its contents lie on the ray, each ray
// as far as its own nearest hit allows. Leaves are searched ray by ray by the one leaf loop.
//
// Exact per ray: a ray is tested against every cell its padded segment crosses up to its
// stop distance (a superset of what its single-ray walk needs), and the nearest hit (lowest
// id on equal t) does not depend on the order of tests, so each answer is the single-ray
// and brute-force answer bit for bit. Empty cells cost the packet one load, whatever its
// size; a cell is built lazily when the first ray steps into it, as a single ray builds it.
#include <algorithm>
#include <bit>
#include <cmath>

#include "core/accel/grid1d/records.h"
#include "core/base/check.h"

namespace gs {

// The packet: its rays, the direction its cells are taken in on each axis, and the rays
// that are done (any-hit rays that found a blocker).
struct Grid1D::PacketWalk {
  std::vector<PacketRay>& rays;
  Context& context;
  uint64_t id;  // the packet's number, for its mailbox
  int step[3];  // +1 or -1: the order of cells along each axis
  uint64_t done = 0;
};

namespace {

constexpr size_t kMaxRays = Accelerator::kMaxPacketRays;
static_assert(kMaxRays <= 64, "a packet's rays are the bits of a 64-bit mask");

// Fewer rays than this going the same way are traced one by one: a packet's walk costs
// more per ray than a single ray's when it carries almost nobody.
constexpr size_t kMinPacketRays = 2;

// The octant of a direction: bit a set when its component a has its sign bit set (-0 too:
// the box tests meet a box's faces in the order of the sign bits).
int octant(const double dir[3]) {
  return std::signbit(dir[0]) | std::signbit(dir[1]) << 1 | std::signbit(dir[2]) << 2;
}

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

// Rays going the way the packet's first ray goes (the same octant and dominant axis, so the
// same order of cells and the same kernel axes) walk together; the others (and a packet of
// one) are traced one at a time by the single-ray walk.
template <bool AnyHit>
void Grid1D::trace_together(std::span<const Ray> rays, std::span<Hit> hits,
                            Context& context) const {
  std::vector<PacketRay>& packet = context.packet;
  packet.clear();
  packet.reserve(kMaxRays);
  uint32_t index[kMaxRays];
  // Zero past the packet's last ray: the lanes read whole groups (packet_lanes.h).
  alignas(64) double t_in[kPacketLanes] = {}, t_out[kPacketLanes] = {};
  int packet_kind = -1;  // octant and dominant axis (which fixes the kernel's axis order)
  uint64_t single = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    hits[i] = Hit{};
    WalkLine line;
    if (!start_walk(input_.clip, rays[i], line)) continue;
    const PacketRay& ray = packet.emplace_back(rays[i], line);
    const int kind = octant(line.dir) | ray.prepared.kz << 3;
    if (packet_kind < 0) packet_kind = kind;
    if (kind != packet_kind) {
      single |= uint64_t{1} << i;
      packet.pop_back();
      continue;
    }
    index[packet.size() - 1] = uint32_t(i);
    t_in[packet.size() - 1] = line.t0, t_out[packet.size() - 1] = line.t1;
  }
  TraceCounters& counters = context.counters;
  if (packet.size() < kMinPacketRays) {
    for (size_t k = 0; k < packet.size(); ++k) single |= uint64_t{1} << index[k];
    packet.clear();
  }
  if (!packet.empty()) {
    // The rays in lanes, by their number in the packet, for the box tests and the kernel.
    RayLanes& lanes = context.ray_lanes;
    const PreparedRay<KernelReal>& first = packet.front().prepared;
    lanes.count = 0, lanes.kx = first.kx, lanes.ky = first.ky, lanes.kz = first.kz;
    for (uint32_t r = 0; r < packet.size(); ++r) {
      PacketRay& ray = packet[r];
      lanes.add(ray.prepared, ray.tmax);
      context.packet_lines.set(r, ray.line);
      set_stop(ray.line, ray.tmax, context.packet_lines.stop[r], ray.t_hi);
      context.ray_box_lanes.set(r, ray.boxes, ray.t_lo, ray.t_hi);
    }
    PacketWalk walk{packet, context, context.packet_mailbox.next_packet(), {}, 0};
    for (int a = 0; a < 3; ++a) walk.step[a] = packet_kind >> a & 1 ? -1 : 1;
    const uint64_t all = packet.size() == 64 ? ~uint64_t{0} : (uint64_t{1} << packet.size()) - 1;
    visit<AnyHit>(root_ref_.load(std::memory_order_acquire), all, t_in, t_out, walk);
    for (size_t k = 0; k < packet.size(); ++k) hits[index[k]] = packet[k].best;
    ++counters.packets;
    counters.packet_rays += packet.size();
  }
  counters.packet_fallback_rays += uint64_t(std::popcount(single));
  for_each_ray(single, [&](uint32_t i) {
    hits[i] = AnyHit ? any_hit(rays[i], context) : intersect(rays[i], context);
  });
}

// Takes `rays` (a mask of the packet's rays, each inside the cell `ref` from t_in to t_out
// on its line) into the cell: builds it if no ray has, and searches or walks it.
template <bool AnyHit>
void Grid1D::visit(uint32_t ref, uint64_t rays, const double* t_in, const double* t_out,
                   PacketWalk& walk) const {
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
        visit_node<AnyHit>(child_ref::payload(ref), rays, t_in, t_out, walk);
        return;
    }
  }
}

// The cells of node `id` the rays cover, front to back (§5.3's order, for the packet's
// direction on the node's axis): per ray the cells between where its point lies at t_in and
// at t_out, one more each side (point location rounds; the walls below decide). Per cell,
// the rays that cover it are box-tested four at a time against the cell's content box, and
// those that meet it step in between its walls (each wall distance as the single walk's
// traversal state computes it, t_origin + I * t_width, widened by the slack) if they enter
// before their stop distance.
template <bool AnyHit>
void Grid1D::visit_node(uint32_t id, uint64_t rays, const double* t_in, const double* t_out,
                        PacketWalk& walk) const {
  const Node& node = nodes_[id];
  const int b = node.axis;
  const int64_t g = node.granularity, first = node.first_cell;
  const StateInfo& info = states_[node.state];
  const PacketLines& lines = walk.context.packet_lines;
  PacketCover cover;
  lane_ops_.cover(lines, {b, info.origin, info.scale, info.width, double(first), double(g - 1)},
                  rays, t_in, t_out, cover);
  const float* boxes = &child_boxes_[node.boxes];
  const uint32_t stride = box_stride(node.granularity);
  const RayBoxLanes& box_lanes = walk.context.ray_box_lanes;
  alignas(64) double child_in[kPacketLanes], child_out[kPacketLanes];
  TraceCounters& counters = walk.context.counters;
  // Which rays cover the k-th cell in the packet's order: over a short run of cells, from
  // where each ray's cells begin and end in it, kept as the cells go by; otherwise per cell.
  const int64_t cover_lo = cover.cover_lo, cover_hi = cover.cover_hi;
  const int64_t run = cover_hi - cover_lo + 1;
  const bool by_events = run <= int64_t(kMaxRays);
  uint64_t begins[kMaxRays + 1], ends[kMaxRays + 1];
  if (by_events) {
    std::fill(begins, begins + run + 1, uint64_t{0});
    std::fill(ends, ends + run + 1, uint64_t{0});
    for_each_ray(rays, [&](uint32_t r) {
      const int64_t from = walk.step[b] > 0 ? cover.lo[r] - cover_lo : cover_hi - cover.hi[r];
      begins[from] |= uint64_t{1} << r,
          ends[from + cover.hi[r] - cover.lo[r] + 1] |= uint64_t{1} << r;
    });
  }
  uint64_t covering = 0;
  for (int64_t k = 0; k < run; ++k) {
    const int64_t cell = walk.step[b] > 0 ? cover_lo + k : cover_hi - k;
    if (by_events) covering = (covering | begins[k]) & ~ends[k];
    const uint32_t ref = refs_[node.children + uint32_t(cell)].load(std::memory_order_acquire);
    if (child_ref::kind(ref) == child_ref::kEmpty) continue;
    if (!by_events) {
      covering = 0;
      for_each_ray(rays, [&](uint32_t r) {
        covering |= uint64_t(cell >= cover.lo[r] && cell <= cover.hi[r]) << r;
      });
    }
    const uint64_t candidates = covering & ~walk.done;
    if (candidates == 0) continue;
    const uint64_t meeting =
        candidates & kernel_.rays_crossed(box_lanes, boxes, stride, uint32_t(cell), candidates);
    if (meeting == 0) continue;
    const uint64_t entering = lane_ops_.enter(lines, b, cover, double(first + cell), meeting, t_in,
                                              t_out, child_in, child_out);
    if (entering == 0) continue;
    ++counters.packet_steps;
    counters.packet_step_rays += uint64_t(std::popcount(entering));
    counters.packet_step_slots += walk.rays.size();
    visit<AnyHit>(ref, entering, child_in, child_out, walk);
  }
}

// Each of `rays` not done searches the leaf (docs/design.md §6.9): triangle by triangle,
// the rays that have not tested it yet (the packet's mailbox) and cross its box (as the
// single-ray leaf loop filters, docs/design.md §6.7) are tested several at a time, rays in
// lanes, each up to its own nearest hit; a hit moves the ray's stop distance in.
template <bool AnyHit>
void Grid1D::search_leaf(const LeafView& leaf, uint64_t rays, PacketWalk& walk) const {
  Context& context = walk.context;
  TraceCounters& counters = context.counters;
  RayLanes& lanes = context.ray_lanes;
  RayBoxLanes& box_lanes = context.ray_box_lanes;
  RayHits& out = context.ray_hits;
  uint64_t searching = rays & ~walk.done, improved = 0;
  counters.traversal_steps += uint64_t(std::popcount(searching));
  for (uint32_t i = 0; i < leaf.count && searching != 0; ++i) {
    const uint32_t id = leaf.ids[i];
    const uint64_t already =
        id & kOnlyHere ? 0 : context.packet_mailbox.mark(id, walk.id, searching);
    counters.mailbox_rejections += uint64_t(std::popcount(already));
    uint64_t testing = searching & ~already;
    if (leaf.boxes)
      testing &= kernel_.rays_crossed(box_lanes, leaf.boxes, box_stride(leaf.count), i, testing);
    if (testing == 0) continue;
    counters.intersection_tests += uint64_t(std::popcount(testing));
    const auto triangle = int32_t(leaf.id(i));
    for_each_ray(kernel_.test_rays(leaf, i, lanes, testing, out), [&](uint32_t r) {
      PacketRay& ray = walk.rays[r];
      if (!closer(out.t[r], triangle, ray.best)) return;
      ray.best = {triangle, out.t[r], out.u[r], out.v[r]};
      ray.tmax = lanes.tmax[r] = out.t[r];
      improved |= uint64_t{1} << r;
      if (!AnyHit) return;
      walk.done |= uint64_t{1} << r;
      searching &= ~(uint64_t{1} << r);
    });
  }
  if (AnyHit) return;
  for_each_ray(improved, [&](uint32_t r) {
    PacketRay& ray = walk.rays[r];
    set_stop(ray.line, ray.tmax, context.packet_lines.stop[r], ray.t_hi);
    box_lanes.set_end(r, ray.t_hi);
  });
}

}  // namespace gs
