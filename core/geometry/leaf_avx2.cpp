// The leaf kernel on 4 double lanes (AVX2). Each lane performs the scalar kernel's
// operations (core/geometry/kernel.h) in the same order, without fused multiply-adds, so its
// t, u and v are the scalar kernel's bit for bit (docs/design.md §6.6). Compiled for AVX2 by
// the pragma below, after every include, so that no inline function shared with other files
// is compiled for it; called only when the CPU has AVX2.
#include <immintrin.h>

#include "core/geometry/simd.h"

#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx2"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2")
#endif

namespace gs {
namespace {

// One coordinate of the lanes' triangles as doubles; masked-off lanes read nothing.
inline __m256d coordinate(const float* array, __m128i mask) {
  return _mm256_cvtps_pd(_mm_maskload_ps(array, mask));
}

// The lanes where `Predicate` holds between some edge function and zero (a template
// argument: the compare takes an immediate).
template <int Predicate>
inline uint32_t any_edge(__m256d e0, __m256d e1, __m256d e2) {
  const __m256d zero = _mm256_setzero_pd();
  return uint32_t(_mm256_movemask_pd(_mm256_or_pd(
      _mm256_or_pd(_mm256_cmp_pd(e0, zero, Predicate), _mm256_cmp_pd(e1, zero, Predicate)),
      _mm256_cmp_pd(e2, zero, Predicate))));
}

}  // namespace

uint32_t test_lanes_avx2(const LeafView& leaf, uint32_t first, uint32_t lanes,
                         const PreparedRay<KernelReal>& ray, float tmax, LaneHits& out) {
  const __m128i mask = _mm_cmpgt_epi32(
      _mm_and_si128(_mm_set1_epi32(int(lanes)), _mm_setr_epi32(1, 2, 4, 8)), _mm_setzero_si128());
  const auto load = [&](int corner, int axis) {
    return coordinate(leaf.corner(first, corner) + size_t(axis) * leaf.count, mask);
  };
  const int kx = ray.kx, ky = ray.ky, kz = ray.kz;
  const __m256d ox = _mm256_set1_pd(ray.origin[kx]), oy = _mm256_set1_pd(ray.origin[ky]),
                oz = _mm256_set1_pd(ray.origin[kz]);
  const __m256d sx = _mm256_set1_pd(ray.sx), sy = _mm256_set1_pd(ray.sy),
                sz = _mm256_set1_pd(ray.sz);
  const __m256d az = _mm256_sub_pd(load(0, kz), oz), bz = _mm256_sub_pd(load(1, kz), oz),
                cz = _mm256_sub_pd(load(2, kz), oz);
  const __m256d ax = _mm256_sub_pd(_mm256_sub_pd(load(0, kx), ox), _mm256_mul_pd(sx, az));
  const __m256d ay = _mm256_sub_pd(_mm256_sub_pd(load(0, ky), oy), _mm256_mul_pd(sy, az));
  const __m256d bx = _mm256_sub_pd(_mm256_sub_pd(load(1, kx), ox), _mm256_mul_pd(sx, bz));
  const __m256d by = _mm256_sub_pd(_mm256_sub_pd(load(1, ky), oy), _mm256_mul_pd(sy, bz));
  const __m256d cx = _mm256_sub_pd(_mm256_sub_pd(load(2, kx), ox), _mm256_mul_pd(sx, cz));
  const __m256d cy = _mm256_sub_pd(_mm256_sub_pd(load(2, ky), oy), _mm256_mul_pd(sy, cz));
  const __m256d e0 = _mm256_sub_pd(_mm256_mul_pd(cx, by), _mm256_mul_pd(cy, bx));
  const __m256d e1 = _mm256_sub_pd(_mm256_mul_pd(ax, cy), _mm256_mul_pd(ay, cx));
  const __m256d e2 = _mm256_sub_pd(_mm256_mul_pd(bx, ay), _mm256_mul_pd(by, ax));

  const __m256d zero = _mm256_setzero_pd();

  // An edge function of exactly zero is redone in wider arithmetic: the scalar kernel's.
  const uint32_t wide = any_edge<_CMP_EQ_OQ>(e0, e1, e2) & lanes;
  const uint32_t inside =
      ~(any_edge<_CMP_LT_OQ>(e0, e1, e2) & any_edge<_CMP_GT_OQ>(e0, e1, e2)) & lanes & ~wide;
  const __m256d det = _mm256_add_pd(_mm256_add_pd(e0, e1), e2);
  const uint32_t nonzero = uint32_t(_mm256_movemask_pd(_mm256_cmp_pd(det, zero, _CMP_NEQ_UQ)));
  const __m256d scaled = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(e0, _mm256_mul_pd(sz, az)),
                                                     _mm256_mul_pd(e1, _mm256_mul_pd(sz, bz))),
                                       _mm256_mul_pd(e2, _mm256_mul_pd(sz, cz)));
  const __m128 t =
      _mm256_cvtpd_ps(_mm256_add_pd(_mm256_set1_pd(ray.shift), _mm256_div_pd(scaled, det)));
  const uint32_t in_range =
      uint32_t(_mm_movemask_ps(_mm_and_ps(_mm_cmp_ps(t, _mm_set1_ps(ray.tmin), _CMP_GT_OQ),
                                          _mm_cmp_ps(t, _mm_set1_ps(tmax), _CMP_LE_OQ))));
  uint32_t hits = inside & nonzero & in_range;
  if (hits != 0) {
    _mm_storeu_ps(out.t, t);
    _mm_storeu_ps(out.u, _mm256_cvtpd_ps(_mm256_div_pd(e1, det)));
    _mm_storeu_ps(out.v, _mm256_cvtpd_ps(_mm256_div_pd(e2, det)));
  }
  if (wide != 0) hits |= test_lanes_scalar(leaf, first, wide, ray, tmax, out);
  return hits;
}

}  // namespace gs

#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
