// The hierarchical adaptive 1D grid of Jevans, "Ray Tracing Scenes of Varying Local
// Complexity" (1990). Each voxel is a leaf or is cut along one axis into g equal cells
// (§4); g is chosen by the §6 cost function from the five code timings and the number of
// rays the §6.5 sampling pass saw; voxels are cut only when a ray first walks into them
// (§4, lazy); voxels cut along the same axis with the same absolute granularity share one
// traversal state (§4, §5.2.2); ray-id mailboxing stops repeated tests (§6.4).
//
// Two kinds of records (docs/design.md §1.9): what the build and the inspector need about a
// voxel (Voxel, Region: its triangles, place, sample), and what the walk reads (Node: one
// per subdivided voxel, one cache line; a child reference per cell that carries the child's
// kind, so that an empty or unbuilt cell costs no load; per cell a content box, so that the
// walk steps only into cells whose contents the ray meets, docs/design.md §1.3; each leaf's
// triangles stored once in the kernel's structure-of-arrays form, core/geometry/leaf.h; the
// triangles that lie in every cell of a cut kept once at its node and tested as the walk goes
// down into it).
// Build and walk are in build.cpp and walk.cpp.
#pragma once
#include <array>
#include <atomic>
#include <mutex>
#include <span>
#include <unordered_map>
#include <vector>

#include "core/accel/accelerator.h"
#include "core/accel/grid1d/cost_model.h"
#include "core/accel/grid1d/packet_lanes.h"
#include "core/base/atomic.h"
#include "core/base/stable_array.h"
#include "core/geometry/leaf.h"
#include "core/geometry/triangles.h"

namespace gs {

// The §6 cost model as it stands for one voxel: the figures it was fed, the best cut per
// axis and the cost of every granularity (for the viewer's inspector). Recomputed from the
// voxel, the sample and the parameters, the same pure function the build evaluates.
struct VoxelCostReport {
  uint32_t voxel = 0;
  uint32_t depth = 0;
  int axis = -1;                  // the cut the build made, or -1 for a leaf
  int granularity = 1;            // 1 for a leaf
  VoxelFigures figures;           // N, extents, mean sizes, estimated rays
  double subdivision_cost = 0.0;  // Subcost * N (§6.5)
  std::vector<AxisPlan> plans;    // per axis that can be cut: best g, costs, pays or not
  struct Alternative {
    int axis;
    int granularity;
    CutCost cost;  // per ray
  };
  std::vector<Alternative> alternatives;
};

class Grid1D final : public Accelerator {
 public:
  // Depth cap when --max-depth is not given: far deeper than the cost function goes on real
  // scenes; it bounds degenerate input.
  static constexpr int kDefaultMaxDepth = 32;

  explicit Grid1D(const AccelParams& params);
  ~Grid1D() override;

  std::string name() const override { return "grid1d"; }
  void build(const Scene& scene) override;
  void sample(std::span<const Ray> sample_rays, double run_rays_per_sample_ray,
              const SpawnRays& spawn = {}, int threads = 1) override;
  void build_all() override;
  Box bounds() const override { return input_.bounds; }
  std::unique_ptr<ThreadContext> make_context() const override;
  Hit intersect(const Ray& ray, ThreadContext& context) const override;
  Hit any_hit(const Ray& ray, ThreadContext& context) const override;
  StructureStats stats() const override;
  std::optional<Walk> record_walk(const Ray& ray, ThreadContext& context) const override;
  void trace_packet(std::span<const Ray> rays, std::span<const uint64_t> keys, std::span<Hit> hits,
                    bool any_hit, ThreadContext& context) const override;
  bool traces_packets() const override { return true; }
  const Grid1D* grid1d() const override { return this; }
  const BuildProgress* build_progress() const override { return &progress_; }

  static constexpr uint32_t kNone = UINT32_MAX;  // "no voxel above": the scene box itself

  // One global uniform 1D grid: the scene box's extent on `axis` cut into `granularity`
  // slabs. Every voxel cut along `axis` with absolute granularity G has its walls on the
  // grid (axis, G), so the ray's position on it is shared by all of them (§4).
  struct StateInfo {
    double origin;         // scene box low bound on the axis
    double extent;         // scene box extent on the axis
    double scale;          // granularity / extent: slabs per unit length
    double width;          // extent / granularity: one slab
    uint64_t granularity;  // absolute granularity G
    uint32_t axis;
  };

  // A voxel as the build and the inspector see it. The status is the lazy build's
  // publication flag: fields are written before a release store of kSplit or kLeaf and read
  // after an acquire load. The triangle list (tri_begin, tri_count) is set when the voxel
  // is created and never changes, so a voxel being cut can still be searched as a leaf.
  struct Voxel {
    std::atomic<uint8_t> status;
    uint8_t axis;
    uint16_t granularity;  // g: cells of this voxel's 1D array
    uint32_t state;        // traversal state (axis, absolute granularity)
    uint32_t tri_begin, tri_count;
    uint32_t first_child;  // kSplit: the g cells are voxels first_child .. + g - 1
  };
  enum Status : uint8_t { kUnexamined = 0, kBuilding, kLeaf, kSplit };

