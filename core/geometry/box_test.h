// A ray against several axis-aligned boxes at once: how the 1D grid's walk finds, among a
// node's cells, those whose contents (their triangles' padded boxes, content_box in
// core/geometry/clip_box.h) the ray meets, and steps straight to them. Four float lanes
// (SSE2, on every x86-64, inlined into the walk), with the exits widened by the bound of
// Ize, "Robust BVH Ray Traversal" (JCGT 2(2), 2013), so that rounding never reports a miss
// for a box the ray crosses (docs/design.md §6.7).
#pragma once
#include <emmintrin.h>

#include <bit>
#include <cmath>
#include <cstdint>

#include "core/geometry/ray.h"

namespace gs {

// gamma(3) of Ize's bound, 3u / (1 - 3u) with u = 2^-24, rounded up: a slab distance
// computed in float ((face - origin) * (1 / dir), three roundings) is within a factor
// 1 +- gamma(3) of the exact one. Exits moved outward by 3 gamma(3) of their magnitude cover
// the entries' error and their own, whatever the signs (rays may start at negative t).
inline constexpr float kSlabGamma = 1.7881409e-7f;

// Boxes in structure-of-arrays form: box i's lo.x is boxes[i], lo.y boxes[stride + i], ...,
// hi.z boxes[5 * stride + i]. An empty box (lo +inf, hi -inf) is never crossed. A block of
// boxes takes box_floats(count) floats: the arrays and room for a 4-lane read from any box
// on.
inline constexpr uint32_t box_stride(uint32_t count) { return (count + 3) & ~3u; }
inline constexpr uint32_t box_floats(uint32_t count) { return 6 * box_stride(count) + 4; }

// Boxes in groups of four: group k holds boxes 4k .. 4k + 3 in the layout above with stride
// 4 (24 floats: lo.x of the four, lo.y, ..., hi.z), so that a test of a group reads 96
// consecutive bytes at a fixed offset per face; `count` boxes take grouped_box_floats(count)
// floats, the last group padded with empty boxes. The 1D grid's nodes keep their cells'
// content boxes so (docs/design.md §1.3).
inline constexpr uint32_t grouped_box_floats(uint32_t count) { return 6 * box_stride(count); }
// The group holding box `box` of grouped boxes, and the box's lane in it.
inline const float* box_group(const float* boxes, uint32_t box) { return boxes + 6 * (box & ~3u); }
inline uint32_t box_lane(uint32_t box) { return box & 3u; }

// Which of the six arrays holds the face a ray meets first (near) and last (far) on axis
// a: the lo faces (arrays 0..2) first unless the ray runs toward lo.
inline uint32_t near_face_array(uint32_t a, bool toward_lo) { return toward_lo ? 3 + a : a; }
inline uint32_t far_face_array(uint32_t a, bool toward_lo) { return toward_lo ? a : 3 + a; }

// A far slab distance computed in float moved outward by 3 gamma(3) of its magnitude
// (whatever its sign): the exit every float slab test here compares with. That is the
// distance times fl(1 + 3 gamma(3)) when it is positive (or +0) and fl(1 - 3 gamma(3)) when
// it is negative (or -0): the larger of the two products, since rounding is monotone, so
// no test of the sign is needed (NaN stays NaN, infinities stay). It is nondecreasing in
// the distance, so the least of the axes' widened exits is the widened least exit: the wide
// kernels (leaf_avx2.cpp, leaf_avx512.cpp) and the packets' bounds test take the least of a
// box's exact far distances (NaN ones dropped) and widen that once, fewer operations where
// many boxes are tested at a time. slab_test4, whose answer the single-ray walk waits for at
// every node, widens each axis's exit: three products that overlap instead of two after the
// chain of minima (0.5-1% faster there, measured). Both decide alike for every input.
inline constexpr float kExitGrowth = 1.0f + 3 * kSlabGamma;
inline constexpr float kExitShrink = 1.0f - 3 * kSlabGamma;
inline __m128 widened_exit(__m128 exact_far) {
  return _mm_max_ps(_mm_mul_ps(exact_far, _mm_set1_ps(kExitGrowth)),
                    _mm_mul_ps(exact_far, _mm_set1_ps(kExitShrink)));
}

// The slab test in four lanes, each a ray and a box (their near and far faces per axis):
// whether the ray crosses the box somewhere in [t0, t1].
inline uint32_t slab_test4(const __m128 near_face[3], const __m128 far_face[3],
                           const __m128 origin[3], const __m128 inv_dir[3], __m128 t0, __m128 t1) {
  __m128 entry = t0, exit = t1;
  for (int a = 0; a < 3; ++a) {
    const __m128 t_near = _mm_mul_ps(_mm_sub_ps(near_face[a], origin[a]), inv_dir[a]);
    const __m128 exact_far = _mm_mul_ps(_mm_sub_ps(far_face[a], origin[a]), inv_dir[a]);
    const __m128 t_far = widened_exit(exact_far);
    // maxps / minps return their second operand when either is NaN: NaN lanes drop out.
    entry = _mm_max_ps(t_near, entry);
    exit = _mm_min_ps(t_far, exit);
  }
  return uint32_t(_mm_movemask_ps(_mm_cmple_ps(entry, exit)));
}

// The ray as the box test reads it, per axis in all four lanes. A zero direction component
// gives 1 / dir = inf, and a face the origin lies on 0 * inf = NaN, which the test's max/min
// ignore: that axis does not constrain the ray, as it should not. Without `cull`, every box
// is reported crossed (origin and 1 / dir zero: every slab distance 0 or NaN), for callers
// whose walk does not follow the ray's own line (WalkLine::far).
struct RayBoxes {
  __m128 origin[3], inv_dir[3];
  uint32_t near_array[3], far_array[3];  // per axis: which of the six arrays it meets first
  // The same faces' offsets in a group of grouped boxes (box_group), kept at hand: the 1D
  // grid tests a group per node it enters, and the products cost as much as the loads.
  uint32_t near_in_group[3], far_in_group[3];  // in bytes

