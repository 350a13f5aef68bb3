// The octree the paper compares with (Jevans 1990 §7; Glassner, "Space Subdivision for Fast
// Ray Tracing", 1984): a node holding more than leaf-size triangles is cut into 8 equal
// children, down to a depth cap. Built eagerly. Traversal is Glassner's: after a leaf, find
// the point just past its exit and locate it from the root; here the point is an integer
// cell on the finest level (2^depth per side), so no epsilon nudge is needed and the walk
// never loses or repeats a leaf. Along an axis thinner than the finest cell of the longest
// one (a flat scene) the root spans the longest extent, so triangles are not copied into
// both halves of every cut (set_cell_extents).
//
// Defaults: max depth 6 and leaf size 4, near the values published comparisons used for
// octrees (depth about 6, 4-8 triangles per leaf); depth 6 allows 8^6 = 262144 leaves. On
// builtin:pyramid (512x512 primary rays, one thread) leaf size 4 traced 2.65 M rays/s, 8
// 2.46 M, 2 2.65 M with more nodes; depth 7 or 8 builds the same tree there. --max-depth is
// capped at 20 (finest cells stay exact integers).
#pragma once
#include <vector>

#include "core/accel/accelerator.h"
#include "core/geometry/leaf.h"
#include "core/geometry/triangles.h"

namespace gs {

class Octree final : public Accelerator {
 public:
  static constexpr int kDefaultMaxDepth = 6;
  static constexpr int kDefaultLeafSize = 4;
  static constexpr int kDepthCap = 20;  // finest cells stay exact integers in uint32

  explicit Octree(const AccelParams& params);

  std::string name() const override { return "octree"; }
  void build(const Scene& scene) override;
  Box bounds() const override { return input_.bounds; }
  std::unique_ptr<ThreadContext> make_context() const override;
  Hit intersect(const Ray& ray, ThreadContext& context) const override;
  Hit any_hit(const Ray& ray, ThreadContext& context) const override;
  // nodes, leaves, voxels_subdivided = internal nodes; traversal_states = null;
  // voxels_over_budget = nodes left leaves because their cut would exceed the memory
  // budget (nodes and references; the triangles' corners come on top);
  // TraceCounters::traversal_steps counts leaves visited.
  StructureStats stats() const override;

  // A packed node: an internal node's 8 children are contiguous at `first` (octant bit 0 =
  // upper x half, bit 1 = y, bit 2 = z); a leaf of count > 0 triangles has them in the leaf
  // store at handle `first`.
  struct Node {
    uint32_t first;
    uint32_t count;  // kInternal for an internal node
  };
  static constexpr uint32_t kInternal = UINT32_MAX;
  static_assert(sizeof(Node) == 8);

  // Read access for tests.
  const std::vector<Node>& nodes() const { return nodes_; }
  int max_depth() const { return depth_; }
  int depth_reached() const { return depth_reached_; }
  uint64_t references() const { return references_; }

 private:
  struct Located {
    uint32_t node;
    uint32_t lo[3];  // the leaf's first finest cell per axis
    uint32_t size;   // finest cells per side
  };
  template <bool AnyHit>
  Hit trace(const Ray& ray, MailboxContext& context) const;
  Located locate(const uint32_t fine[3]) const;
  uint32_t fine_cell(int axis, double p) const;
  double wall(int axis, uint64_t fine_index) const;
  void set_cell_extents();
  void build_node(uint32_t node, int depth, const uint32_t lo[3], std::vector<uint32_t>& tris);
  uint32_t make_leaf(int depth, const uint32_t lo[3], const std::vector<uint32_t>& tris);
  bool split(uint32_t node, int depth, const uint32_t lo[3], const std::vector<uint32_t>& tris,
             std::vector<uint32_t> (&children)[8]);

  int depth_;
  size_t leaf_size_;
  uint64_t memory_budget_;
  Kernel kernel_;
  BuildInput input_;       // its clip box: the box every ray is clipped to; the root's low corner
  uint32_t fine_ = 1;      // 2^depth_: finest cells per side
  double inv_fine_ = 1.0;  // 2^-depth_, exact
  double cell_extent_[3] = {};  // the root cell's extent (see set_cell_extents)
  double fine_scale_[3] = {};   // finest cells per unit length
  std::vector<Node> nodes_;
  LeafStore leaves_;
  uint64_t references_ = 0;
  uint64_t planned_refs_ = 0;  // references_ plus every list still being built (build only)
  uint64_t leaf_count_ = 0, internal_ = 0, over_budget_ = 0;
  int depth_reached_ = 0;
  double build_seconds_ = 0.0;
};

}  // namespace gs
