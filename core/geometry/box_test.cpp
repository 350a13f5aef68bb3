#include "core/geometry/box_test.h"

#include <emmintrin.h>

#include <cmath>

namespace gs {

RayBoxes::RayBoxes(const Ray& ray) {
  for (uint32_t a = 0; a < 3; ++a) {
    origin[a] = ray.origin[a];
    inv_dir[a] = 1.0f / ray.dir[a];
    // -0 too: 1 / -0 = -inf, the ray meets the hi face first.
    const bool toward_lo = std::signbit(ray.dir[a]);
    near_array[a] = toward_lo ? 3 + a : a;
    far_array[a] = toward_lo ? a : 3 + a;
  }
}

uint64_t crossed_boxes_sse2(const float* boxes, uint32_t stride, uint32_t first, uint32_t count,
                            const RayBoxes& ray, float t0, float t1) {
  const __m128 outward_size = _mm_set1_ps(3 * kSlabGamma), one = _mm_set1_ps(1.0f),
               sign = _mm_set1_ps(-0.0f);
  uint64_t bits = 0;
  for (uint32_t i = 0; i < count; i += 4) {
    __m128 entry = _mm_set1_ps(t0), exit = _mm_set1_ps(t1);
    for (int a = 0; a < 3; ++a) {
      const __m128 o = _mm_set1_ps(ray.origin[a]), inv = _mm_set1_ps(ray.inv_dir[a]);
      const __m128 near_face = _mm_loadu_ps(boxes + ray.near_array[a] * stride + first + i);
      const __m128 far_face = _mm_loadu_ps(boxes + ray.far_array[a] * stride + first + i);
      const __m128 t_near = _mm_mul_ps(_mm_sub_ps(near_face, o), inv);
      const __m128 exact_far = _mm_mul_ps(_mm_sub_ps(far_face, o), inv);
      const __m128 outward = _mm_or_ps(_mm_and_ps(exact_far, sign), outward_size);
      const __m128 t_far = _mm_mul_ps(exact_far, _mm_add_ps(one, outward));
      // maxps / minps return their second operand when either is NaN: NaN lanes drop out.
      entry = _mm_max_ps(t_near, entry);
      exit = _mm_min_ps(t_far, exit);
    }
    bits |= uint64_t(_mm_movemask_ps(_mm_cmple_ps(entry, exit))) << i;
  }
  return count == 64 ? bits : bits & ((uint64_t{1} << count) - 1);
}

}  // namespace gs
