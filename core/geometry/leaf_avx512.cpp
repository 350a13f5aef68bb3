// The leaf kernel on 8 double lanes (AVX-512 F, VL, DQ): leaf_avx2.cpp's operations, twice
// as wide, with the same guarantee (each lane's t, u and v are the scalar kernel's bit for
// bit). Compiled for AVX-512 by the pragma below, after every include; called only when the
// CPU has it.
#include <immintrin.h>

#include <bit>

#include "core/geometry/simd.h"

#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx512f,avx512vl,avx512dq"))), \
                             apply_to = function)
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

// One test per lane, as in leaf_avx2.cpp: corner k of the lane's triangle on the ray's axes
// kx, ky, kz against the lane's ray.
struct Lanes {
  __m512d corner[3][3];
  __m512d origin[3], shear[3], shift;
  __m256 tmin, tmax;
};

// The scalar kernel's operations in every lane of `lanes`: the lanes hit (t, u and v stored
// at t_out, u_out, v_out), and in `wide` the lanes whose edge functions rounded to zero.
[[gnu::always_inline]] inline uint32_t hit_lanes(const Lanes& l, uint32_t lanes, uint32_t& wide,
                                                 float* t_out, float* u_out, float* v_out) {
  const __m512d az = _mm512_sub_pd(l.corner[0][2], l.origin[2]);
  const __m512d bz = _mm512_sub_pd(l.corner[1][2], l.origin[2]);
  const __m512d cz = _mm512_sub_pd(l.corner[2][2], l.origin[2]);
  const auto sheared = [&](int k, int a, __m512d z) {
    return _mm512_sub_pd(_mm512_sub_pd(l.corner[k][a], l.origin[a]), _mm512_mul_pd(l.shear[a], z));
  };
  const __m512d ax = sheared(0, 0, az), ay = sheared(0, 1, az);
  const __m512d bx = sheared(1, 0, bz), by = sheared(1, 1, bz);
  const __m512d cx = sheared(2, 0, cz), cy = sheared(2, 1, cz);
  const __m512d e0 = _mm512_sub_pd(_mm512_mul_pd(cx, by), _mm512_mul_pd(cy, bx));
  const __m512d e1 = _mm512_sub_pd(_mm512_mul_pd(ax, cy), _mm512_mul_pd(ay, cx));
  const __m512d e2 = _mm512_sub_pd(_mm512_mul_pd(bx, ay), _mm512_mul_pd(by, ax));

  const __m512d zero = _mm512_setzero_pd();
  wide = any_edge<_CMP_EQ_OQ>(e0, e1, e2) & lanes;
  const uint32_t inside =
      ~(any_edge<_CMP_LT_OQ>(e0, e1, e2) & any_edge<_CMP_GT_OQ>(e0, e1, e2)) & lanes & ~wide;
  const __m512d det = _mm512_add_pd(_mm512_add_pd(e0, e1), e2);
  const uint32_t nonzero = _mm512_cmp_pd_mask(det, zero, _CMP_NEQ_UQ);
  const __m512d sz = l.shear[2];
  const __m512d scaled = _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(e0, _mm512_mul_pd(sz, az)),
                                                     _mm512_mul_pd(e1, _mm512_mul_pd(sz, bz))),
                                       _mm512_mul_pd(e2, _mm512_mul_pd(sz, cz)));
  const __m256 t = to_float(_mm512_add_pd(l.shift, _mm512_div_pd(scaled, det)));
  const uint32_t in_range =
      _mm256_cmp_ps_mask(t, l.tmin, _CMP_GT_OQ) & _mm256_cmp_ps_mask(t, l.tmax, _CMP_LE_OQ);
  const uint32_t hits = inside & nonzero & in_range;
  if (hits != 0) {
    _mm256_storeu_ps(t_out, t);
    _mm256_storeu_ps(u_out, to_float(_mm512_div_pd(e1, det)));
    _mm256_storeu_ps(v_out, to_float(_mm512_div_pd(e2, det)));
  }
  return hits;
}

// widened_exit (box_test.h) on sixteen lanes. Merge-masked with every lane on: GCC 12's
// _mm512_max_ps / _mm512_min_ps start from an undefined register and warn
// (maybe-uninitialized); the operation is the same.
inline __m512 widened_exit16(__m512 exact_far) {
  return _mm512_mask_max_ps(exact_far, 0xFFFF,
                            _mm512_mul_ps(exact_far, _mm512_set1_ps(kExitGrowth)),
                            _mm512_mul_ps(exact_far, _mm512_set1_ps(kExitShrink)));
}

}  // namespace