  RayBoxes() = default;
  explicit RayBoxes(const Ray& ray, bool cull = true) {
    for (uint32_t a = 0; a < 3; ++a) {
      origin[a] = _mm_set1_ps(cull ? ray.origin[a] : 0.0f);
      inv_dir[a] = _mm_set1_ps(cull ? 1.0f / ray.dir[a] : 0.0f);
      // -0 too: 1 / -0 = -inf, the ray meets the hi face first.
      const bool toward_lo = std::signbit(ray.dir[a]);
      near_array[a] = near_face_array(a, toward_lo);
      far_array[a] = far_face_array(a, toward_lo);
      near_in_group[a] = 4 * near_array[a] * sizeof(float);
      far_in_group[a] = 4 * far_array[a] * sizeof(float);
    }
  }

  // Bits 0..3 for boxes first .. first + 3: set when the ray crosses the box somewhere in
  // [t0, t1] (all four lanes). Callers mask off boxes past the ones they asked about.
  uint32_t crossed4(const float* boxes, uint32_t stride, uint32_t first, __m128 t0,
                    __m128 t1) const {
    __m128 near_face[3], far_face[3];
    for (int a = 0; a < 3; ++a) {
      near_face[a] = _mm_loadu_ps(boxes + near_array[a] * stride + first);
      far_face[a] = _mm_loadu_ps(boxes + far_array[a] * stride + first);
    }
    return slab_test4(near_face, far_face, origin, inv_dir, t0, t1);
  }
  // Bits 0..3 for the four boxes of a group of grouped boxes (box_group).
  uint32_t crossed_group(const float* group, __m128 t0, __m128 t1) const {
    const char* bytes = reinterpret_cast<const char*>(group);
    __m128 near_face[3], far_face[3];
    for (int a = 0; a < 3; ++a) {
      near_face[a] = _mm_loadu_ps(reinterpret_cast<const float*>(bytes + near_in_group[a]));
      far_face[a] = _mm_loadu_ps(reinterpret_cast<const float*>(bytes + far_in_group[a]));
    }
    return slab_test4(near_face, far_face, origin, inv_dir, t0, t1);
  }
};

// Interval bounds of a packet's box-test rays (RayBoxLanes; the interval arithmetic of
// Boulos, Wald and Shirley's packet culling, 2006): per axis the least and the greatest
// origin and 1 / dir, the least t0 and the greatest t1. A box test against the bounds
// (may_cross4, Kernel::bounds_crossed) says "no ray crosses" only where each ray's own test
// (slab_test4) would say it misses (docs/design.md §6.9): the least entry and the greatest
// exit any ray can compute bound every ray's, because float rounding is monotone.
// An axis some ray does not cross with a finite 1 / dir of the packet's sign (a zero
// component, or a far ray's zero) is not used. Every figure in all four lanes.
struct RayBoxBounds {
  // (face - origin) * inv_dir grows with the face term and, for 1 / dir > 0, falls with the
  // origin: the least near distance takes the greatest origin, the greatest far distance the
  // least (and the other way round for 1 / dir < 0).
  __m128 near_origin[3] = {}, far_origin[3] = {}, inv_lo[3] = {}, inv_hi[3] = {};
  __m128 t0_lo = {}, t1_hi = {};
  uint32_t axes = 0;  // bit a: axis a bounds the rays

