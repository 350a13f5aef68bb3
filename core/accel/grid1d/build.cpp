// The 1D grid's build: the root voxel, the §6.5 sampling pass, and the lazy cut of one voxel
// (§6: the cost function chooses the axis and g; the cells become voxels and the voxel gets
// its walk node), published to walking threads with release stores (docs/design.md §5).
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <stdexcept>

#include "core/accel/grid1d/cost_model.h"
#include "core/accel/grid1d/records.h"
#include "core/base/error.h"
#include "core/base/parallel.h"
#include "core/base/timing.h"

namespace gs {
namespace {

// Absolute granularities stay exact integers in double (wall = x0 + E * (I / G)).
constexpr uint64_t kMaxAbsoluteGranularity = uint64_t{1} << 50;

// A wall of the global grid (origin, extent, granularity). Computed from the integer index
// so that one physical wall has bit-identical coordinates at every level: I / G is the
// correctly rounded quotient, the same for every (I, G) naming the same fraction.
double grid_wall(double origin, double extent, uint64_t index, uint64_t granularity) {
  return origin + extent * (double(index) / double(granularity));
}

// Region::mean_size where the voxel's plan computed none.
constexpr double kNotComputed = std::numeric_limits<double>::quiet_NaN();

double surface_area(const double extent[3]) {
  return 2.0 * (extent[0] * extent[1] + extent[1] * extent[2] + extent[2] * extent[0]);
}

// Which cell of a cut a coordinate falls in, clamped to the voxel's own cells: floor(v) -
// first_cell for v = (x - origin) * scale. Computed as the walk's descent does, clamped first
// and then truncated, which is floor for what is left and needs no library call on baseline
// x86-64. The same cell: v - first_cell is exact (both are multiples of v's unit in the last
// place, at most 1/8 below the 2^50 granularity cap), and a negative difference clamps to 0
// either way.
struct CellLocator {
  double origin, scale, first_cell, last_local;
  int32_t operator()(double x) const {
    return int32_t(std::clamp((x - origin) * scale - first_cell, 0.0, last_local));
  }
};

// The cells an item lies in: first..last of a cut's g (< 2^16) cells.
struct CellRange {
  int32_t first, last;
};

// Items spread over g cells, item i over the cells range(i) (first..last): each cell's
// items are counted as the ranges are found (add), then laid out as offsets (g + 1) and a
// flat list, items in their original order within each cell. The ranges are kept in
// storage left uninitialised: every slot is written once by add.
class CellSpread {
 public:
  CellSpread(size_t items, int g)
      : ranges_(std::make_unique_for_overwrite<CellRange[]>(items)), counts_(size_t(g) + 1, 0) {}
  void add(size_t i, CellRange range) {
    ranges_[i] = range;
    for (int32_t c = range.first; c <= range.last; ++c) ++counts_[size_t(c) + 1];
  }
  // `items` are the items added, in their order.
  void lay_out(std::span<const uint32_t> items, std::vector<uint32_t>& offsets,
               std::vector<uint32_t>& flat) {
    offsets = std::move(counts_);
    const size_t g = offsets.size() - 1;
    for (size_t c = 0; c < g; ++c) offsets[c + 1] += offsets[c];
    flat.resize(offsets[g]);
    std::vector<uint32_t> cursor(offsets.begin(), offsets.end() - 1);
    for (size_t i = 0; i < items.size(); ++i)
      for (int32_t c = ranges_[i].first; c <= ranges_[i].last; ++c) flat[cursor[c]++] = items[i];
  }

