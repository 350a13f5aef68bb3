// The one surface every acceleration structure has (docs/design.md §2): build, bounds,
// intersect, occluded, stats; made by name from one factory. Dispatch is once per ray; the
// inner loops behind intersect/occluded are non-virtual.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/accel/build_progress.h"
#include "core/accel/params.h"
#include "core/accel/walk.h"
#include "core/geometry/ray.h"
#include "core/scene/scene.h"

namespace gs {

class Grid1D;

// Counters a tracing thread accumulates; merged by the caller at the end of a run.
struct TraceCounters {
  uint64_t intersection_tests = 0;  // real ray/triangle tests, mailbox rejections excluded
  uint64_t mailbox_rejections = 0;
  uint64_t traversal_steps = 0;     // cell-to-cell steps (each structure says what a step is)
  uint64_t descents = 0;            // set-ups in a subdivided voxel (grid1d: §6.2's Vertcost)
  uint64_t voxels_built = 0;        // voxels this thread examined (cut or made leaves) lazily
  double lazy_build_seconds = 0.0;  // time this thread spent building voxels
  // Triangles of the leaves searched, one per ray: each one's box is tested, and only those
  // whose box the ray crosses go on to a real test (what §6.2's Intcost is paid for).
  uint64_t leaf_triangles = 0;
  // Packet traversal (Accelerator::trace_packet; only structures that walk rays together
  // count these).
  uint64_t packets = 0;               // packets walked together
  uint64_t packet_rays = 0;           // rays in them
  uint64_t packet_fallback_rays = 0;  // rays traced one at a time: they diverged from the packet
  uint64_t packet_steps = 0;          // cells a packet stepped into together
  uint64_t packet_step_rays = 0;      // rays active in those steps, summed
  uint64_t packet_step_slots = 0;     // rays of the packet in those steps, summed

  void add(const TraceCounters& other);
  // Active rays per packet step over the packet's rays (1: every ray of the packet needed
  // every cell it stepped into); 0 without packet steps.
  double packet_active_fraction() const;
};

// Per-thread scratch a structure needs while tracing (mailboxes, traversal state values).
// Owned by exactly one thread at a time.
class ThreadContext {
 public:
  static constexpr uint64_t kNoRayIndex = ~uint64_t{0};
  virtual ~ThreadContext() = default;
  TraceCounters counters;
  // The key of the ray being traced, set before each call: its position in the ray file
  // (run_trace) or its render_ray_key (pixel, sample, bounce, kind; the renderer), never
  // dependent on thread scheduling; kNoRayIndex elsewhere (sampling pass, walks). Only
  // "zero" reads it: its oracle is indexed by it.
  uint64_t ray_index = kNoRayIndex;
};

// Structure figures; std::nullopt where a structure cannot measure one (written as null).
struct StructureStats {
  std::optional<uint64_t> nodes;
  std::optional<uint64_t> voxels_subdivided;
  std::optional<uint64_t> leaves;
  std::optional<uint64_t> traversal_states;
  // The deepest level built: the root (or a grid3d's root grid) is 0, its children 1.
  std::optional<uint64_t> depth;
  uint64_t memory_bytes = 0;
  double build_seconds =
      0.0;  // up-front build plus the sampling pass (lazy work is added by callers)
  // Voxels or nodes left leaves because their cut would exceed the memory budget (the
  // uniform grid: cells its resolution wanted that the budget did not allow).
  uint64_t voxels_over_budget = 0;
  // False for a structure whose tests (with its mailbox rejections) or cell steps cannot be
  // counted (embree): run_stats writes those counters as null instead of a made-up 0.
  bool counts_tests = true;
  bool counts_steps = true;
  bool counts_descents = false;  // only grid1d goes down into subdivided voxels one by one
};

// The rays a run casts from one ray's answer, appended to `next` (see Accelerator::sample).
using SpawnRays = std::function<void(const Ray& ray, const Hit& hit, std::vector<Ray>& next)>;

class Accelerator {
 public:
  virtual ~Accelerator() = default;
  virtual std::string name() const = 0;