  void set(const float origin_lo[3], const float origin_hi[3], const float inv_dir_lo[3],
           const float inv_dir_hi[3], float t0, float t1) {
    axes = 0;
    for (int a = 0; a < 3; ++a) {
      const bool up = inv_dir_lo[a] > 0.0f && inv_dir_hi[a] < INFINITY;
      const bool down = inv_dir_hi[a] < 0.0f && inv_dir_lo[a] > -INFINITY;
      axes |= uint32_t(up || down) << a;
      near_origin[a] = _mm_set1_ps(up ? origin_hi[a] : origin_lo[a]);
      far_origin[a] = _mm_set1_ps(up ? origin_lo[a] : origin_hi[a]);
      inv_lo[a] = _mm_set1_ps(inv_dir_lo[a]), inv_hi[a] = _mm_set1_ps(inv_dir_hi[a]);
    }
    t0_lo = _mm_set1_ps(t0), t1_hi = _mm_set1_ps(t1);
  }
  // Bits 0..3 for boxes first .. first + 3: clear when no ray of the bounds crosses the box.
  uint32_t may_cross4(const float* boxes, uint32_t stride, uint32_t first,
                      const uint32_t near_array[3], const uint32_t far_array[3]) const {
    __m128 entry = t0_lo, greatest_far = _mm_set1_ps(INFINITY);
    for (int a = 0; a < 3; ++a) {
      if (!(axes >> a & 1)) continue;
      // A ray's near distance is at least the near gap times one of the two 1 / dir bounds,
      // its far distance at most the far gap times one of them (the products are linear
      // in 1 / dir): the least and the greatest of the two products bound them.
      const __m128 near_gap =
          _mm_sub_ps(_mm_loadu_ps(boxes + near_array[a] * stride + first), near_origin[a]);
      const __m128 far_gap =
          _mm_sub_ps(_mm_loadu_ps(boxes + far_array[a] * stride + first), far_origin[a]);
      const __m128 least_near =
          _mm_min_ps(_mm_mul_ps(near_gap, inv_lo[a]), _mm_mul_ps(near_gap, inv_hi[a]));
      const __m128 exact_far =
          _mm_max_ps(_mm_mul_ps(far_gap, inv_lo[a]), _mm_mul_ps(far_gap, inv_hi[a]));
      entry = _mm_max_ps(least_near, entry);
      greatest_far = _mm_min_ps(exact_far, greatest_far);
    }
    // slab_test4's widening, which grows with the distance: applied to the least over the
    // axes of each axis's greatest far distance.
    const __m128 exit = _mm_min_ps(widened_exit(greatest_far), t1_hi);
    return uint32_t(_mm_movemask_ps(_mm_cmpngt_ps(entry, exit)));  // NaN: may cross
  }
};

// Up to 64 rays with the same direction signs (so the same near and far faces) against one
// box at a time, rays in lanes: RayBoxes' test with the roles swapped, for a packet's rays
// in a leaf (docs/design.md §6.9). crossed() takes four rays at a time; the kernels of wider
// instruction sets take 8 or 16 (Kernel::rays_crossed), each lane the same operations.
// Arrays padded and aligned for a 16-lane read from any multiple of 16.
struct RayBoxLanes {
  static constexpr uint32_t kPadded = 64 + 16;
  alignas(64) float origin[3][kPadded] = {}, inv_dir[3][kPadded] = {};
  alignas(64) float t0[kPadded] = {}, t1[kPadded] = {};
  uint32_t near_array[3] = {0, 1, 2}, far_array[3] = {3, 4, 5};
  RayBoxBounds bounds;  // of the rays the packet walk set (the packet's prepare)

