// A leaf's triangles stored once, in the form the kernels read (structure of arrays), and
// the one leaf-test loop every structure uses: mailbox, kernel, nearest-hit rule, counters.
// The kernel tests several triangles at once where the CPU allows (core/geometry/simd.h):
// every lane computes exactly the scalar kernel's operations in the same order, so the
// answers are the scalar kernel's bit for bit (docs/design.md §6.6).
#pragma once
#include <bit>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/accel/accelerator.h"
#include "core/base/check.h"
#include "core/base/stable_array.h"
#include "core/geometry/box_test.h"
#include "core/geometry/clip_box.h"
#include "core/geometry/kernel.h"
#include "core/geometry/mailbox.h"
#include "core/geometry/triangles.h"

namespace gs {

// Set in a leaf's id entry when the triangle's padded box lies inside the leaf's cell: no
// earlier cell of any walk can have held it, so it skips the mailbox.
inline constexpr uint32_t kOnlyHere = 1u << 31;

// One leaf: triangle i's corner k (0..2), axis a (0..2) is coords[(3k + a) * count + i];
// ids[i] is its id, with kOnlyHere possibly set. `boxes` (when not null) holds the
// triangles' padded boxes rounded outward to float, in box_test.h's layout (stride
// box_stride(count)): a ray whose segment misses a triangle's box cannot be reported a hit
// by the kernel (docs/design.md §6.7), so the leaf loop skips the test.
struct LeafView {
  const float* coords = nullptr;
  const uint32_t* ids = nullptr;
  uint32_t count = 0;
  const float* boxes = nullptr;

  uint32_t id(uint32_t i) const { return ids[i] & ~kOnlyHere; }
  const float* corner(uint32_t i, int k) const { return coords + size_t(3 * k) * count + i; }
};

// Leaves appended by one or more building threads, never moved (readers may be walking
// others while a leaf is added). A leaf's handle is its position in the id arena, which
// holds its count, where its floats start in the float arena, and its ids; its floats are
// its coordinates and then its triangles' boxes.
class LeafStore {
 public:
  // Address space for `max_bytes` of leaves (reserved, committed as leaves are written).
  explicit LeafStore(uint64_t max_bytes = 0);
  // Drops every leaf and reserves `max_bytes` afresh: for a structure built up front, which
  // knows what its leaves take before it stores them. Only while nobody reads the store.
  void reset(uint64_t max_bytes);
  // Exchanges two stores' leaves (handles stay valid in the store that holds them now). Only
  // while nobody reads either.
  void swap(LeafStore& other) noexcept {
    ids_.swap(other.ids_);
    coords_.swap(other.coords_);
  }
  // Appends a leaf of the triangles `ids` (each with kOnlyHere where it applies; corners
  // and padded boxes from `input`) and returns its handle, or kFull when the reservation is
  // spent.
  static constexpr uint32_t kFull = UINT32_MAX;
  uint32_t add(const std::vector<uint32_t>& ids, const BuildInput& input);
  LeafView view(uint32_t handle) const {
    GRIDSCOPE_CHECK(size_t(handle) + 1 < ids_.size());
    const uint32_t count = ids_[handle];
    const float* coords = &coords_[ids_[size_t(handle) + 1]];
    return {coords, &ids_[size_t(handle) + 2], count, coords + size_t(9) * count};
  }
  // At most the bytes one leaf of n triangles takes: its count, offset and ids, its
  // coordinates, and its boxes (box_floats(n) <= 6n + 22).
  static uint64_t bytes_for(uint32_t n) {
    return uint64_t(n + 2) * sizeof(uint32_t) + (uint64_t(n) * 15 + 22) * sizeof(float);
  }
  uint64_t bytes() const { return ids_.size() * sizeof(uint32_t) + coords_.size() * sizeof(float); }