uint32_t test_lanes_avx512(const LeafView& leaf, uint32_t first, uint32_t lanes,
                           const PreparedRay<KernelReal>& ray, float tmax, LaneHits& out) {
  const auto mask = __mmask8(lanes);
  const int axes[3] = {ray.kx, ray.ky, ray.kz};
  Lanes l;
  for (int k = 0; k < 3; ++k)
    for (int a = 0; a < 3; ++a)
      l.corner[k][a] = _mm512_maskz_cvtps_pd(
          mask, _mm256_maskz_loadu_ps(mask, leaf.corner(first, k) + size_t(axes[a]) * leaf.count));
  for (int a = 0; a < 3; ++a) l.origin[a] = _mm512_set1_pd(ray.origin[axes[a]]);
  l.shear[0] = _mm512_set1_pd(ray.sx), l.shear[1] = _mm512_set1_pd(ray.sy);
  l.shear[2] = _mm512_set1_pd(ray.sz);
  l.shift = _mm512_set1_pd(ray.shift);
  l.tmin = _mm256_set1_ps(ray.tmin), l.tmax = _mm256_set1_ps(tmax);
  uint32_t wide = 0;
  uint32_t hits = hit_lanes(l, lanes, wide, out.t, out.u, out.v);
  if (wide != 0) hits |= test_lanes_scalar(leaf, first, wide, ray, tmax, out);
  return hits;
}

uint64_t test_rays_avx512(const LeafView& leaf, uint32_t tri, const RayLanes& rays, uint64_t lanes,
                          RayHits& out) {
  const int axes[3] = {rays.kx, rays.ky, rays.kz};
  Lanes l;
  for (int k = 0; k < 3; ++k)
    for (int a = 0; a < 3; ++a)
      l.corner[k][a] = _mm512_set1_pd(double(leaf.corner(tri, k)[size_t(axes[a]) * leaf.count]));
  uint64_t hits = 0, wide_lanes = 0;
  for (; lanes != 0; lanes &= ~(uint64_t{255} << 8 * (std::countr_zero(lanes) / 8))) {
    const uint32_t first = uint32_t(std::countr_zero(lanes)) & ~7u;
    const uint32_t group = uint32_t(lanes >> first) & 255u;
    l.origin[0] = _mm512_loadu_pd(rays.ox + first), l.origin[1] = _mm512_loadu_pd(rays.oy + first);
    l.origin[2] = _mm512_loadu_pd(rays.oz + first);
    l.shear[0] = _mm512_loadu_pd(rays.sx + first), l.shear[1] = _mm512_loadu_pd(rays.sy + first);
    l.shear[2] = _mm512_loadu_pd(rays.sz + first);
    l.shift = _mm512_loadu_pd(rays.shift + first);
    l.tmin = _mm256_loadu_ps(rays.tmin + first), l.tmax = _mm256_loadu_ps(rays.tmax + first);
    uint32_t wide = 0;
    hits |= uint64_t(hit_lanes(l, group, wide, out.t + first, out.u + first, out.v + first))
            << first;
    wide_lanes |= uint64_t(wide) << first;
  }
  if (wide_lanes != 0) hits |= test_rays_scalar(leaf, tri, rays, wide_lanes, out);
  return hits;
}

uint64_t rays_crossed_avx512(const RayBoxLanes& lanes, const float* boxes, uint32_t stride,
                             uint32_t first, uint64_t which, uint64_t rays, uint64_t* crossing) {
  // slab_test4's operations, sixteen rays at a time.
  for (uint64_t boxes_left = which; boxes_left != 0; boxes_left &= boxes_left - 1)
    crossing[std::countr_zero(boxes_left)] = 0;
  for (uint64_t left = rays; left != 0;) {
    const uint32_t group = uint32_t(std::countr_zero(left)) & ~15u;
    const __m512 t0 = _mm512_load_ps(lanes.t0 + group), t1 = _mm512_load_ps(lanes.t1 + group);
    __m512 origin[3], inv_dir[3];
    for (int a = 0; a < 3; ++a)
      origin[a] = _mm512_load_ps(lanes.origin[a] + group),
      inv_dir[a] = _mm512_load_ps(lanes.inv_dir[a] + group);
    for (uint64_t boxes_left = which; boxes_left != 0; boxes_left &= boxes_left - 1) {
      const auto k = uint32_t(std::countr_zero(boxes_left));
      __m512 entry = t0, least_far = _mm512_set1_ps(INFINITY);
      for (int a = 0; a < 3; ++a) {
        const __m512 near_face = _mm512_set1_ps(boxes[lanes.near_array[a] * stride + first + k]);
        const __m512 far_face = _mm512_set1_ps(boxes[lanes.far_array[a] * stride + first + k]);
        const __m512 t_near = _mm512_mul_ps(_mm512_sub_ps(near_face, origin[a]), inv_dir[a]);
        const __m512 exact_far = _mm512_mul_ps(_mm512_sub_ps(far_face, origin[a]), inv_dir[a]);
        // Merge-masked with every lane on, as in widened_exit16.
        entry = _mm512_mask_max_ps(entry, 0xFFFF, t_near, entry);
        least_far = _mm512_mask_min_ps(least_far, 0xFFFF, exact_far, least_far);
      }
      const __m512 exit = _mm512_mask_min_ps(t1, 0xFFFF, widened_exit16(least_far), t1);
      crossing[k] |= uint64_t(_mm512_cmp_ps_mask(entry, exit, _CMP_LE_OQ)) << group;
    }
    left &= ~(uint64_t{0xFFFF} << group);
  }
  return boxes_with_crossers(which, rays, crossing);
}

