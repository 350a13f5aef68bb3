// The leaf kernels for wider instruction sets, each compiled for its own target in its own
// file (leaf_avx2.cpp, leaf_avx512.cpp) and called only when the CPU has it
// (core/geometry/leaf.h, kernel_for).
#pragma once
#include <bit>

#include "core/geometry/leaf.h"

namespace gs {

// 4 double lanes.
uint32_t test_lanes_avx2(const LeafView& leaf, uint32_t first, uint32_t lanes,
                         const PreparedRay<KernelReal>& ray, float tmax, LaneHits& out);
// 8 double lanes.
uint32_t test_lanes_avx512(const LeafView& leaf, uint32_t first, uint32_t lanes,
                           const PreparedRay<KernelReal>& ray, float tmax, LaneHits& out);

// The same with rays in lanes (RayTest).
uint64_t test_rays_avx2(const LeafView& leaf, uint32_t tri, const RayLanes& rays, uint64_t lanes,
                        RayHits& out);
uint64_t test_rays_avx512(const LeafView& leaf, uint32_t tri, const RayLanes& rays, uint64_t lanes,
                          RayHits& out);
uint64_t test_rays_scalar(const LeafView& leaf, uint32_t tri, const RayLanes& rays, uint64_t lanes,
                          RayHits& out);

// The boxes (bits of `which`) of a RaysCrossed call whose crossing entries hold a ray of
// `rays`, after those entries are cut to `rays` (the wide kernels test whole groups of rays).
inline uint64_t boxes_with_crossers(uint64_t which, uint64_t rays, uint64_t* crossing) {
  uint64_t crossed = 0;
  for (; which != 0; which &= which - 1) {
    const auto k = uint32_t(std::countr_zero(which));
    crossing[k] &= rays;
    crossed |= uint64_t(crossing[k] != 0) << k;
  }
  return crossed;
}

// RaysCrossed with 4 (SSE), 8 and 16 rays in lanes.
uint64_t rays_crossed_sse(const RayBoxLanes& lanes, const float* boxes, uint32_t stride,
                          uint32_t first, uint64_t which, uint64_t rays, uint64_t* crossing);
uint64_t rays_crossed_avx2(const RayBoxLanes& lanes, const float* boxes, uint32_t stride,
                           uint32_t first, uint64_t which, uint64_t rays, uint64_t* crossing);
uint64_t rays_crossed_avx512(const RayBoxLanes& lanes, const float* boxes, uint32_t stride,
                             uint32_t first, uint64_t which, uint64_t rays, uint64_t* crossing);

// BoundsCrossed with 4 (SSE), 8 and 16 boxes in lanes.
uint64_t bounds_crossed_sse(const RayBoxLanes& lanes, const float* boxes, uint32_t stride,
                            uint32_t first, uint32_t count);
uint64_t bounds_crossed_avx2(const RayBoxLanes& lanes, const float* boxes, uint32_t stride,
                             uint32_t first, uint32_t count);
uint64_t bounds_crossed_avx512(const RayBoxLanes& lanes, const float* boxes, uint32_t stride,
                               uint32_t first, uint32_t count);

// BoxesCrossed with 4 (SSE), 8 and 16 boxes in lanes.
uint64_t boxes_crossed_sse(const RayBoxes& ray, const float* boxes, uint32_t stride, uint32_t first,
                           uint32_t count, __m128 t0, __m128 t1);
uint64_t boxes_crossed_avx2(const RayBoxes& ray, const float* boxes, uint32_t stride,
                            uint32_t first, uint32_t count, __m128 t0, __m128 t1);
uint64_t boxes_crossed_avx512(const RayBoxes& ray, const float* boxes, uint32_t stride,
                              uint32_t first, uint32_t count, __m128 t0, __m128 t1);

// Lanes whose edge functions rounded to zero: the scalar kernel redoes them in wider
// arithmetic (the paper's rule), so they are handed to it. Returns the lanes of `zero` it
// found hit, filling `out`.
uint32_t test_lanes_scalar(const LeafView& leaf, uint32_t first, uint32_t lanes,
                           const PreparedRay<KernelReal>& ray, float tmax, LaneHits& out);

}  // namespace gs