 private:
  StableArray<uint32_t> ids_;
  StableArray<float> coords_;
};

// The kernel's instruction set. One binary carries them all and picks the widest the CPU
// has (or GRIDSCOPE_ISA=scalar|avx2|avx512), as Embree does.
enum class Isa { scalar, avx2, avx512 };
const char* isa_name(Isa isa);
// Whether this CPU can run `isa`.
bool isa_supported(Isa isa);
// The instruction set structures built from now on use: GRIDSCOPE_ISA if set (a UsageError
// when it names an unknown set or one this CPU lacks), else the widest this CPU has.
Isa kernel_isa();
// Overrides kernel_isa() for structures built afterwards (the tests run every path);
// UsageError when this CPU lacks it.
void force_kernel_isa(Isa isa);

// What a kernel call reports for up to kMaxLanes triangles of a leaf.
inline constexpr uint32_t kMaxLanes = 8;
struct LaneHits {
  float t[kMaxLanes], u[kMaxLanes], v[kMaxLanes];
};

// Tests triangles first .. first + kLanes - 1 of `leaf` (those whose bit is set in `lanes`)
// and returns the bits of those hit with tmin < t <= tmax, their t, u and v in `out`. Every
// lane's figures are the scalar intersect_triangle's, bit for bit.
using LaneTest = uint32_t (*)(const LeafView& leaf, uint32_t first, uint32_t lanes,
                              const PreparedRay<KernelReal>& ray, float tmax, LaneHits& out);

// A packet's rays in the form the rays-in-lanes kernels read (structure of arrays of their
// PreparedRay figures), all with the same axis order kx, ky, kz; each array padded so that a
// kMaxLanes-wide read from any ray on stays inside it.
struct RayLanes {
  static constexpr uint32_t kMaxRays = 64;
  static constexpr uint32_t kPadded = kMaxRays + kMaxLanes;
  uint32_t count = 0;
  int kx = 0, ky = 0, kz = 0;
  alignas(64) double ox[kPadded] = {}, oy[kPadded] = {}, oz[kPadded] = {};
  alignas(64) double sx[kPadded] = {}, sy[kPadded] = {}, sz[kPadded] = {};
  alignas(64) double shift[kPadded] = {};
  alignas(64) float tmin[kPadded] = {}, tmax[kPadded] = {};  // tmax: the ray's nearest hit so far