  // Builds what is built up front. The scene must outlive the structure.
  virtual void build(const Scene& scene) = 0;
  // The paper's sampling pass (§6.5): a regular subset of the run's rays, traced before the
  // run so that the cost function knows how many rays cross a voxel; each sample ray stands
  // for `run_rays_per_sample_ray` rays of the run. `spawn`, when given, adds the rays the run
  // casts from a sample ray's answer (a renderer's shadow ray); they are sampled too, with
  // the same weight. `spawn` may be called from `threads` threads at once, each call with a
  // `next` of its own; the structure it builds must not depend on `threads`. Default: nothing.
  virtual void sample(std::span<const Ray> sample_rays, double run_rays_per_sample_ray,
                      const SpawnRays& spawn = {}, int threads = 1);
  // Builds everything a lazy structure would build on demand (--eager). Default: nothing.
  virtual void build_all() {}

  virtual Box bounds() const = 0;
  virtual std::unique_ptr<ThreadContext> make_context() const = 0;
  // Nearest hit with tmin < t <= tmax, lowest id among equal t; a miss for invalid rays.
  virtual Hit intersect(const Ray& ray, ThreadContext& context) const = 0;
  // Some hit with tmin < t <= tmax (not necessarily the nearest), or a miss; the walk stops
  // at the first one found. Shadow rays and `trace --occluded`.
  virtual Hit any_hit(const Ray& ray, ThreadContext& context) const = 0;
  // The most rays trace_packet takes at once.
  static constexpr size_t kMaxPacketRays = 64;
  // Traces up to kMaxPacketRays rays, hits[i] being exactly what intersect (with `any_hit`:
  // any_hit) answers for rays[i]; keys[i] is ray i's ThreadContext::ray_index. Coherent
  // rays (a tile's primary rays, or their shadow rays toward one light) walk a structure
  // with a packet traversal (traces_packets) together; the others trace them one by one.
  virtual void trace_packet(std::span<const Ray> rays, std::span<const uint64_t> keys,
                            std::span<Hit> hits, bool any_hit, ThreadContext& context) const;
  virtual bool traces_packets() const { return false; }
  bool occluded(const Ray& ray, ThreadContext& context) const {
    return any_hit(ray, context).found();
  }
  virtual StructureStats stats() const = 0;
  // Called once a run knows how many ray keys (ThreadContext::ray_index) it will trace:
  // `keys` of them, one per `what` ("ray", "ray key of this render"). A structure that
  // answers by key (the zero-overhead oracle) throws InputError unless it holds one answer
  // per key; the others need nothing.
  virtual void check_ray_keys(size_t /*keys*/, const std::string& /*what*/) const {}
  // The nearest-hit search for one ray, cell by cell, by the same code that traces; for a
  // structure without cells to walk (brute), nothing.
  virtual std::optional<Walk> record_walk(const Ray& /*ray*/, ThreadContext& /*context*/) const {
    return std::nullopt;
  }
  // The explorer's overlays and inspector (cells, traversal states, cost reports) read the
  // 1D grid's own records; every other structure has none to show.
  virtual const Grid1D* grid1d() const { return nullptr; }
  // How far the build has got, readable from another thread while build, sample or
  // build_all run (and while rays build lazily); null for a structure that cannot tell.
  virtual const BuildProgress* build_progress() const { return nullptr; }
};

// The structures this build has, in the registry's order (registry.h).
std::vector<std::string> accelerator_names();
// Throws UsageError for an unknown name, a structure this build lacks, or a parameter out of
// range (check_params).
std::unique_ptr<Accelerator> make_accelerator(const std::string& name, const AccelParams& params);
// Throws UsageError naming the flag when a parameter is outside its range (params.h) or the
// depth exceeds structure `name`'s own cap (registry.h). Every parameter is checked, those
// the structure does not read too: a program sets them all.
void check_params(const std::string& name, const AccelParams& params);

}  // namespace gs