  // Read access for tests, the viewer and statistics (valid once tracing has stopped).
  size_t voxel_count() const { return voxels_.size(); }
  const Voxel& voxel(uint32_t id) const { return voxels_[id]; }
  // The triangles sorted into the voxel (a cut voxel's spanning ones included; its cells'
  // lists leave those out).
  std::span<const uint32_t> voxel_triangles(uint32_t id) const {
    return {&tri_indices_[voxels_[id].tri_begin], voxels_[id].tri_count};
  }
  const StateInfo& state_info(uint32_t id) const { return states_[id]; }
  size_t state_count() const { return states_.size(); }
  // The voxel's box, from its slab on each axis's global grid (exact walls).
  void voxel_box(uint32_t id, double lo[3], double hi[3]) const;
  uint32_t voxel_depth(uint32_t id) const;
  // Call while no thread traces (the figures read the voxel's triangle list and sample).
  VoxelCostReport cost_report(uint32_t id) const;
  // Rays that used each traversal state (counted once per ray, merged when a tracing
  // thread's context ends).
  uint64_t state_rays(uint32_t state) const;
  // The kernel the walk tests leaves with (core/geometry/leaf.h).
  Isa isa() const { return isa_; }

 private:
  struct Region;
  struct Node;
  struct Cut;
  struct SampleRay;
  class Context;
  struct RayWalk;
  class WalkRecorder;
  struct NullRecorder;

  // Walk (walk.cpp).
  struct Cursor;
  template <bool AnyHit, class Recorder>
  Hit trace(const Ray& ray, Context& context, Recorder& recorder) const;
  template <bool AnyHit, class Recorder>
  bool enter(Cursor& cursor, RayWalk& walk, Context& context, Recorder& recorder) const;
  template <bool AnyHit, class Recorder>
  bool test_spanning(uint32_t node, double t_enter, RayWalk& walk, Context& context,
                     Recorder& recorder) const;
  template <bool AnyHit, class Recorder>
  bool search(const LeafView& leaf, RayWalk& walk, Context& context, Recorder& recorder) const;
  template <class Recorder>
  bool next_cell(Cursor& cursor, RayWalk& walk, Context& context, Recorder& recorder) const;
  template <class Recorder>
  int64_t seek(uint32_t node, int64_t from, bool from_is_current, Cursor& cursor, RayWalk& walk,
               Context& context, Recorder& recorder) const;
  int64_t slab_at(const Node& node, double t, const RayWalk& walk) const;
  uint32_t state_of(uint32_t node, int axis) const;
  bool holds_start(uint32_t node, int64_t cell, const RayWalk& walk) const;
  bool held_by_chain(uint32_t chain, uint32_t up, int axis, RayWalk& walk, Context& context) const;
  void activate(int axis, uint32_t node, uint32_t state, RayWalk& walk) const;
  template <class Recorder>
  int64_t descend(uint32_t node, double t_cur, int entered_axis, RayWalk& walk, Context& context,
                  Recorder& recorder) const;
  LeafView leaf_of(uint32_t ref, Context& context) const;
  LeafView unbuilt_leaf(uint32_t voxel, Context& context) const;
  uint32_t cursor_voxel(const Cursor& cursor) const;

  // Packet walk (packet.cpp).
  struct PacketWalk;
  template <bool AnyHit>
  void trace_together(std::span<const Ray> rays, std::span<Hit> hits, Context& context) const;
  template <bool AnyHit>
  void walk_together(uint64_t rays, int32_t kind, Hit* best, Context& context) const;
  template <bool AnyHit>
  void visit(uint32_t ref, uint64_t rays, PacketWalk& walk) const;
  template <bool AnyHit>
  void visit_node(uint32_t node, uint64_t rays, PacketWalk& walk) const;
  template <bool AnyHit>
  void search_leaf(const LeafView& leaf, uint64_t rays, PacketWalk& walk) const;
  template <bool AnyHit>
  void search_alone(const LeafView& leaf, uint32_t base, uint32_t run, uint64_t may_cross,
                    uint64_t& searching, uint64_t& improved, PacketWalk& walk) const;
  template <bool AnyHit>
  void test_crossers(const LeafView& leaf, uint32_t i, uint64_t crossers, uint64_t& searching,
                     uint64_t& improved, PacketWalk& walk) const;