  // Appends a ray (whose axis order must be kx, ky, kz) searching up to tmax.
  void add(const PreparedRay<KernelReal>& ray, float ray_tmax) {
    ox[count] = ray.origin[kx], oy[count] = ray.origin[ky], oz[count] = ray.origin[kz];
    sx[count] = ray.sx, sy[count] = ray.sy, sz[count] = ray.sz;
    shift[count] = ray.shift, tmin[count] = ray.tmin, tmax[count++] = ray_tmax;
  }
  // Lane r's ray as the scalar kernel takes it (for lanes it redoes in wider arithmetic).
  PreparedRay<KernelReal> prepared(uint32_t r) const {
    PreparedRay<KernelReal> ray;
    ray.origin[kx] = ox[r], ray.origin[ky] = oy[r], ray.origin[kz] = oz[r];
    ray.shift = shift[r], ray.tmin = tmin[r];
    ray.kx = kx, ray.ky = ky, ray.kz = kz;
    ray.sx = sx[r], ray.sy = sy[r], ray.sz = sz[r];
    return ray;
  }
};

// What a RayTest reports for a packet's rays.
struct RayHits {
  alignas(64) float t[RayLanes::kPadded], u[RayLanes::kPadded], v[RayLanes::kPadded];
};

// Tests triangle `tri` of `leaf` against the rays of `rays` whose bit is set in `lanes`,
// several at a time (rays in lanes), each up to its own tmax, and returns the bits of those
// hit with their t, u and v in `out`: what LaneTest does with the roles of ray and triangle
// swapped, with the same guarantee (each lane is the scalar kernel, bit for bit).
using RayTest = uint64_t (*)(const LeafView& leaf, uint32_t tri, const RayLanes& rays,
                             uint64_t lanes, RayHits& out);

// For each box first + k of `boxes` (box_test.h's layout) with bit k of `which` set, the
// rays of `rays` (bits) whose lanes of `lanes` cross it: crossing[k] (the other entries are
// not written). Returns the boxes (bits k) some ray crosses. RayBoxLanes::crossed, 4, 8 or 16
// rays at a time by instruction set; each group of rays is loaded once for all the boxes (a
// leaf's triangles are tested together).
using RaysCrossed = uint64_t (*)(const RayBoxLanes& lanes, const float* boxes, uint32_t stride,
                                 uint32_t first, uint64_t which, uint64_t rays, uint64_t* crossing);

// Of `count` (1..64) boxes of `boxes` from box `first` on (box_test.h's layout, stride
// `stride`), those that one ray crosses within [t0, t1]: bit k for box first + k, none past
// `count`. RayBoxes::crossed4's test 4, 8 or 16 boxes at a time by instruction set, each
// lane the same operations, so every bit is crossed4's (a leaf's triangles are filtered in
// a few wide tests).
using BoxesCrossed = uint64_t (*)(const RayBoxes& ray, const float* boxes, uint32_t stride,
                                  uint32_t first, uint32_t count, __m128 t0, __m128 t1);

// Of `count` (1..64) boxes of `boxes` from box `first` on (box_test.h's layout, stride
// `stride`), those that one of the rays of `lanes`' bounds may cross: bit k for box first
// + k, none past `count`. RayBoxBounds::may_cross4's test 4, 8 or 16 boxes at a time by
// instruction set, each lane the same operations (a packet's leaf rules out the triangles no
// ray reaches before testing any ray).
using BoundsCrossed = uint64_t (*)(const RayBoxLanes& lanes, const float* boxes, uint32_t stride,
                                   uint32_t first, uint32_t count);

struct Kernel {
  uint32_t lanes = 1;      // doubles: the triangle tests' width
  uint32_t box_lanes = 4;  // floats: the box tests' width
  LaneTest test = nullptr;
  RayTest test_rays = nullptr;
  RaysCrossed rays_crossed = nullptr;
  BoxesCrossed boxes_crossed = nullptr;
  BoundsCrossed bounds_crossed = nullptr;
};
Kernel kernel_for(Isa isa);

// The per-thread context of a structure whose only tracing scratch is the mailbox.
// Cache-line aligned: two threads' contexts must not share a line.
struct alignas(64) MailboxContext final : ThreadContext {
  Mailbox mailbox;
};

// The timed path's recorder hooks for leaf tests: nothing.
struct NoLeafRecord {
  void tested(uint32_t /*count*/) {}
  void rejected() {}
};

// The segment a ray's box tests cover, in the ray's own t (docs/design.md §6.7): from its
// entry into the clip box to a stop distance `stop` (in the walk line's t), rounded outward
// to float; the whole line from far away (WalkLine::far), where box tests cull nothing.
inline __m128 box_test_start(const WalkLine& line) {
  return _mm_set1_ps(line.far ? -std::numeric_limits<float>::infinity()
                              : float_down(line.shift + line.t0));
}
inline __m128 box_test_end(bool far, double shift, double stop) {
  return _mm_set1_ps(far ? std::numeric_limits<float>::infinity() : float_up(shift + stop));
}
inline __m128 box_test_end(const WalkLine& line, double stop) {
  return box_test_end(line.far, line.shift, stop);
}

// The ray's test against a leaf's triangle boxes (LeafView::boxes), over the segment it
// searches: its RayBoxes and that segment in its own t, as the 1D grid tests content boxes
// (docs/design.md §6.7). Without `boxes`, every triangle is tested.
struct BoxFilter {
  const RayBoxes* boxes = nullptr;
  __m128 t_lo = _mm_setzero_ps(), t_hi = _mm_setzero_ps();

