// crossed_boxes on 16 float lanes (AVX-512 F): box_test.cpp's SSE2 operations, four times as
// wide, with masked loads so that no lane reads past the boxes. Compiled for AVX-512 by the
// pragma below, after every include; called only when the CPU has it.
#include <immintrin.h>

#include "core/geometry/box_test.h"

#pragma GCC push_options
#pragma GCC target("avx512f,avx512vl,avx512dq")

namespace gs {

uint64_t crossed_boxes_avx512(const float* boxes, uint32_t stride, uint32_t first,
                              uint32_t count, const RayBoxes& ray, float t0, float t1) {
  const __m512 outward_size = _mm512_set1_ps(3 * kSlabGamma), one = _mm512_set1_ps(1.0f);
  const __m512i sign = _mm512_set1_epi32(int(0x80000000u));
  uint64_t bits = 0;
  for (uint32_t i = 0; i < count; i += 16) {
    const auto load = __mmask16(count - i >= 16 ? 0xFFFFu : (1u << (count - i)) - 1u);
    __m512 entry = _mm512_set1_ps(t0), exit = _mm512_set1_ps(t1);
    for (int a = 0; a < 3; ++a) {
      const __m512 o = _mm512_set1_ps(ray.origin[a]), inv = _mm512_set1_ps(ray.inv_dir[a]);
      const __m512 near_face =
          _mm512_maskz_loadu_ps(load, boxes + ray.near_array[a] * stride + first + i);
      const __m512 far_face =
          _mm512_maskz_loadu_ps(load, boxes + ray.far_array[a] * stride + first + i);
      const __m512 t_near = _mm512_mul_ps(_mm512_sub_ps(near_face, o), inv);
      const __m512 exact_far = _mm512_mul_ps(_mm512_sub_ps(far_face, o), inv);
      const __m512 outward = _mm512_castsi512_ps(_mm512_or_si512(
          _mm512_and_si512(_mm512_castps_si512(exact_far), sign),
          _mm512_castps_si512(outward_size)));
      const __m512 t_far = _mm512_mul_ps(exact_far, _mm512_add_ps(one, outward));
      // vmaxps / vminps return their second operand when either is NaN: NaN lanes drop out.
      // (Zero-masked with every lane on: GCC 12's plain forms warn about their own
      // undefined source operand.)
      entry = _mm512_maskz_max_ps(0xFFFF, t_near, entry);
      exit = _mm512_maskz_min_ps(0xFFFF, t_far, exit);
    }
    bits |= uint64_t(_mm512_mask_cmp_ps_mask(load, entry, exit, _CMP_LE_OQ)) << i;
  }
  return count == 64 ? bits : bits & ((uint64_t{1} << count) - 1);
}

}  // namespace gs

#pragma GCC pop_options
