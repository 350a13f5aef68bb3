// A ray against many axis-aligned boxes at once: how the 1D grid's walk finds, among a
// node's cells, those whose contents (their triangles' padded boxes, content_box in
// core/geometry/clip_box.h) the ray meets, and steps straight to them. Float lanes with the
// exits widened by the bound of Ize, "Robust BVH Ray Traversal" (JCGT 2(2), 2013), so that
// rounding never reports a miss for a box the ray crosses (docs/design.md §6).
#pragma once
#include <cstdint>

#include "core/geometry/ray.h"

namespace gs {

// gamma(3) of Ize's bound, 3u / (1 - 3u) with u = 2^-24, rounded up: a slab distance
// computed in float ((face - origin) * (1 / dir), three roundings) is within a factor
// 1 +- gamma(3) of the exact one. Exits moved outward by 3 gamma(3) of their magnitude cover
// the entries' error and their own, whatever the signs (rays may start at negative t).
inline constexpr float kSlabGamma = 1.7881409e-7f;

// Boxes in structure-of-arrays form: box i's lo.x is boxes[i], lo.y boxes[stride + i], ...,
// hi.z boxes[5 * stride + i]. An empty box (lo +inf, hi -inf) is never crossed.
inline constexpr uint32_t box_stride(uint32_t count) { return (count + 3) & ~3u; }

// The ray as the box kernels read it. A zero direction component gives 1 / dir = inf, and a
// face the origin lies on 0 * inf = NaN, which the kernels' max/min ignore: that axis does
// not constrain the ray, as it should not.
struct RayBoxes {
  float origin[3], inv_dir[3];
  uint32_t near_array[3], far_array[3];  // per axis: which of the six arrays it meets first

  explicit RayBoxes(const Ray& ray);
};

// Bit i set when box first + i (i < count <= 64) is crossed by the ray somewhere in
// [t0, t1]. Lanes of 4 (SSE2, every x86-64), 8 (AVX2) or 16 (AVX-512), chosen with the leaf
// kernel (core/geometry/leaf.h, Kernel::boxes).
using BoxesTest = uint64_t (*)(const float* boxes, uint32_t stride, uint32_t first,
                               uint32_t count, const RayBoxes& ray, float t0, float t1);
uint64_t crossed_boxes_sse2(const float* boxes, uint32_t stride, uint32_t first, uint32_t count,
                            const RayBoxes& ray, float t0, float t1);
uint64_t crossed_boxes_avx2(const float* boxes, uint32_t stride, uint32_t first, uint32_t count,
                            const RayBoxes& ray, float t0, float t1);
uint64_t crossed_boxes_avx512(const float* boxes, uint32_t stride, uint32_t first,
                              uint32_t count, const RayBoxes& ray, float t0, float t1);

}  // namespace gs