  // Lazy build (build.cpp).
  void make_root();
  std::vector<SampleRay> scout_sample(Grid1D& scout, std::span<const Ray> sample_rays,
                                      const SpawnRays& spawn, int threads);
  void keep_scout(std::unique_ptr<Grid1D> scout);
  uint32_t scout_node(uint32_t voxel, int axis, int g) const;
  uint32_t scout_leaf(uint32_t voxel) const;
  void take_scouts_cells(uint32_t scout_node, Cut& cut) const;
  void report_sampling(uint64_t traced, const Grid1D& scout) const;
  // A voxel another thread is cutting is searched through its id list up to this many
  // triangles; a larger one is waited for (examine).
  static constexpr uint32_t kSearchedWhileCut = 64;
  uint32_t examine(uint32_t voxel, Context& context) const;
  uint32_t settle(uint32_t voxel, Context& context) const;
  uint32_t make_leaf(uint32_t voxel) const;
  Cut plan_cut(uint32_t voxel) const;
  struct Crossing {  // a sample segment crossing a voxel, clipped to it
    uint32_t ray;    // sample_ index
    double t0, t1;
  };
  std::vector<Crossing> crossings(uint32_t voxel, const double lo[3], const double hi[3]) const;
  VoxelFigures figures_of(uint32_t voxel, const double lo[3], const double hi[3],
                          size_t crossing_count) const;
  double mean_clipped_size(uint32_t voxel, int axis, const double lo[3], const double hi[3]) const;
  double planned_mean_size(uint32_t voxel, int axis, const double lo[3], const double hi[3]) const;
  std::array<int, 3> granularity_limits(uint32_t voxel, const VoxelFigures& figures,
                                        const double lo[3], const double hi[3]) const;
  bool sort_into_cells(uint32_t voxel, int axis, int g, const double lo[3], const double hi[3],
                       std::span<const Crossing> crossing, Cut& cut) const;
  uint32_t commit_cut(uint32_t voxel, const Cut& cut) const;
  static uint16_t sole_cell(const Cut& cut);
  static uint64_t occupied_cells(const Cut& cut);
  uint32_t walk_above(uint32_t node, int axis) const;
  uint32_t passed_chain(uint32_t node) const;
  bool is_chain(uint32_t node) const;
  void link_children(uint32_t voxel, const Cut& cut, uint32_t first_child, uint32_t node) const;
  void write_content_boxes(uint32_t voxel, const Cut& cut, const Node& node) const;
  double estimated_rays(uint32_t voxel, size_t crossing_count) const;
  uint32_t state_for(uint32_t axis, uint64_t granularity) const;
  bool reserve_bytes(uint64_t bytes) const;
  // `first` (an append's result) unless the append failed: then a UsageError naming `what`.
  size_t fits_budget(size_t first, const char* what) const;
  // Triangles `tris` of voxel `voxel` as a leaf block lists them: with kOnlyHere where a
  // triangle lies in the voxel alone.
  std::vector<uint32_t> leaf_ids(uint32_t voxel, std::span<const uint32_t> tris) const;

  AccelParams params_;
  Isa isa_;
  Kernel kernel_;
  PacketLaneOps lane_ops_;
  BuildInput input_;
  double build_seconds_ = 0.0;

  // The sampling pass (§6.5): sample rays, their segments clipped at their hits.
  std::vector<SampleRay> sample_;
  double rays_per_sample_ = 0.0;  // rays of the run each sample ray stands for
  bool sampled_ = false;
  // The sampling pass's scout, kept: this structure's storage of triangle lists, content
  // boxes and leaf blocks is the scout's, continued, and a voxel the scout cut (or made a
  // leaf) the way this one does takes the scout's as they stand instead of sorting its
  // triangles again (Region::scout_twin; docs/design.md §1.5).
  std::unique_ptr<Grid1D> scout_;

  // Lazily grown storage: appended by whichever thread cuts a voxel, never moved.
  mutable std::mutex state_mutex_;  // guards state_ids_
  mutable StableArray<Voxel> voxels_;
  mutable StableArray<Region> regions_;  // parallel to voxels_
  mutable StableArray<uint32_t> tri_indices_;
  mutable StableArray<uint32_t> sample_indices_;
  mutable StableArray<Node> nodes_;
  mutable StableArray<uint32_t> node_voxels_;  // parallel to nodes_: the voxel each one is
  // Per node: one child reference per cell (child_ref in records.h), and its cells'
  // content boxes.
  mutable StableArray<std::atomic<uint32_t>> refs_;
  mutable StableArray<float> child_boxes_;
  mutable LeafStore leaves_;
  mutable StableArray<StateInfo> states_;
  mutable StableArray<std::atomic<uint64_t>> state_rays_;  // parallel to states_
  mutable std::unordered_map<uint64_t, uint32_t> state_ids_;
  // The root voxel's reference: where every walk starts.
  mutable std::atomic<uint32_t> root_ref_{0};
  // Voxels examined and cut, triangles sorted, the sampling pass's rays: the build's
  // figures, read by the statistics and (while the build runs) by a progress display.
  mutable BuildProgress progress_;
  mutable std::atomic<uint64_t> over_budget_{0};
  mutable std::atomic<uint64_t> deepest_{0};
  mutable std::atomic<uint64_t> bytes_used_{0};
};

}  // namespace gs
