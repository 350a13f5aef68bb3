// A bounding volume hierarchy built with the binned surface area heuristic (Goldsmith &
// Salmon 1987; MacDonald & Booth 1990; binning as in Wald, "On fast construction of
// SAH-based bounding volume hierarchies", 2007): 16 bins per axis over the centroids,
// cost = Ctrav + Cisect * (A_L N_L + A_R N_R) / A with Ctrav = Cisect = 1, a leaf costing
// Cisect * N. Leaves hold up to `leaf_size` triangles (default 4); a node with more is
// always split (by the median when the SAH finds no split), one with fewer becomes a leaf
// when no split is cheaper. `max_depth` (default 64) caps the depth. Built eagerly.
//
// Nodes are packed in 32 bytes (box in float + first/count); each leaf's triangles are
// stored once in the kernel's form (core/geometry/leaf.h). Node boxes are the triangles'
// boxes padded by ClipBox::padding and rounded outward to float. Traversal, as an ordinary
// fast scalar BVH does it: float slab tests with the exit widened by the bound of Ize,
// "Robust BVH Ray Traversal" (JCGT 2(2), 2013), so that rounding never culls a node the
// ray crosses, and a hit the kernel reports is never culled: answers equal brute's bit for
// bit. A scalar stack, nearer child first, skipping nodes whose entry lies beyond the
// nearest hit (plus the slack every walk allows), the stop distance updated only on a hit.
//
// Stats: nodes, leaves, voxels_subdivided = inner nodes, traversal_states = null,
// traversal_steps = nodes visited (popped and not culled, root included),
// voxels_over_budget = nodes left leaves because their children would take the nodes past
// the memory budget (the triangles, copied once in leaf order, come on top).
#pragma once
#include <vector>

#include "core/accel/accelerator.h"
#include "core/geometry/leaf.h"
#include "core/geometry/triangles.h"

namespace gs {

class Bvh final : public Accelerator {
 public:
  static constexpr int kDefaultLeafSize = 4;
  static constexpr int kDefaultMaxDepth = 64;
  static constexpr int kMaxDepthCap = 120;  // the traversal stack holds depth + 1 entries

  explicit Bvh(const AccelParams& params);

  std::string name() const override { return "bvh"; }
  void build(const Scene& scene) override;
  Box bounds() const override { return input_.bounds; }
  std::unique_ptr<ThreadContext> make_context() const override;
  Hit intersect(const Ray& ray, ThreadContext& context) const override;
  Hit any_hit(const Ray& ray, ThreadContext& context) const override;
  StructureStats stats() const override;

  struct Node {
    float lo[3];
    uint32_t first;  // inner: left child (right = first + 1); leaf: its leaf handle
    float hi[3];
    uint32_t count;  // 0 for an inner node
  };
  static_assert(sizeof(Node) == 32);

  size_t node_count() const { return nodes_.size(); }
  const Node& node(uint32_t id) const { return nodes_[id]; }

 private:
  struct Builder;
  struct RayBox;
  template <bool AnyHit>
  Hit trace(const Ray& ray, MailboxContext& context) const;

  int leaf_size_;
  int max_depth_;
  uint64_t memory_budget_;  // bytes of nodes
  Kernel kernel_;
  std::vector<Node> nodes_;
  LeafStore leaves_;
  BuildInput input_;
  uint64_t leaves_count_ = 0, over_budget_ = 0, deepest_ = 0;
  double build_seconds_ = 0.0;
};

}  // namespace gs