uint64_t boxes_crossed_avx512(const RayBoxes& ray, const float* boxes, uint32_t stride,
                              uint32_t first, uint32_t count, __m128 t0, __m128 t1) {
  // slab_test4's operations, sixteen boxes at a time; masked loads read only boxes below
  // `count` (the block may end at the end of its storage).
  __m512 origin[3], inv_dir[3];
  for (int a = 0; a < 3; ++a)
    origin[a] = _mm512_set1_ps(_mm_cvtss_f32(ray.origin[a])),
    inv_dir[a] = _mm512_set1_ps(_mm_cvtss_f32(ray.inv_dir[a]));
  const __m512 start = _mm512_set1_ps(_mm_cvtss_f32(t0)), end = _mm512_set1_ps(_mm_cvtss_f32(t1));
  uint64_t met = 0;
  for (uint32_t k = 0; k < count; k += 16) {
    const __mmask16 load = count - k >= 16 ? __mmask16(0xFFFF) : __mmask16((1u << (count - k)) - 1);
    __m512 entry = start, least_far = _mm512_set1_ps(INFINITY);
    for (int a = 0; a < 3; ++a) {
      const __m512 near_face =
          _mm512_maskz_loadu_ps(load, boxes + ray.near_array[a] * stride + first + k);
      const __m512 far_face =
          _mm512_maskz_loadu_ps(load, boxes + ray.far_array[a] * stride + first + k);
      const __m512 t_near = _mm512_mul_ps(_mm512_sub_ps(near_face, origin[a]), inv_dir[a]);
      const __m512 exact_far = _mm512_mul_ps(_mm512_sub_ps(far_face, origin[a]), inv_dir[a]);
      // Merge-masked with every lane on, as in widened_exit16.
      entry = _mm512_mask_max_ps(entry, 0xFFFF, t_near, entry);
      least_far = _mm512_mask_min_ps(least_far, 0xFFFF, exact_far, least_far);
    }
    const __m512 exit = _mm512_mask_min_ps(end, 0xFFFF, widened_exit16(least_far), end);
    met |= uint64_t(_mm512_mask_cmp_ps_mask(load, entry, exit, _CMP_LE_OQ)) << k;
  }
  return met;
}

uint64_t bounds_crossed_avx512(const RayBoxLanes& lanes, const float* boxes, uint32_t stride,
                               uint32_t first, uint32_t count) {
  // RayBoxBounds::may_cross4's operations, sixteen boxes at a time; masked loads as in
  // boxes_crossed_avx512.
  const RayBoxBounds& bounds = lanes.bounds;
  uint64_t met = 0;
  for (uint32_t k = 0; k < count; k += 16) {
    const __mmask16 load = count - k >= 16 ? __mmask16(0xFFFF) : __mmask16((1u << (count - k)) - 1);
    __m512 entry = _mm512_set1_ps(_mm_cvtss_f32(bounds.t0_lo)),
           greatest_far = _mm512_set1_ps(INFINITY);
    for (int a = 0; a < 3; ++a) {
      if (!(bounds.axes >> a & 1)) continue;
      const __m512 near_gap = _mm512_sub_ps(
          _mm512_maskz_loadu_ps(load, boxes + lanes.near_array[a] * stride + first + k),
          _mm512_set1_ps(_mm_cvtss_f32(bounds.near_origin[a])));
      const __m512 far_gap = _mm512_sub_ps(
          _mm512_maskz_loadu_ps(load, boxes + lanes.far_array[a] * stride + first + k),
          _mm512_set1_ps(_mm_cvtss_f32(bounds.far_origin[a])));
      const __m512 inv_lo = _mm512_set1_ps(_mm_cvtss_f32(bounds.inv_lo[a])),
                   inv_hi = _mm512_set1_ps(_mm_cvtss_f32(bounds.inv_hi[a]));
      // Merge-masked with every lane on, as in widened_exit16.
      const __m512 least_near = _mm512_mask_min_ps(
          near_gap, 0xFFFF, _mm512_mul_ps(near_gap, inv_lo), _mm512_mul_ps(near_gap, inv_hi));
      const __m512 exact_far = _mm512_mask_max_ps(far_gap, 0xFFFF, _mm512_mul_ps(far_gap, inv_lo),
                                                  _mm512_mul_ps(far_gap, inv_hi));
      entry = _mm512_mask_max_ps(entry, 0xFFFF, least_near, entry);
      greatest_far = _mm512_mask_min_ps(greatest_far, 0xFFFF, exact_far, greatest_far);
    }
    const __m512 end = _mm512_set1_ps(_mm_cvtss_f32(bounds.t1_hi));
    const __m512 exit = _mm512_mask_min_ps(end, 0xFFFF, widened_exit16(greatest_far), end);
    met |= uint64_t(_mm512_mask_cmp_ps_mask(load, entry, exit, _CMP_NGT_UQ)) << k;
  }
  return met;
}

}  // namespace gs

#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