  // A walk that keeps the segment as it was at the start, up to the ray's tmax (the filter
  // then culls a little less once a hit is found).
  static BoxFilter up_to_tmax(const RayBoxes& boxes, const WalkLine& line, float tmax) {
    return {&boxes, box_test_start(line), box_test_end(line, line.stop(tmax))};
  }
  // Bits 0..count-1 (count <= 64) for triangles first .. first + count - 1 whose box the
  // ray's segment crosses (all of them without a filter or boxes).
  uint64_t crossed(const Kernel& kernel, const LeafView& leaf, uint32_t first,
                   uint32_t count) const {
    if (!boxes || !leaf.boxes) return count == 64 ? ~uint64_t{0} : (uint64_t{1} << count) - 1;
    return kernel.boxes_crossed(*boxes, leaf.boxes, box_stride(leaf.count), first, count, t_lo,
                                t_hi);
  }
};

// Tests triangles block + k of the leaf (bit k of `crossed`, a 64-triangle block's boxes
// the ray crosses) that this ray has not tested yet (`mailbox`), keeping `best` the nearest
// hit (lowest id among equal t; docs/design.md §6.4) and `tmax` its t. Returns true when one
// of them became the nearest hit (AnyHit: when one blocks the ray, which ends the search).
// Triangles go to the kernel in its groups of kernel.lanes, in order; a group none of whose
// boxes the ray crosses is passed over. `mailbox` is the ray's (Mailbox) or, for a packet's
// ray searching alone, the packet's seen through the ray's bit. Forced inline: with GCC's
// own inlining the single walk took 0.3-0.5% more instructions a ray (pyramid 1,573 against
// 1,563, cathedral 5,694 against 5,665).
template <bool AnyHit, class Mailboxes, class Record>
[[gnu::always_inline]] inline bool test_crossed(const LeafView& leaf, const Kernel& kernel,
                                                const PreparedRay<KernelReal>& ray, uint32_t block,
                                                uint64_t crossed, uint64_t ray_id, float& tmax,
                                                Hit& best, Mailboxes& mailbox,
                                                TraceCounters& counters, Record& record) {
  const uint32_t group = (1u << kernel.lanes) - 1u;
  bool found = false;
  while (crossed != 0) {
    const uint32_t offset = uint32_t(std::countr_zero(crossed)) & ~(kernel.lanes - 1u);
    const uint32_t first = block + offset;
    uint32_t lanes = 0, tested = 0;
    for (uint32_t left = uint32_t(crossed >> offset) & group; left != 0; left &= left - 1) {
      const auto j = uint32_t(std::countr_zero(left));
      const uint32_t id = leaf.ids[first + j];
      if (!(id & kOnlyHere) && mailbox.already_tested(id, ray_id)) {
        ++counters.mailbox_rejections;
        record.rejected();
      } else {
        lanes |= 1u << j;
        ++tested;
      }
    }
    crossed &= ~(uint64_t{group} << offset);
    if (lanes == 0) continue;
    counters.intersection_tests += tested;
    record.tested(tested);
    LaneHits out;
    for (uint32_t hits = kernel.test(leaf, first, lanes, ray, tmax, out); hits != 0;
         hits &= hits - 1) {
      const uint32_t j = uint32_t(std::countr_zero(hits));
      const auto id = int32_t(leaf.id(first + j));
      if (closer(out.t[j], id, best)) {
        best = {id, out.t[j], out.u[j], out.v[j]};
        tmax = out.t[j];
        found = true;
        if (AnyHit) return true;
      }
    }
  }
  return found;
}

// Tests the leaf's triangles this ray has not tested yet and whose boxes it crosses
// (`filter`), as test_crossed does, a block of 64 at a time: most boxes are missed, so only
// the triangles whose box the ray crosses are looked at.
template <bool AnyHit, class Record = NoLeafRecord>
inline bool test_leaf(const LeafView& leaf, const Kernel& kernel,
                      const PreparedRay<KernelReal>& ray, const BoxFilter& filter, uint64_t ray_id,
                      float& tmax, Hit& best, Mailbox& mailbox, TraceCounters& counters,
                      Record&& record = {}) {
  GRIDSCOPE_CHECK(kernel.lanes <= kMaxLanes && 64 % kernel.lanes == 0);
  counters.leaf_triangles += leaf.count;
  bool found = false;
  for (uint32_t block = 0; block < leaf.count; block += 64) {
    const uint64_t crossed = filter.crossed(kernel, leaf, block, std::min(64u, leaf.count - block));
    if (test_crossed<AnyHit>(leaf, kernel, ray, block, crossed, ray_id, tmax, best, mailbox,
                             counters, record)) {
      found = true;
      if (AnyHit) return true;
    }
  }
  return found;
}

}  // namespace gs