  // Bits 0..3: the boxes first .. first + 3 one of the bounded rays may cross.
  uint32_t may_cross4(const float* boxes, uint32_t stride, uint32_t first) const {
    return bounds.may_cross4(boxes, stride, first, near_array, far_array);
  }

  // Sets ray `lane` to `ray` searching [t_lo, t_hi] (the same lanes of each).
  void set(uint32_t lane, const RayBoxes& ray, __m128 t_lo, __m128 t_hi) {
    for (int a = 0; a < 3; ++a) {
      origin[a][lane] = _mm_cvtss_f32(ray.origin[a]),
      inv_dir[a][lane] = _mm_cvtss_f32(ray.inv_dir[a]);
      near_array[a] = ray.near_array[a], far_array[a] = ray.far_array[a];
    }
    t0[lane] = _mm_cvtss_f32(t_lo), t1[lane] = _mm_cvtss_f32(t_hi);
  }
  // A new end for ray `lane`'s segment (its nearest hit moved in).
  void set_end(uint32_t lane, __m128 t_hi) { t1[lane] = _mm_cvtss_f32(t_hi); }
  // Ray `lane` as a single ray's box tests take it (its segment is t0[lane] .. t1[lane]):
  // the same figures, so the same bits. The face offsets are set as RayBoxes' constructor
  // sets them, on purpose not through a shared setter: that cost the single walk 0.8% more
  // instructions a ray (pyramid 1,563 -> 1,576).
  RayBoxes single(uint32_t lane) const {
    RayBoxes ray;
    for (int a = 0; a < 3; ++a) {
      ray.origin[a] = _mm_set1_ps(origin[a][lane]), ray.inv_dir[a] = _mm_set1_ps(inv_dir[a][lane]);
      ray.near_array[a] = near_array[a], ray.far_array[a] = far_array[a];
      ray.near_in_group[a] = 4 * near_array[a] * sizeof(float);
      ray.far_in_group[a] = 4 * far_array[a] * sizeof(float);
    }
    return ray;
  }
  // Of the rays in `rays` (bits), those that cross box `box` of `boxes`: four at a time,
  // only the fours that hold one of them.
  uint64_t crossed(const float* boxes, uint32_t stride, uint32_t box, uint64_t rays) const {
    __m128 near_face[3], far_face[3];
    for (int a = 0; a < 3; ++a) {
      near_face[a] = _mm_set1_ps(boxes[near_array[a] * stride + box]);
      far_face[a] = _mm_set1_ps(boxes[far_array[a] * stride + box]);
    }
    uint64_t met = 0;
    const uint64_t asked = rays;
    while (rays != 0) {
      const uint32_t first = uint32_t(std::countr_zero(rays)) & ~3u;
      __m128 o[3], inv[3];
      for (int a = 0; a < 3; ++a)
        o[a] = _mm_load_ps(origin[a] + first), inv[a] = _mm_load_ps(inv_dir[a] + first);
      met |= uint64_t(slab_test4(near_face, far_face, o, inv, _mm_load_ps(t0 + first),
                                 _mm_load_ps(t1 + first)))
             << first;
      rays &= ~(uint64_t{15} << first);
    }
    return met & asked;
  }
};

}  // namespace gs
