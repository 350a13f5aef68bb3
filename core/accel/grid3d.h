// Adaptive nested 3D grids of Jevans and Wyvill, "Adaptive voxel subdivision for ray
// tracing" (Graphics Interface 1989), the "nested 3D grid" of Jevans 1990 §7: a uniform
// grid over the scene box, about cbrt(N) cells per side with cells as cubic as the box's
// aspect allows; a cell holding more than `leaf_size` triangles (default 16) gets its own
// uniform grid of about cbrt(n) cells per side (at least 2 on its longest side), and so
// on, up to `max_depth` levels (default 3: the root grid and two levels of sub-grids; the
// paper's "usually 2-3"). Sub-grids are built lazily, when a ray first walks into their
// cell, with the same publication scheme as grid1d (docs/design.md §1.7).
//
// Traversal: a 3D DDA per level (Cleary et al. 1983, Amanatides & Woo 1987); a ray
// entering a subdivided cell starts that cell's DDA at its current point and, when it
// leaves the sub-grid, the parent's DDA resumes where it was. Wall distances come from
// integer wall indices, never accumulated. Per-thread 64-bit ray-id mailbox.
//
// Stats: nodes = grids + cells, voxels_subdivided = cells with a sub-grid, leaves = cells
// without one, traversal_states = null, traversal_steps = cell steps at any level.
#pragma once
#include <array>
#include <atomic>
#include <vector>

#include "core/accel/accelerator.h"
#include "core/base/atomic.h"
#include "core/base/stable_array.h"
#include "core/geometry/leaf.h"
#include "core/geometry/triangles.h"

namespace gs {

class NestedGrid final : public Accelerator {
 public:
  static constexpr int kDefaultLeafSize = 16;
  static constexpr int kDefaultMaxDepth = 3;
  static constexpr int kMaxDepthCap = 16;  // bounds the traversal's recursion

  explicit NestedGrid(const AccelParams& params);
  ~NestedGrid() override;

  std::string name() const override { return "grid3d"; }
  void build(const Scene& scene) override;
  void build_all() override;
  Box bounds() const override { return input_.bounds; }
  std::unique_ptr<ThreadContext> make_context() const override;
  Hit intersect(const Ray& ray, ThreadContext& context) const override;
  Hit any_hit(const Ray& ray, ThreadContext& context) const override;
  StructureStats stats() const override;

  // One uniform grid: its box and resolution; its cells are cells_[first_cell ..].
  struct GridNode {
    double lo[3], hi[3];
    double width[3], inv_width[3];
    int32_t res[3];
    uint32_t first_cell;
    uint32_t depth;  // 1: the root grid
  };
  // A cell. status is the lazy build's publication flag (release store of kSplit after
  // `child` and the child grid are written; acquire load before reading them). The
  // cell's leaf never changes, so a cell being subdivided is still searched as a leaf. A
  // triangle whose padded box lies inside the cell skips the mailbox there.
  struct Cell {
    std::atomic<uint8_t> status;
    uint32_t child;  // kSplit: the sub-grid's id
    uint32_t leaf;   // its triangles' leaf handle (when ref_count > 0)
    uint32_t ref_count;
  };
  enum Status : uint8_t { kUnexamined = 0, kBuilding, kLeaf, kSplit };

  // Read access for tests (valid once tracing has stopped).
  size_t grid_count() const { return grids_.size(); }
  const GridNode& grid(uint32_t id) const { return grids_[id]; }
  size_t cell_count() const { return cells_.size(); }
  const Cell& cell(uint32_t id) const { return cells_[id]; }

 private:
  struct RayWalk;
  struct Plan;

  template <bool AnyHit>
  Hit trace(const Ray& ray, MailboxContext& context) const;
  template <bool AnyHit>
  bool walk(uint32_t grid_id, double t_cur, int entered_axis, RayWalk& w,
            MailboxContext& context) const;
  template <bool AnyHit>
  bool test_cell(const Cell& cell, RayWalk& w, MailboxContext& context) const;
  uint8_t examine(uint32_t cell_id, MailboxContext& context) const;
  bool subdivide(uint32_t cell_id) const;
  bool plan_grid(const double lo[3], const double hi[3], const std::vector<uint32_t>& ids,
                 int min_long_side, Plan& plan) const;
  void sort_into(const double lo[3], const double hi[3], const std::array<int32_t, 3>& res,
                 const std::vector<uint32_t>& ids, Plan& plan) const;
  bool commit(const Plan& plan, uint32_t depth, uint32_t& grid_id) const;
  void cell_box(const GridNode& grid, uint32_t local, double lo[3], double hi[3]) const;
  bool reserve_bytes(uint64_t bytes) const;

  AccelParams params_;
  int leaf_size_ = kDefaultLeafSize;
  int max_depth_ = kDefaultMaxDepth;
  Kernel kernel_;
  BuildInput input_;  // its clip box is the root grid's box
  bool has_root_ = false;
  double build_seconds_ = 0.0;

  // Lazily grown storage: appended by whichever thread subdivides a cell, never moved.
  mutable StableArray<GridNode> grids_;
  mutable StableArray<Cell> cells_;
  mutable LeafStore leaves_;
  mutable std::atomic<uint64_t> subdivided_{0};
  mutable std::atomic<uint64_t> over_budget_{0};
  mutable std::atomic<uint64_t> deepest_{0};  // the deepest sub-grid's depth - 1
  mutable std::atomic<uint64_t> bytes_used_{0};
};

}  // namespace gs
