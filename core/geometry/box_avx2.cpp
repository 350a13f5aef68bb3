// crossed_boxes on 8 float lanes (AVX2): box_test.cpp's SSE2 operations, twice as wide, with
// masked loads so that no lane reads past the boxes. Compiled for AVX2 by the pragma below,
// after every include; called only when the CPU has it.
#include <immintrin.h>

#include "core/geometry/box_test.h"

#pragma GCC push_options
#pragma GCC target("avx2")

namespace gs {

uint64_t crossed_boxes_avx2(const float* boxes, uint32_t stride, uint32_t first, uint32_t count,
                            const RayBoxes& ray, float t0, float t1) {
  const __m256 outward_size = _mm256_set1_ps(3 * kSlabGamma), one = _mm256_set1_ps(1.0f),
               sign = _mm256_set1_ps(-0.0f);
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  uint64_t bits = 0;
  for (uint32_t i = 0; i < count; i += 8) {
    const __m256i load = _mm256_cmpgt_epi32(_mm256_set1_epi32(int(count - i)), lane);
    __m256 entry = _mm256_set1_ps(t0), exit = _mm256_set1_ps(t1);
    for (int a = 0; a < 3; ++a) {
      const __m256 o = _mm256_set1_ps(ray.origin[a]), inv = _mm256_set1_ps(ray.inv_dir[a]);
      const __m256 near_face =
          _mm256_maskload_ps(boxes + ray.near_array[a] * stride + first + i, load);
      const __m256 far_face =
          _mm256_maskload_ps(boxes + ray.far_array[a] * stride + first + i, load);
      const __m256 t_near = _mm256_mul_ps(_mm256_sub_ps(near_face, o), inv);
      const __m256 exact_far = _mm256_mul_ps(_mm256_sub_ps(far_face, o), inv);
      const __m256 outward = _mm256_or_ps(_mm256_and_ps(exact_far, sign), outward_size);
      const __m256 t_far = _mm256_mul_ps(exact_far, _mm256_add_ps(one, outward));
      entry = _mm256_max_ps(t_near, entry);
      exit = _mm256_min_ps(t_far, exit);
    }
    bits |= uint64_t(_mm256_movemask_ps(_mm256_cmp_ps(entry, exit, _CMP_LE_OQ))) << i;
  }
  return count == 64 ? bits : bits & ((uint64_t{1} << count) - 1);
}

}  // namespace gs

#pragma GCC pop_options
