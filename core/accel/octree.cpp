#include "core/accel/octree.h"

#include <algorithm>
#include <chrono>
#include <limits>

#include "core/base/timing.h"

namespace gs {
namespace {

// A cut whose children hold this many copies of each triangle on average, one of them all
// of the triangles, separates nothing (see Octree::split).
constexpr uint64_t kInseparableCopies = 2;

}  // namespace

Octree::Octree(const AccelParams& params)
    : depth_(std::clamp(params.depth_or(kDefaultMaxDepth), 1, kDepthCap)),
      leaf_size_(size_t(params.leaf_size_or(kDefaultLeafSize))),
      memory_budget_(params.memory_budget),
      kernel_(kernel_for(kernel_isa())) {}

void Octree::build(const Scene& scene) {
  const auto start = Clock::now();
  input_ = BuildInput(scene);
  std::vector<uint32_t> usable = input_.usable;
  // Cuts keep nodes and leaves within the budget; the root, a leaf if nothing is cut, is
  // built whatever the budget.
  leaves_.reset(std::max(memory_budget_, LeafStore::bytes_for(uint32_t(usable.size()))));
  fine_ = uint32_t{1} << depth_;
  inv_fine_ = 1.0 / double(fine_);
  set_cell_extents();
  nodes_.assign(1, Node{0, 0});
  references_ = 0;
  planned_refs_ = usable.size();
  leaf_count_ = internal_ = over_budget_ = 0;
  depth_reached_ = 0;
  const uint32_t origin[3] = {0, 0, 0};
  build_node(0, 0, origin, usable);
  input_.release_triangles();
  build_seconds_ = seconds_since(start);
}

// The root's cells span the scene box, except along an axis thinner than the finest cell
// of the longest one (a flat or nearly flat scene): there every triangle would straddle
// every cut and be copied into both halves at each level, 2^depth copies in all. Such an
// axis's cells span the longest extent from the box's low side instead, so the whole scene
// stays in the first cell along it and nothing is copied. Rays are still clipped to the
// scene box, as brute clips them.
void Octree::set_cell_extents() {
  double longest = 0.0;
  for (int a = 0; a < 3; ++a) longest = std::max(longest, input_.clip.hi[a] - input_.clip.lo[a]);
  for (int a = 0; a < 3; ++a) {
    const double extent = input_.clip.hi[a] - input_.clip.lo[a];
    cell_extent_[a] = extent < longest * inv_fine_ ? longest : extent;
    fine_scale_[a] = cell_extent_[a] > 0.0 ? double(fine_) / cell_extent_[a] : 0.0;
  }
}

// Glassner's rule: a node with more than leaf-size triangles is cut into 8, unless the depth
// cap is reached or the cut separates nothing (below). Depth first, children contiguous.
void Octree::build_node(uint32_t node, int depth, const uint32_t lo[3],
                        std::vector<uint32_t>& tris) {
  std::vector<uint32_t> children[8];
  if (tris.size() > leaf_size_ && depth < depth_ && split(node, depth, lo, tris, children)) {
    const uint32_t first = uint32_t(nodes_.size());
    nodes_.resize(nodes_.size() + 8);
    nodes_[node] = {first, kInternal};
    ++internal_;
    tris = {};  // free the parent's list before the children's subtrees
    const uint32_t half = fine_ >> (depth + 1);
    for (uint32_t k = 0; k < 8; ++k) {
      const uint32_t child_lo[3] = {lo[0] + (k & 1) * half, lo[1] + ((k >> 1) & 1) * half,
                                    lo[2] + ((k >> 2) & 1) * half};
      build_node(first + k, depth + 1, child_lo, children[k]);
    }
    return;
  }
  nodes_[node] = {make_leaf(depth, lo, tris), uint32_t(tris.size())};
  references_ += tris.size();
  ++leaf_count_;
  depth_reached_ = std::max(depth_reached_, depth);
}

// Stores a leaf's triangles (a triangle whose padded box lies inside the leaf skips the
// mailbox) and returns its handle; 0 for no triangles.
uint32_t Octree::make_leaf(int depth, const uint32_t lo[3], const std::vector<uint32_t>& tris) {
  if (tris.empty()) return 0;
  const uint32_t size = fine_ >> depth;
  double cell_lo[3], cell_hi[3];
  for (int a = 0; a < 3; ++a)
    cell_lo[a] = wall(a, lo[a]), cell_hi[a] = wall(a, uint64_t(lo[a]) + size);
  std::vector<uint32_t> ids(tris);
  for (uint32_t& id : ids) {
    const TriangleBox box = input_.box(id);
    bool inside = true;
    for (int a = 0; a < 3; ++a) inside &= box[a] >= cell_lo[a] && box[a + 3] <= cell_hi[a];
    if (inside) id |= kOnlyHere;
  }
  return leaves_.add(ids, input_);
}

// Sorts the node's triangles into its 8 children by padded box overlap with the children's
// closed boxes (a triangle touching the mid-plane goes into both halves). False, leaving a
// leaf, when the cut separates nothing: one child keeps every triangle while each sits in
// two children or more on average (coincident or nearly coincident triangles straddling
// the cut, docs/design.md §1; cutting again only copies them). A child keeping everything with
// little straddling (a cluster inside one octant) is cut. False too when the nodes and
// references planned so far (every open list counted as the leaf it may yet become) plus
// this cut's would exceed the memory budget: the finished tree then stays within it.
bool Octree::split(uint32_t /*node*/, int depth, const uint32_t lo[3],
                   const std::vector<uint32_t>& tris, std::vector<uint32_t> (&children)[8]) {
  const uint32_t half = fine_ >> (depth + 1);
  double mid[3];
  for (int a = 0; a < 3; ++a) mid[a] = wall(a, lo[a] + half);
  for (const uint32_t id : tris) {
    const TriangleBox box = input_.box(id);
    unsigned low = 0, high = 0;  // per axis bit: overlaps the lower / upper half
    for (int a = 0; a < 3; ++a) {
      low |= unsigned(box[a] <= mid[a]) << a;
      high |= unsigned(box[a + 3] >= mid[a]) << a;
    }
    for (unsigned k = 0; k < 8; ++k)
      if ((high & k) == k && (low & ~k & 7u) == (~k & 7u)) children[k].push_back(id);
  }
  size_t largest = 0;
  uint64_t refs = 0;
  for (const auto& child : children) {
    largest = std::max(largest, child.size());
    refs += child.size();
  }
  if (largest == tris.size() && refs >= kInseparableCopies * tris.size()) return false;
  const uint64_t planned = planned_refs_ + refs - tris.size();
  // Every node may become a leaf with its header: bytes_for(0) each, and each reference's.
  const uint64_t bytes = (nodes_.size() + 8) * (sizeof(Node) + LeafStore::bytes_for(0)) +
                         planned * (LeafStore::bytes_for(1) - LeafStore::bytes_for(0));
  if (bytes > memory_budget_ || planned >= UINT32_MAX) {
    ++over_budget_;
    return false;
  }
  planned_refs_ = planned;
  return true;
}

// A wall of the finest level from its integer index: lo + extent * (i / 2^depth), the same
// double for every level that names it (scaling by a power of two is exact).
double Octree::wall(int axis, uint64_t fine_index) const {
  return input_.clip.lo[axis] + cell_extent_[axis] * (double(fine_index) * inv_fine_);
}

// The finest cell holding coordinate p, clamped into the box; off by one only within
// rounding of a wall, which the triangles' padding covers.
uint32_t Octree::fine_cell(int axis, double p) const {
  const double cell = (p - input_.clip.lo[axis]) * fine_scale_[axis];
  return uint32_t(std::clamp(cell, 0.0, double(fine_ - 1)));
}

// Glassner's point location from the root, on integer coordinates: one bit per level.
Octree::Located Octree::locate(const uint32_t fine[3]) const {
  uint32_t node = 0;
  int d = 0;
  while (nodes_[node].count == kInternal) {
    const int shift = depth_ - 1 - d;
    const uint32_t octant = ((fine[0] >> shift) & 1) | (((fine[1] >> shift) & 1) << 1) |
                            (((fine[2] >> shift) & 1) << 2);
    node = nodes_[node].first + octant;
    ++d;
  }
  Located out;
  out.node = node;
  out.size = fine_ >> d;
  for (int a = 0; a < 3; ++a) out.lo[a] = fine[a] & ~(out.size - 1);
  return out;
}

std::unique_ptr<ThreadContext> Octree::make_context() const {
  return std::make_unique<MailboxContext>();
}

Hit Octree::intersect(const Ray& ray, ThreadContext& context) const {
  return trace<false>(ray, static_cast<MailboxContext&>(context));
}

Hit Octree::any_hit(const Ray& ray, ThreadContext& context) const {
  return trace<true>(ray, static_cast<MailboxContext&>(context));
}

// Glassner's walk: locate the leaf holding the current point, test it, leave it through its
// nearest wall and locate the finest cell just beyond. The cell on the exit axis is the
// neighbour's by integer arithmetic; on the other axes it comes from the exit point, kept
// inside the leaf just left and never behind the previous cell, so the walk always advances
// (it ends after at most 3 * 2^depth leaves). The walk follows the line the kernel tests
// (start_walk) and stops once a leaf's exit passes the nearest hit plus the slack.
template <bool AnyHit>
Hit Octree::trace(const Ray& ray, MailboxContext& context) const {
  Hit best;
  WalkLine line;
  if (!start_walk(input_.clip, ray, line)) return best;
  const RayBoxes boxes(ray, !line.far);
  const BoxFilter filter = BoxFilter::up_to_tmax(boxes, line, ray.tmax);
  int step[3];
  uint32_t fine[3];
  for (int a = 0; a < 3; ++a) {
    step[a] = step_of(ray.dir[a]);
    fine[a] = fine_cell(a, line.origin[a] + line.t0 * line.dir[a]);
  }
  const PreparedRay<KernelReal> prepared(ray, line.shift, line.inv_dir);
  float tmax = ray.tmax;
  double stop = line.stop(tmax);
  const uint64_t ray_id = context.mailbox.next_ray();
  uint64_t leaves = 0;
  for (;;) {
    const Located leaf = locate(fine);
    ++leaves;
    const Node& node = nodes_[leaf.node];
    if (node.count > 0 &&
        test_leaf<AnyHit>(leaves_.view(node.first), kernel_, prepared, filter, ray_id, tmax, best,
                          context.mailbox, context.counters)) {
      if (AnyHit) break;
      stop = line.stop(tmax);
    }
    double t_exit = kInf;
    int s = -1;
    for (int a = 0; a < 3; ++a) {
      if (step[a] == 0) continue;
      const uint32_t index = step[a] > 0 ? leaf.lo[a] + leaf.size : leaf.lo[a];
      const double t = (wall(a, index) - line.origin[a]) * line.inv_dir[a];
      if (t < t_exit) t_exit = t, s = a;
    }
    if (s < 0 || t_exit > stop) break;
    const uint32_t next = step[s] > 0 ? leaf.lo[s] + leaf.size : leaf.lo[s] - 1;
    if (next >= fine_) break;  // left the box (below 0 wraps around)
    for (int c = 0; c < 3; ++c) {
      if (c == s || step[c] == 0) continue;
      const uint32_t at = fine_cell(c, line.origin[c] + t_exit * line.dir[c]);
      const uint32_t last = leaf.lo[c] + leaf.size - 1;
      fine[c] = step[c] > 0 ? std::clamp(at, fine[c], last) : std::clamp(at, leaf.lo[c], fine[c]);
    }
    fine[s] = next;
  }
  context.counters.traversal_steps += leaves;
  return best;
}

StructureStats Octree::stats() const {
  StructureStats s;
  s.nodes = nodes_.size();
  s.leaves = leaf_count_;
  s.voxels_subdivided = internal_;
  s.traversal_states = std::nullopt;
  s.depth = uint64_t(depth_reached_);
  s.memory_bytes = nodes_.size() * sizeof(Node) + leaves_.bytes();
  s.build_seconds = build_seconds_;
  s.voxels_over_budget = over_budget_;
  return s;
}

}  // namespace gs
