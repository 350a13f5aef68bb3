// The leaf kernel on 8 double lanes (AVX-512 F, VL, DQ): leaf_avx2.cpp's operations, twice
// as wide, with the same guarantee (each lane's t, u and v are the scalar kernel's bit for
// bit). Compiled for AVX-512 by the pragma below, after every include; called only when the
// CPU has it.
#include <immintrin.h>

#include "core/geometry/simd.h"

#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx512f,avx512vl,avx512dq"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx512f,avx512vl,avx512dq")
#endif

namespace gs {
namespace {

// The lanes where `Predicate` holds between some edge function and zero (a template
// argument: the compare takes an immediate).
template <int Predicate>
inline uint32_t any_edge(__m512d e0, __m512d e1, __m512d e2) {
  const __m512d zero = _mm512_setzero_pd();
  return uint32_t(_mm512_cmp_pd_mask(e0, zero, Predicate) |
                  _mm512_cmp_pd_mask(e1, zero, Predicate) |
                  _mm512_cmp_pd_mask(e2, zero, Predicate));
}

// All eight lanes to float. (The zero-masked form: GCC 12's plain _mm512_cvtpd_ps warns
// about its own undefined source operand.)
inline __m256 to_float(__m512d x) { return _mm512_maskz_cvtpd_ps(0xFF, x); }

}  // namespace

uint32_t test_lanes_avx512(const LeafView& leaf, uint32_t first, uint32_t lanes,
                           const PreparedRay<KernelReal>& ray, float tmax, LaneHits& out) {
  const auto mask = __mmask8(lanes);
  const auto load = [&](int corner, int axis) {
    return _mm512_maskz_cvtps_pd(
        mask, _mm256_maskz_loadu_ps(mask, leaf.corner(first, corner) + size_t(axis) * leaf.count));
  };
  const int kx = ray.kx, ky = ray.ky, kz = ray.kz;
  const __m512d ox = _mm512_set1_pd(ray.origin[kx]), oy = _mm512_set1_pd(ray.origin[ky]),
                oz = _mm512_set1_pd(ray.origin[kz]);
  const __m512d sx = _mm512_set1_pd(ray.sx), sy = _mm512_set1_pd(ray.sy),
                sz = _mm512_set1_pd(ray.sz);
  const __m512d az = _mm512_sub_pd(load(0, kz), oz), bz = _mm512_sub_pd(load(1, kz), oz),
                cz = _mm512_sub_pd(load(2, kz), oz);
  const __m512d ax = _mm512_sub_pd(_mm512_sub_pd(load(0, kx), ox), _mm512_mul_pd(sx, az));
  const __m512d ay = _mm512_sub_pd(_mm512_sub_pd(load(0, ky), oy), _mm512_mul_pd(sy, az));
  const __m512d bx = _mm512_sub_pd(_mm512_sub_pd(load(1, kx), ox), _mm512_mul_pd(sx, bz));
  const __m512d by = _mm512_sub_pd(_mm512_sub_pd(load(1, ky), oy), _mm512_mul_pd(sy, bz));
  const __m512d cx = _mm512_sub_pd(_mm512_sub_pd(load(2, kx), ox), _mm512_mul_pd(sx, cz));
  const __m512d cy = _mm512_sub_pd(_mm512_sub_pd(load(2, ky), oy), _mm512_mul_pd(sy, cz));
  const __m512d e0 = _mm512_sub_pd(_mm512_mul_pd(cx, by), _mm512_mul_pd(cy, bx));
  const __m512d e1 = _mm512_sub_pd(_mm512_mul_pd(ax, cy), _mm512_mul_pd(ay, cx));
  const __m512d e2 = _mm512_sub_pd(_mm512_mul_pd(bx, ay), _mm512_mul_pd(by, ax));

  const __m512d zero = _mm512_setzero_pd();
  // An edge function of exactly zero is redone in wider arithmetic: the scalar kernel's.
  const uint32_t wide = any_edge<_CMP_EQ_OQ>(e0, e1, e2) & lanes;
  const uint32_t inside =
      ~(any_edge<_CMP_LT_OQ>(e0, e1, e2) & any_edge<_CMP_GT_OQ>(e0, e1, e2)) & lanes & ~wide;
  const __m512d det = _mm512_add_pd(_mm512_add_pd(e0, e1), e2);
  const uint32_t nonzero = _mm512_cmp_pd_mask(det, zero, _CMP_NEQ_UQ);
  const __m512d scaled = _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(e0, _mm512_mul_pd(sz, az)),
                                                     _mm512_mul_pd(e1, _mm512_mul_pd(sz, bz))),
                                       _mm512_mul_pd(e2, _mm512_mul_pd(sz, cz)));
  const __m256 t = to_float(_mm512_add_pd(_mm512_set1_pd(ray.shift), _mm512_div_pd(scaled, det)));
  const uint32_t in_range = _mm256_cmp_ps_mask(t, _mm256_set1_ps(ray.tmin), _CMP_GT_OQ) &
                            _mm256_cmp_ps_mask(t, _mm256_set1_ps(tmax), _CMP_LE_OQ);
  uint32_t hits = inside & nonzero & in_range;
  if (hits != 0) {
    _mm256_storeu_ps(out.t, t);
    _mm256_storeu_ps(out.u, to_float(_mm512_div_pd(e1, det)));
    _mm256_storeu_ps(out.v, to_float(_mm512_div_pd(e2, det)));
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