 private:
  std::unique_ptr<CellRange[]> ranges_;
  std::vector<uint32_t> counts_;  // at c + 1: cell c's items
};

}  // namespace

Grid1D::Grid1D(const AccelParams& params)
    : params_(params),
      isa_(kernel_isa()),
      kernel_(kernel_for(isa_)),
      lane_ops_(packet_lane_ops(isa_)),
      voxels_(params.memory_budget),
      regions_(params.memory_budget),
      tri_indices_(params.memory_budget),
      sample_indices_(params.memory_budget),
      nodes_(params.memory_budget),
      node_voxels_(params.memory_budget),
      refs_(params.memory_budget),
      child_boxes_(params.memory_budget),
      leaves_(params.memory_budget),
      states_(std::min<uint64_t>(params.memory_budget, uint64_t{64} << 20)),
      state_rays_(std::min<uint64_t>(params.memory_budget, uint64_t{64} << 20)) {
  static_assert(sizeof(Node) == 64, "one walk node a cache line");
}

Grid1D::~Grid1D() = default;

uint32_t Grid1D::voxel_depth(uint32_t id) const { return regions_[id].depth; }

uint64_t Grid1D::state_rays(uint32_t state) const {
  return state_rays_[state].load(std::memory_order_relaxed);
}

void Grid1D::voxel_box(uint32_t id, double lo[3], double hi[3]) const {
  const Region& region = regions_[id];
  const ClipBox& root = input_.clip;
  for (int a = 0; a < 3; ++a) {
    const double origin = root.lo[a], extent = root.hi[a] - root.lo[a];
    lo[a] = grid_wall(origin, extent, region.cell[a], region.grid[a]);
    hi[a] = grid_wall(origin, extent, region.cell[a] + 1, region.grid[a]);
  }
}

// The root voxel's records and triangle list (and the sample's index list) are the least the
// structure can be: a budget that cannot hold them is a usage error, not a silent leaf.
size_t Grid1D::fits_budget(size_t first, const char* what) const {
  if (first == SIZE_MAX)
    throw UsageError("--memory-budget " + std::to_string(params_.memory_budget) +
                     " bytes cannot hold grid1d's root voxel (" + what + ")");
  return first;
}

void Grid1D::build(const Scene& scene) {
  const auto start = Clock::now();
  input_ = BuildInput(scene);
  make_root();
  build_seconds_ = seconds_since(start);
}

// The root voxel: every usable triangle, the traversal states of the box on each axis.
void Grid1D::make_root() {
  for (uint32_t a = 0; a < 3; ++a) state_for(a, 1);  // states 0, 1, 2: the box on each axis
  const auto root = uint32_t(fits_budget(voxels_.append(1), "its record"));
  if (!regions_.construct(root, 1)) fits_budget(SIZE_MAX, "its region");
  Voxel& voxel = voxels_[root];
  const std::vector<uint32_t>& usable = input_.usable;
  voxel.tri_begin = uint32_t(fits_budget(tri_indices_.append(usable.size()), "its triangle list"));
  voxel.tri_count = uint32_t(usable.size());
  std::copy(usable.begin(), usable.end(), &tri_indices_[voxel.tri_begin]);
  Region& region = regions_[root];
  for (int a = 0; a < 3; ++a) region.cell[a] = 0, region.grid[a] = 1, region.above[a] = kNone;
  region.ref = kNone;
  region.scout_twin = kNone;
  std::fill_n(region.mean_size, 3, kNotComputed);
  region.area_rays = kInf;  // no sampling pass: assume plenty of rays
  const bool empty = usable.empty() || input_.clip.empty;
  if (empty) voxel.status.store(kLeaf, std::memory_order_relaxed);
  root_ref_ = child_ref::make(empty ? child_ref::kEmpty : child_ref::kUnbuilt, root);
  bytes_used_ = sizeof(Voxel) + sizeof(Region) + usable.size() * sizeof(uint32_t);
}

// The sampling pass in two passes (§6.5: the segments that decide a cut must already end at
// their hits). First a scout, a grid1d with no sample (every cut assumes plenty of rays),
// traces the sample rays and those `spawn` adds, on `threads` threads; then the segments,
// clipped at the scout's exact answers, go to this structure's root, which nothing has cut.
// Every cut is thus a function of the sample alone. The scout is kept (keep_scout).
void Grid1D::sample(std::span<const Ray> sample_rays, double run_rays_per_sample_ray,
                    const SpawnRays& spawn, int threads) {
  if (sampled_ || (voxels_[0].status.load() != kUnexamined && voxels_[0].tri_count > 0))
    throw std::logic_error("Grid1D::sample must come once, before any tracing or build_all");
  const auto start = Clock::now();
  auto scout = std::make_unique<Grid1D>(params_);
  sample_ = scout_sample(*scout, sample_rays, spawn, threads);
  keep_scout(std::move(scout));
  sampled_ = true;
  rays_per_sample_ = run_rays_per_sample_ray;
  Region& root = regions_[0];
  // Used only if no sample segment crosses the box.
  root.area_rays = double(sample_rays.size()) * run_rays_per_sample_ray;
  root.sample_count = uint32_t(sample_.size());
  root.sample_begin =
      uint32_t(fits_budget(sample_indices_.append(sample_.size()), "the sampling pass's rays"));
  for (uint32_t j = 0; j < sample_.size(); ++j) sample_indices_[root.sample_begin + j] = j;
  bytes_used_ += sample_.size() * sizeof(uint32_t);
  build_seconds_ += seconds_since(start);
}

namespace {

// A chunk of the scout's sample rays: their answers, and the rays `spawn` added for them, in
// their order, with their answers.
struct ScoutChunk {
  std::vector<Hit> hits;
  std::vector<Ray> spawned;
  std::vector<Hit> spawned_hits;
};
constexpr size_t kScoutChunk = 64;

// Traces the sample and what `spawn` adds to it, kScoutChunk rays at a time on `threads`
// threads; `traced(count)` after each chunk, with the sample rays traced so far.
std::vector<ScoutChunk> trace_sample(const Accelerator& scout, std::span<const Ray> sample_rays,
                                     const SpawnRays& spawn, int threads,
                                     const std::function<void(uint64_t)>& traced) {
  const size_t n = sample_rays.size();
  std::vector<ScoutChunk> chunks((n + kScoutChunk - 1) / kScoutChunk);
  std::vector<std::unique_ptr<ThreadContext>> contexts(chunk_workers(n, kScoutChunk, threads));
  for (auto& context : contexts) context = scout.make_context();
  std::atomic<uint64_t> done{0};
  parallel_chunks(n, kScoutChunk, threads, [&](size_t worker, size_t begin, size_t end) {
    ThreadContext& context = *contexts[worker];
    ScoutChunk& chunk = chunks[begin / kScoutChunk];
    for (size_t i = begin; i < end; ++i) {
      chunk.hits.push_back(scout.intersect(sample_rays[i], context));
      if (!spawn) continue;
      const size_t first = chunk.spawned.size();
      spawn(sample_rays[i], chunk.hits.back(), chunk.spawned);
      for (size_t k = first; k < chunk.spawned.size(); ++k)
        chunk.spawned_hits.push_back(scout.intersect(chunk.spawned[k], context));
    }
    traced(done.fetch_add(end - begin, std::memory_order_relaxed) + (end - begin));
  });
  return chunks;
}

}  // namespace

// The sample's segments inside the clip box, each ending at its ray's nearest hit: the sample
// rays' in order, then those of the rays they spawned, in the order of the rays that spawned
// them. Answers are exact in any structure however it was built, so the segments, and with
// them every cut, do not depend on the threads or on the order they trace in.
std::vector<Grid1D::SampleRay> Grid1D::scout_sample(Grid1D& scout, std::span<const Ray> sample_rays,
                                                    const SpawnRays& spawn, int threads) {
  // The scout borrows the build's input and gives it back however it leaves.
  struct Loan {
    BuildInput& owner;
    BuildInput& borrower;
    ~Loan() { owner = std::move(borrower); }
  } loan{input_, scout.input_};
  scout.input_ = std::move(input_);
  scout.make_root();
  progress_.sample_rays.store(sample_rays.size(), std::memory_order_relaxed);
  const std::vector<ScoutChunk> chunks = trace_sample(
      scout, sample_rays, spawn, threads, [&](uint64_t traced) { report_sampling(traced, scout); });
  std::vector<SampleRay> segments;
  const auto add_segment = [&](const Ray& ray, const Hit& hit) {
    SampleRay s{};
    s.ray = ray;
    if (!scout.input_.clip.clip(ray, s.t0, s.t1)) return;
    if (hit.found()) s.t1 = std::min(s.t1, double(hit.t));
    for (int a = 0; a < 3; ++a) s.origin[a] = ray.origin[a], s.dir[a] = ray.dir[a];
    segments.push_back(s);
  };
  for (size_t i = 0; i < sample_rays.size(); ++i)
    add_segment(sample_rays[i], chunks[i / kScoutChunk].hits[i % kScoutChunk]);
  for (const ScoutChunk& chunk : chunks)
    for (size_t k = 0; k < chunk.spawned.size(); ++k)
      add_segment(chunk.spawned[k], chunk.spawned_hits[k]);
  return segments;
}

// The scout's cuts are most of this structure's: both cut by the same cost function, the scout
// as if rays were plentiful, this structure with the sample's rays, and where rays are
// plentiful (near the root, and wherever the sample's rays go) they agree (on the bench's
// scenes 95-99% of the triangles this structure sorts lie in cuts the scout made the same
// way). So this structure takes over the scout's storage of triangle lists, content boxes
// and leaf blocks, and keeps the scout's voxel tree to find in it, for each voxel, its twin
// (Region::scout_twin): a cut the twin made the same way, or a leaf it made, is taken as it
// stands instead of being built again (scout_node, scout_leaf). Nothing that decides a cut
// comes from the scout: only what the cut would compute, bit for bit the same. Memory the
// scout holds counts against this structure's budget.
void Grid1D::keep_scout(std::unique_ptr<Grid1D> scout) {
  tri_indices_.swap(scout->tri_indices_);
  child_boxes_.swap(scout->child_boxes_);
  leaves_.swap(scout->leaves_);
  // Both roots list the usable triangles in their order.
  voxels_[0].tri_begin = scout->voxels_[0].tri_begin;
  regions_[0].scout_twin = 0;
  bytes_used_ += scout->bytes_used_.load();
  scout_ = std::move(scout);
}

// The scout's node for voxel `id` cut along `axis` into g cells, when the scout cut the
// voxel's twin that very way; kNone otherwise.
uint32_t Grid1D::scout_node(uint32_t id, int axis, int g) const {
  const uint32_t twin = regions_[id].scout_twin;
  if (twin == kNone) return kNone;
  const Voxel& voxel = scout_->voxels_[twin];
  if (voxel.status.load(std::memory_order_acquire) != kSplit || voxel.axis != axis ||
      voxel.granularity != g)
    return kNone;
  // A cut voxel's cells have its node as their nearest ancestor cut along its axis.
  return scout_->regions_[voxel.first_child].above[axis];
}

// The scout's leaf block for voxel `id`, when the scout made the voxel's twin a leaf with one
// (of the same triangles: the block this structure would store); LeafStore::kFull otherwise.
uint32_t Grid1D::scout_leaf(uint32_t id) const {
  const uint32_t twin = regions_[id].scout_twin;
  if (twin == kNone || scout_->voxels_[twin].status.load(std::memory_order_acquire) != kLeaf)
    return LeafStore::kFull;
  const uint32_t at = scout_->regions_[twin].ref;
  const uint32_t ref =
      (at == kNone ? scout_->root_ref_ : scout_->refs_[at]).load(std::memory_order_acquire);
  return child_ref::kind(ref) == child_ref::kLeaf ? child_ref::payload(ref) : LeafStore::kFull;
}

// The sampling pass's figures after `traced` of its rays: the scout builds as they go. Several
// threads report; the largest count reported stands.
void Grid1D::report_sampling(uint64_t traced, const Grid1D& scout) const {
  raise_to(progress_.sample_rays_traced, traced);
  raise_to(progress_.scout_voxels_built,
           scout.progress_.voxels_built.load(std::memory_order_relaxed));
}

void Grid1D::build_all() {
  const auto start = Clock::now();
  Context context(*this);
  std::vector<uint32_t> stack{0};
  while (!stack.empty()) {
    const uint32_t id = stack.back();
    stack.pop_back();
    examine(id, context);
    if (voxels_[id].status.load(std::memory_order_acquire) != kSplit) continue;
    const Voxel& voxel = voxels_[id];
    for (uint32_t i = 0; i < voxel.granularity; ++i) stack.push_back(voxel.first_child + i);
  }
  build_seconds_ += seconds_since(start);
}

std::unique_ptr<ThreadContext> Grid1D::make_context() const {
  return std::make_unique<Context>(*this);
}

// The lazy build of one voxel: the thread that wins the status CAS cuts it (or makes it a
// leaf) and publishes the voxel's child reference, then its status, with release stores.
// Returns the reference the caller continues with: the published one, or kUnbuilt (search
// the voxel through its id list) while another thread is still cutting a small voxel or
// when the memory budget left a leaf without its leaf block. A large voxel being cut is
// waited for: searching it would test each ray (a packet's 64) against all its triangles,
// which costs more than the rest of its cut (the root's 60,000 triangles on lumpy: two
// threads made 3-4 times the tests of one).
uint32_t Grid1D::examine(uint32_t id, Context& context) const {
  const Region& region = regions_[id];
  const std::atomic<uint32_t>& slot = region.ref == kNone ? root_ref_ : refs_[region.ref];
  std::atomic<uint8_t>& status = voxels_[id].status;
  uint8_t expected = kUnexamined;
  if (!status.compare_exchange_strong(expected, kBuilding, std::memory_order_acquire)) {
    if (expected != kBuilding) return slot.load(std::memory_order_acquire);
    if (voxels_[id].tri_count <= kSearchedWhileCut) return child_ref::make(child_ref::kUnbuilt, id);
    status.wait(kBuilding, std::memory_order_acquire);
    return slot.load(std::memory_order_acquire);
  }
  const auto start = Clock::now();
  uint32_t ref = 0;
  try {
    ref = settle(id, context);
  } catch (...) {
    // A cut that throws (no memory, a full table of traversal states) hands the voxel back:
    // threads waiting for it wake and search it; the next ray to reach it tries again.
    status.store(kUnexamined, std::memory_order_release);
    status.notify_all();
    throw;
  }
  context.counters.lazy_build_seconds += seconds_since(start);
  return ref;
}

// Cuts voxel `id`, whose status this thread set to kBuilding, or makes it a leaf, and
// publishes it. A cut whose triangles all fall into one cell (the paper's teapot in a
// stadium: a chain of such cuts isolates a small cluster in large extents) settles that
// cell at once, down the chain, and publishes the chain's bottom as the voxel's reference:
// the walk goes from the chain's top straight into the cluster, never into the chain's
// voxels, whose other cells are empty (docs/design.md §1.3). Nobody else can reach the
// chain's cells meanwhile: their node is published nowhere.
uint32_t Grid1D::settle(uint32_t id, Context& context) const {
  const Region& region = regions_[id];
  std::atomic<uint32_t>& slot = region.ref == kNone ? root_ref_ : refs_[region.ref];
  const Cut cut = plan_cut(id);
  uint32_t ref = cut.granularity >= 2 ? commit_cut(id, cut) : kNone;
  const bool split = ref != kNone;
  if (!split) {
    ref = make_leaf(id);
  } else if (const uint32_t node = child_ref::payload(ref); is_chain(node)) {
    const uint32_t cell = voxels_[id].first_child + nodes_[node].sole_cell;
    voxels_[cell].status.store(kBuilding, std::memory_order_relaxed);
    ref = settle(cell, context);
  }
  slot.store(ref, std::memory_order_release);
  voxels_[id].status.store(split ? kSplit : kLeaf, std::memory_order_release);
  voxels_[id].status.notify_all();  // threads waiting in examine
  ++context.counters.voxels_built;
  add_progress(progress_.voxels_built);
  return ref;
}

std::vector<uint32_t> Grid1D::leaf_ids(uint32_t id, std::span<const uint32_t> tris) const {
  double lo[3], hi[3];
  voxel_box(id, lo, hi);
  std::vector<uint32_t> ids(tris.size());
  for (size_t i = 0; i < tris.size(); ++i) {
    const TriangleBox box = input_.box(tris[i]);
    bool inside = true;
    for (int a = 0; a < 3; ++a) inside &= box[a] >= lo[a] && box[a + 3] <= hi[a];
    ids[i] = inside ? tris[i] | kOnlyHere : tris[i];
  }
  return ids;
}

// A finished leaf's triangles stored once in the kernel's form; the kUnbuilt reference
// (search through the id list) when the memory budget is spent.
uint32_t Grid1D::make_leaf(uint32_t id) const {
  const uint32_t scouts = scout_leaf(id);
  if (scouts != LeafStore::kFull) return child_ref::make(child_ref::kLeaf, scouts);
  const uint32_t count = voxels_[id].tri_count;
  const uint32_t unbuilt = child_ref::make(child_ref::kUnbuilt, id);
  if (!reserve_bytes(LeafStore::bytes_for(count))) return unbuilt;
  const uint32_t handle = leaves_.add(leaf_ids(id, voxel_triangles(id)), input_);
  if (handle == LeafStore::kFull || handle > child_ref::kMaxPayload) return unbuilt;
  return child_ref::make(child_ref::kLeaf, handle);
}

// The sample's segments that cross the voxel lo..hi, clipped to it: its rays of the run
// (§6.5) and, for a cut, the cells each one crosses. Computed once per voxel examined.
std::vector<Grid1D::Crossing> Grid1D::crossings(uint32_t id, const double lo[3],
                                                const double hi[3]) const {
  const Region& region = regions_[id];
  std::vector<Crossing> crossing;
  if (!sampled_) return crossing;
  crossing.reserve(region.sample_count);
  for (uint32_t i = 0; i < region.sample_count; ++i) {
    const uint32_t j = sample_indices_[region.sample_begin + i];
    const SampleRay& s = sample_[j];
    double t0 = s.t0, t1 = s.t1;
    if (clip_segment(s.origin, s.dir, lo, hi, t0, t1)) crossing.push_back({j, t0, t1});
  }
  return crossing;
}

// Rays of the run crossing the voxel: the sample's segments that cross it, scaled to the
// run; a voxel no segment crosses gets the area estimate from its parent (§6.5).
double Grid1D::estimated_rays(uint32_t id, size_t crossing_count) const {
  return crossing_count > 0 ? double(crossing_count) * rays_per_sample_ : regions_[id].area_rays;
}

// N, extents and estimated rays; the mean triangle sizes are left to mean_clipped_size, for
// the axes a decision needs.
VoxelFigures Grid1D::figures_of(uint32_t id, const double lo[3], const double hi[3],
                                size_t crossing_count) const {
  VoxelFigures figures;
  figures.triangles = voxels_[id].tri_count;
  for (int a = 0; a < 3; ++a) figures.extent[a] = hi[a] - lo[a];
  figures.rays = estimated_rays(id, crossing_count);
  return figures;
}

// The mean size along `axis` of the voxel's triangles, each clipped to the voxel (§6.3). One
// axis at a time: the paper's alternation plans one axis per voxel, and a pass over the
// triangles for all three cost as much as the cut itself.
double Grid1D::mean_clipped_size(uint32_t id, int axis, const double lo[3],
                                 const double hi[3]) const {
  const Voxel& voxel = voxels_[id];
  if (voxel.tri_count == 0) return 0.0;
  double sum = 0.0;
  for (uint32_t i = 0; i < voxel.tri_count; ++i) {
    const uint32_t tri = tri_indices_[voxel.tri_begin + i];
    sum += std::max(0.0, std::min(input_.box_hi(tri, axis), hi[axis]) -
                             std::max(input_.box_lo(tri, axis), lo[axis]));
  }
  return sum / voxel.tri_count;
}

// mean_clipped_size for a voxel's plan: the scout's twin's where its plan computed it (the
// same triangles in the same order: the same sum, bit for bit). Kept in the voxel's region,
// where a structure that keeps this one as its scout finds it.
double Grid1D::planned_mean_size(uint32_t id, int axis, const double lo[3],
                                 const double hi[3]) const {
  Region& region = regions_[id];
  const uint32_t twin = region.scout_twin;
  double mean = twin == kNone ? kNotComputed : scout_->regions_[twin].mean_size[axis];
  if (std::isnan(mean)) mean = mean_clipped_size(id, axis, lo, hi);
  return region.mean_size[axis] = mean;
}

// The most cells each axis may take: max granularity (the root's own below it), the minimum
// cell width, and the absolute granularity cap; 0 for an axis that cannot be cut.
std::array<int, 3> Grid1D::granularity_limits(uint32_t id, const VoxelFigures& figures,
                                              const double lo[3], const double hi[3]) const {
  const Region& region = regions_[id];
  const double min_width = input_.clip.min_cell_width(lo, hi);
  const int level_cap = region.depth == 0
                            ? std::min(params_.max_granularity, params_.max_root_granularity)
                            : params_.max_granularity;
  std::array<int, 3> limits{};
  for (int a = 0; a < 3; ++a) {
    const double thin_limit = min_width > 0.0 ? figures.extent[a] / min_width : 0.0;
    const double max_g = std::min({double(level_cap), std::floor(thin_limit),
                                   double(kMaxAbsoluteGranularity / region.grid[a])});
    limits[a] = max_g < 2.0 ? 0 : int(max_g);
  }
  return limits;
}

// The §6 decision for one voxel, a pure function of the voxel, the sample and the
// parameters (never of which ray arrived first), so lazy, eager and any number of threads
// build the same structure. Candidate axes: the paper's alternation by depth, or all axes
// by cost (the paper's future work, comparing with the along-axis term added back). An
// axis that cannot be cut (too thin) or whose cut separates nothing (every cell would keep
// all the voxel's triangles: coincident or spanning triangles) gives way to the next
// candidate. A cut that leaves all triangles in one cell and the others empty is kept: it
// is how a small cluster in large extents ("teapot in a stadium") gets isolated, and the
// depth cap and the minimum cell width bound it on degenerate input.
Grid1D::Cut Grid1D::plan_cut(uint32_t id) const {
  Cut cut;
  const Voxel& voxel = voxels_[id];
  const Region& region = regions_[id];
  if (voxel.tri_count < 2 || region.depth >= uint32_t(params_.depth_or(kDefaultMaxDepth)))
    return cut;
  double lo[3], hi[3];
  voxel_box(id, lo, hi);
  const std::vector<Crossing> crossing = crossings(id, lo, hi);
  VoxelFigures figures = figures_of(id, lo, hi, crossing.size());
  cut.rays = figures.rays;
  const std::array<int, 3> limits = granularity_limits(id, figures, lo, hi);
  const bool alternate = params_.axis == AxisRule::alternate;
  std::vector<AxisPlan> plans;
  bool first_axis = true;
  for (int k = 0; k < 3; ++k) {
    const int a = (int(region.depth) + k) % 3;
    if (limits[a] == 0) continue;
    figures.mean_size[a] = planned_mean_size(id, a, lo, hi);
    const AxisPlan plan = plan_axis(params_, figures, a, limits[a]);
    if (alternate) {
      // The first axis that can be cut decides whether to cut; the next ones are planned,
      // and tried, only if its cut would separate nothing.
      if (first_axis && plan.granularity < 2) return cut;
      first_axis = false;
      if (plan.granularity >= 2 && sort_into_cells(id, a, plan.granularity, lo, hi, crossing, cut))
        return cut;
    } else if (plan.granularity >= 2) {
      plans.push_back(plan);
    }
  }
  // The cost rule planned every axis: the cheapest whole cut is tried first.
  const auto whole = [&](const AxisPlan& p) {
    return p.cut_total + figures.rays * along_axis_cost(params_, figures, p.axis);
  };
  std::stable_sort(plans.begin(), plans.end(),
                   [&](const AxisPlan& x, const AxisPlan& y) { return whole(x) < whole(y); });
  for (const AxisPlan& plan : plans)
    if (sort_into_cells(id, plan.axis, plan.granularity, lo, hi, crossing, cut)) return cut;
  return Cut{};
}

VoxelCostReport Grid1D::cost_report(uint32_t id) const {
  VoxelCostReport report;
  report.voxel = id;
  report.depth = regions_[id].depth;
  const Voxel& voxel = voxels_[id];
  if (voxel.status.load(std::memory_order_acquire) == kSplit)
    report.axis = voxel.axis, report.granularity = voxel.granularity;
  double lo[3], hi[3];
  voxel_box(id, lo, hi);
  report.figures = figures_of(id, lo, hi, crossings(id, lo, hi).size());
  for (int a = 0; a < 3; ++a) report.figures.mean_size[a] = mean_clipped_size(id, a, lo, hi);
  report.subdivision_cost = params_.subcost * report.figures.triangles;
  const std::array<int, 3> limits = granularity_limits(id, report.figures, lo, hi);
  for (int a = 0; a < 3; ++a) {
    if (limits[a] == 0) continue;
    report.plans.push_back(plan_axis(params_, report.figures, a, limits[a]));
    for (int g = 2; g <= limits[a]; ++g)
      report.alternatives.push_back({a, g, cut_cost(params_, report.figures, a, g)});
  }
  return report;
}

bool Grid1D::sort_into_cells(uint32_t id, int axis, int g, const double lo[3], const double hi[3],
                             std::span<const Crossing> crossing, Cut& cut) const {
  const Region& region = regions_[id];
  const StateInfo& grid = states_[axis];  // the scene box on this axis
  const uint64_t granularity = region.grid[axis] * uint64_t(g);
  const CellLocator locate{grid.origin, double(granularity) / grid.extent,
                           double(region.cell[axis] * uint64_t(g)), double(g - 1)};

  cut.scout_node = scout_node(id, axis, g);
  if (cut.scout_node != kNone) {
    take_scouts_cells(cut.scout_node, cut);
  } else {
    const std::span<const uint32_t> tris = voxel_triangles(id);
    CellSpread tri_spread(tris.size(), g);
    bool separates = false;
    cut.spanning.clear();
    for (size_t i = 0; i < tris.size(); ++i) {
      const CellRange range{locate(std::max(input_.box_lo(tris[i], axis), lo[axis])),
                            locate(std::min(input_.box_hi(tris[i], axis), hi[axis]))};
      const bool spans = range.first == 0 && range.last == g - 1;
      separates |= !spans;
      // A triangle in every cell goes to the node (Node::spanning), in no cell.
      if (spans) cut.spanning.push_back(tris[i]);
      tri_spread.add(i, spans ? CellRange{1, 0} : range);
    }
    if (!separates) return false;
    tri_spread.lay_out(tris, cut.tri_offsets, cut.tris);
  }
  cut.axis = axis;
  cut.granularity = g;

  CellSpread ray_spread(crossing.size(), g);
  std::vector<uint32_t> rays(crossing.size());
  for (size_t i = 0; i < crossing.size(); ++i) {
    const Crossing& c = crossing[i];
    const SampleRay& s = sample_[c.ray];
    const int32_t c0 = locate(s.origin[axis] + c.t0 * s.dir[axis]);
    const int32_t c1 = locate(s.origin[axis] + c.t1 * s.dir[axis]);
    ray_spread.add(i, {std::min(c0, c1), std::max(c0, c1)});
    rays[i] = c.ray;
  }
  ray_spread.lay_out(rays, cut.sample_offsets, cut.samples);
  return true;
}

// A cut the scout made the same way (its node `node`): its cells' triangle counts as
// offsets (their lists stay where the scout put them, in tri_indices_) and its spanning
// triangles, from its node's leaf block.
void Grid1D::take_scouts_cells(uint32_t node, Cut& cut) const {
  const Voxel& cut_voxel = scout_->voxels_[scout_->node_voxels_[node]];
  cut.scout_cells = cut_voxel.first_child;
  const Voxel* cells = &scout_->voxels_[cut.scout_cells];
  const uint32_t g = cut_voxel.granularity;
  cut.tri_offsets.resize(g + 1);
  for (uint32_t i = 0; i < g; ++i) cut.tri_offsets[i] = cells[i].tri_begin - cells[0].tri_begin;
  cut.tri_offsets[g] = cut.tri_offsets[g - 1] + cells[g - 1].tri_count;
  cut.tris.clear();
  cut.spanning.clear();
  if (const uint32_t spanning = scout_->nodes_[node].spanning; spanning != Node::kNoSpanning) {
    const LeafView leaf = leaves_.view(spanning);
    for (uint32_t k = 0; k < leaf.count; ++k) cut.spanning.push_back(leaf.id(k));
  }
}

// Counts `bytes` against the memory budget; false (and nothing counted) when they do not
// fit. Under a tight budget which voxels get cut depends on which thread comes first; the
// answers do not.
bool Grid1D::reserve_bytes(uint64_t bytes) const {
  uint64_t used = bytes_used_.load(std::memory_order_relaxed);
  do {
    if (used + bytes > params_.memory_budget) return false;
  } while (!bytes_used_.compare_exchange_weak(used, used + bytes, std::memory_order_relaxed));
  return true;
}

uint32_t Grid1D::state_for(uint32_t axis, uint64_t granularity) const {
  std::lock_guard lock(state_mutex_);
  const uint64_t key = granularity << 2 | axis;
  const auto found = state_ids_.find(key);
  if (found != state_ids_.end()) return found->second;
  const auto id = uint32_t(fits_budget(states_.append(1), "its traversal states"));
  if (!state_rays_.construct(id, 1)) fits_budget(SIZE_MAX, "its traversal states");
  const double extent = input_.clip.hi[axis] - input_.clip.lo[axis];
  states_[id] = {input_.clip.lo[axis],         extent,      double(granularity) / extent,
                 extent / double(granularity), granularity, axis};
  state_ids_.emplace(key, id);
  return id;
}

// Publishes the cut's cells as new voxels and the voxel's walk node with its cells'
// references and content boxes; returns the node's reference, or kNone (the voxel stays a
// leaf) when they do not fit the memory budget. The caller's release stores make all of it
// visible to the threads that then walk into the voxel.
uint32_t Grid1D::commit_cut(uint32_t id, const Cut& cut) const {
  const auto g = uint32_t(cut.granularity);
  const bool scouts = cut.scout_node != kNone;  // the cells' lists, boxes and spanning block
  const uint64_t cells_bytes =
      scouts ? 0
             : sizeof(uint32_t) * cut.tris.size() +
                   sizeof(float) * (Node::kSummaryFloats + grouped_box_floats(g)) +
                   (cut.spanning.empty() ? 0 : LeafStore::bytes_for(uint32_t(cut.spanning.size())));
  const uint64_t bytes = g * (sizeof(Voxel) + sizeof(Region)) + sizeof(Node) +
                         sizeof(uint32_t) * (1 + g + cut.samples.size()) + cells_bytes;
  if (voxels_.size() + g >= size_t(child_ref::kMaxPayload) || !reserve_bytes(bytes)) {
    ++over_budget_;
    return kNone;
  }
  const Node* scouts_node = scouts ? &scout_->nodes_[cut.scout_node] : nullptr;
  uint32_t spanning = scouts ? scouts_node->spanning : Node::kNoSpanning;
  if (!scouts && !cut.spanning.empty()) {
    spanning = leaves_.add(leaf_ids(id, cut.spanning), input_);
    if (spanning == LeafStore::kFull) {
      ++over_budget_;
      return kNone;
    }
  }
  // Each array holds at most the budget, which reserve_bytes has checked: these appends
  // fail only if one array alone outgrows it, and then the voxel stays a leaf.
  const size_t first_voxel = voxels_.append(g);
  const size_t node = nodes_.append(1);
  const size_t refs = refs_.append(g);
  const size_t summary = scouts ? scouts_node->summary()
                                : child_boxes_.append(Node::kSummaryFloats + grouped_box_floats(g));
  const size_t boxes = summary == SIZE_MAX ? SIZE_MAX : summary + Node::kSummaryFloats;
  const size_t tri_base =
      scouts ? scout_->voxels_[cut.scout_cells].tri_begin : tri_indices_.append(cut.tris.size());
  const size_t sample_base = sample_indices_.append(cut.samples.size());
  if (first_voxel == SIZE_MAX || node == SIZE_MAX || node >= child_ref::kMaxPayload ||
      refs == SIZE_MAX || boxes == SIZE_MAX || boxes > UINT32_MAX || tri_base == SIZE_MAX ||
      sample_base == SIZE_MAX || !regions_.construct(first_voxel, g) ||
      !node_voxels_.construct(node, 1)) {
    ++over_budget_;
    return kNone;
  }
  std::copy(cut.tris.begin(), cut.tris.end(), &tri_indices_[tri_base]);
  std::copy(cut.samples.begin(), cut.samples.end(), &sample_indices_[sample_base]);
  const Region& region = regions_[id];
  const int axis = cut.axis;
  const uint32_t state = state_for(uint32_t(axis), region.grid[axis] * g);
  static_assert(sizeof(Node) == 64, "a node is one cache line");
  Node& record = nodes_[node];
  record.first_cell = int64_t(region.cell[axis] * g);
  record.state = state;
  for (int a = 0; a < 3; ++a)
    record.above[a] = walk_above(region.above[a], a),
    record.passed[a] = passed_chain(region.above[a]);
  record.children = uint32_t(refs);
  record.boxes = uint32_t(boxes);
  record.granularity = uint16_t(g);
  record.sole_cell = sole_cell(cut);
  record.axis = uint8_t(axis);
  record.spanning = spanning;
  record.occupied = occupied_cells(cut);
  node_voxels_[node] = id;

  Voxel& voxel = voxels_[id];
  voxel.axis = uint8_t(axis);
  voxel.granularity = uint16_t(g);
  voxel.state = state;
  voxel.first_child = uint32_t(first_voxel);
  link_children(id, cut, uint32_t(first_voxel), uint32_t(node));
  if (!scouts) write_content_boxes(id, cut, record);
  for (size_t i = 0; i < g; ++i) {
    voxels_[first_voxel + i].tri_begin = uint32_t(tri_base + cut.tri_offsets[i]);
    Region& child_region = regions_[first_voxel + i];
    child_region.sample_begin = uint32_t(sample_base + cut.sample_offsets[i]);
    child_region.sample_count = cut.sample_offsets[i + 1] - cut.sample_offsets[i];
  }
  add_progress(progress_.voxels_subdivided);
  add_progress(progress_.triangles_sorted, voxels_[id].tri_count);
  if (scouts) add_progress(progress_.triangles_from_scout, voxels_[id].tri_count);
  raise_to(deepest_, region.depth + 1);
  return child_ref::make(child_ref::kNode, uint32_t(node));
}

// The node a walk climbs to on axis a from below `node` (a voxel's nearest ancestor cut
// along a, or kNone): `node` itself, or, when it is a chain voxel (all its triangles in one
// cell, never walked in: settle), the node above it on a, and so on up. Stepping there
// instead leaves the chain's empty cells without a look; the walk keeps the chain's own
// nodes on the other axes until the ray gets there (held_by_chain, docs/design.md §1.3).
uint32_t Grid1D::walk_above(uint32_t node, int a) const {
  return passed_chain(node) != kNone ? nodes_[node].above[a] : node;
}

// The chain node walk_above(node, a) passes by, or kNone.
uint32_t Grid1D::passed_chain(uint32_t node) const {
  return node != kNone && is_chain(node) ? node : kNone;
}

bool Grid1D::is_chain(uint32_t node) const { return nodes_[node].sole_cell != Node::kManyCells; }

// The one cell of a cut that holds triangles (Node::sole_cell), or Node::kManyCells; never
// a cut that keeps spanning triangles at its node, which the walk must go down into.
uint16_t Grid1D::sole_cell(const Cut& cut) {
  uint16_t sole = Node::kManyCells;
  if (!cut.spanning.empty()) return sole;
  for (int i = 0; i < cut.granularity; ++i) {
    if (cut.tri_offsets[i + 1] == cut.tri_offsets[i]) continue;
    if (sole != Node::kManyCells) return Node::kManyCells;
    sole = uint16_t(i);
  }
  return sole;
}

// Node::occupied of a cut: bit i for a cell i < 63 that holds triangles, bit 63 for any
// such cell from 63 on.
uint64_t Grid1D::occupied_cells(const Cut& cut) {
  uint64_t occupied = 0;
  for (int i = 0; i < cut.granularity; ++i)
    if (cut.tri_offsets[i + 1] != cut.tri_offsets[i]) occupied |= uint64_t{1} << std::min(i, 63);
  return occupied;
}

namespace {

// Box k of a group of four in the grouped layout (box_group; faces lo.xyz, hi.xyz).
Box grouped_box(const float* group, uint32_t k) {
  Box box;
  for (int a = 0; a < 3; ++a) box.lo[a] = group[4 * a + k], box.hi[a] = group[4 * (3 + a) + k];
  return box;
}

// `run` grown to hold the box `box`, which is not empty.
void add_box(Box& run, const Box& box) {
  run.extend(box.lo);
  run.extend(box.hi);
}

// A box's surface area: how likely a ray that meets its surroundings is to meet it.
double box_area(const Box& box) {
  const double extent[3] = {double(box.hi.x) - box.lo.x, double(box.hi.y) - box.lo.y,
                            double(box.hi.z) - box.lo.z};
  return surface_area(extent);
}

// The union boxes of `parts` runs of consecutive boxes of `boxes` (fewer when there are
// fewer boxes) whose summed surface areas are least (about the chance that a ray meets one of
// them): an exact partition by dynamic programming over the runs' ends. Always as many runs
// as allowed: fewer runs can sum less where boxes overlap, but their union is larger (on the
// dragon that way the camera rays went down into 8% more nodes). Cells are taken in at most
// kBlocks blocks of consecutive ones, so that a node of thousands of cells costs no more
// than one of 64.
std::vector<Box> tightest_runs(const std::vector<Box>& boxes, uint32_t parts) {
  constexpr size_t kBlocks = 64;
  const size_t n = boxes.size(), blocks = std::min(n, kBlocks);
  std::vector<Box> block(blocks);
  for (size_t b = 0; b < blocks; ++b)
    for (size_t i = b * n / blocks; i < (b + 1) * n / blocks; ++i) add_box(block[b], boxes[i]);
  // least[k][j]: the least summed area of blocks 0 .. j - 1 in k runs; cut[k][j], where the
  // last of those runs begins.
  const size_t most = std::min<size_t>(parts, blocks);
  std::vector<std::vector<double>> least(most + 1, std::vector<double>(blocks + 1, kInf));
  std::vector<std::vector<size_t>> cut(most + 1, std::vector<size_t>(blocks + 1, 0));
  least[0][0] = 0.0;
  for (size_t k = 1; k <= most; ++k)
    for (size_t j = k; j <= blocks; ++j) {
      Box run;
      for (size_t i = j; i-- > k - 1;) {  // the last run is blocks i .. j - 1
        add_box(run, block[i]);
        const double area = least[k - 1][i] + box_area(run);
        if (area < least[k][j]) least[k][j] = area, cut[k][j] = i;
      }
    }
  std::vector<Box> runs(most);
  for (size_t k = most, j = blocks; k > 0; j = cut[k][j], --k)
    for (size_t i = cut[k][j]; i < j; ++i) add_box(runs[k - 1], block[i]);
  return runs;
}

// A node's summary (Node::boxes): four boxes whose union holds every cell's content box and
// `spanning` (the spanning triangles' box, empty when there are none), each box exact (a
// union of floats). The spanning triangles' box, which runs the node's whole length, has a
// box of its own; the cells that hold triangles are split into runs of consecutive cells
// whose boxes are as small as they can be (tightest_runs): where a voxel holds a few clusters
// apart, a ray between them meets no box. Boxes left over are empty.
void write_summary(const float* cell_boxes, uint32_t g, const float spanning[6], float* summary) {
  std::vector<Box> cells;
  for (uint32_t i = 0; i < g; ++i) {
    const Box cell = grouped_box(box_group(cell_boxes, i), box_lane(i));
    if (!cell.empty()) cells.push_back(cell);
  }
  Box spanning_box;
  for (int a = 0; a < 3; ++a)
    spanning_box.lo[a] = spanning[a], spanning_box.hi[a] = spanning[3 + a];
  const bool spans = !spanning_box.empty();
  std::vector<Box> boxes = tightest_runs(cells, spans ? 3 : 4);
  if (spans) boxes.push_back(spanning_box);
  boxes.resize(4);
  for (uint32_t q = 0; q < 4; ++q)
    for (int a = 0; a < 3; ++a)
      summary[4 * a + q] = boxes[q].lo[a], summary[4 * (3 + a) + q] = boxes[q].hi[a];
}

}  // namespace

// The cells' records: place, triangle counts, area estimate (§6.5), twins in the scout, and
// their references (empty cells are leaves from birth: nothing to cut, ever).
void Grid1D::link_children(uint32_t id, const Cut& cut, uint32_t first_child, uint32_t node) const {
  const Region& parent = regions_[id];
  const int axis = cut.axis;
  const auto g = uint32_t(cut.granularity);
  double lo[3], hi[3], parent_extent[3], child_extent[3];
  voxel_box(id, lo, hi);
  for (int a = 0; a < 3; ++a) parent_extent[a] = child_extent[a] = hi[a] - lo[a];
  child_extent[axis] /= double(g);
  const double parent_area = surface_area(parent_extent);
  const double area_share = parent_area > 0.0 ? surface_area(child_extent) / parent_area : 1.0;
  const Node& record = nodes_[node];
  for (uint32_t i = 0; i < g; ++i) {
    const uint32_t child = first_child + i;
    Voxel& voxel = voxels_[child];
    voxel.tri_count = cut.tri_offsets[i + 1] - cut.tri_offsets[i];
    Region& region = regions_[child];
    region = parent;
    region.cell[axis] = parent.cell[axis] * g + i;
    region.grid[axis] = parent.grid[axis] * g;
    region.above[axis] = node;
    region.depth = parent.depth + 1;
    region.ref = record.children + i;
    region.scout_twin = cut.scout_node == kNone ? kNone : cut.scout_cells + i;
    std::fill_n(region.mean_size, 3, kNotComputed);
    region.area_rays = cut.rays * area_share;
    const bool empty = voxel.tri_count == 0;
    if (empty) voxel.status.store(kLeaf, std::memory_order_relaxed);
    refs_[record.children + i].store(
        child_ref::make(empty ? child_ref::kEmpty : child_ref::kUnbuilt, child),
        std::memory_order_relaxed);
  }
}

// The content boxes of a cut's cells (an empty cell's is empty: lo +inf, hi -inf, never
// crossed) and its node's summary.
void Grid1D::write_content_boxes(uint32_t id, const Cut& cut, const Node& record) const {
  const auto g = uint32_t(cut.granularity);
  double lo[3], hi[3];
  voxel_box(id, lo, hi);
  const uint32_t stride = box_stride(g);
  float* boxes = &child_boxes_[record.boxes];
  const uint32_t first_child = voxels_[id].first_child;
  for (uint32_t i = 0; i < stride; ++i) {
    float box[6];
    if (i < g) {
      double cell_lo[3], cell_hi[3];
      voxel_box(first_child + i, cell_lo, cell_hi);
      const uint32_t* tris = cut.tris.data() + cut.tri_offsets[i];
      content_box(
          cut.tri_offsets[i + 1] - cut.tri_offsets[i],
          [&](uint32_t k) { return input_.box(tris[k]); }, cell_lo, cell_hi, input_.clip.padding,
          box);
    } else {  // padding lanes: never crossed
      content_box(
          0, [&](uint32_t) { return input_.box(0); }, lo, hi, 0.0, box);
    }
    for (int k = 0; k < 6; ++k) boxes[6 * (i & ~3u) + 4 * k + (i & 3u)] = box[k];
  }
  float spanning_box[6];
  content_box(
      uint32_t(cut.spanning.size()), [&](uint32_t k) { return input_.box(cut.spanning[k]); }, lo,
      hi, input_.clip.padding, spanning_box);
  write_summary(boxes, g, spanning_box, &child_boxes_[record.summary()]);
}

StructureStats Grid1D::stats() const {
  StructureStats s;
  s.nodes = voxels_.size();
  const uint64_t subdivided = progress_.voxels_subdivided.load(std::memory_order_relaxed);
  s.voxels_subdivided = subdivided;
  s.leaves = voxels_.size() - subdivided;
  s.traversal_states = states_.size();
  s.counts_descents = true;
  s.depth = deepest_.load();
  s.memory_bytes = bytes_used_ + input_.triangles.size() * sizeof(TriangleVerts) +
                   sample_.size() * sizeof(SampleRay) + states_.size() * sizeof(StateInfo);
  s.build_seconds = build_seconds_;
  s.voxels_over_budget = over_budget_.load();
  return s;
}

}  // namespace gs
