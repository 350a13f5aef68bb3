// The leaf kernel on 4 double lanes (AVX2). Each lane performs the scalar kernel's
// operations (core/geometry/kernel.h) in the same order, without fused multiply-adds, so its
// t, u and v are the scalar kernel's bit for bit (docs/design.md §6.6). Compiled for AVX2 by
// the pragma below, after every include, so that no inline function shared with other files
// is compiled for it; called only when the CPU has AVX2.
#include <immintrin.h>

#include <bit>

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

// One test per lane: corner k of the lane's triangle on the ray's axes kx, ky, kz
// (corner[k][0..2]) against the lane's ray (origin on those axes, shear, shift, t range).
struct Lanes {
  __m256d corner[3][3];
  __m256d origin[3], shear[3], shift;
  __m128 tmin, tmax;
};

// The scalar kernel's operations in every lane of `lanes`: returns the lanes hit (their t, u
// and v stored at t_out, u_out, v_out) and sets `wide` to the lanes whose edge functions rounded to
// zero, which the scalar kernel must redo in wider arithmetic.
[[gnu::always_inline]] inline uint32_t hit_lanes(const Lanes& l, uint32_t lanes, uint32_t& wide,
                                                 float* t_out, float* u_out, float* v_out) {
  const __m256d az = _mm256_sub_pd(l.corner[0][2], l.origin[2]);
  const __m256d bz = _mm256_sub_pd(l.corner[1][2], l.origin[2]);
  const __m256d cz = _mm256_sub_pd(l.corner[2][2], l.origin[2]);
  const auto sheared = [&](int k, int a, __m256d z) {
    return _mm256_sub_pd(_mm256_sub_pd(l.corner[k][a], l.origin[a]), _mm256_mul_pd(l.shear[a], z));
  };
  const __m256d ax = sheared(0, 0, az), ay = sheared(0, 1, az);
  const __m256d bx = sheared(1, 0, bz), by = sheared(1, 1, bz);
  const __m256d cx = sheared(2, 0, cz), cy = sheared(2, 1, cz);
  const __m256d e0 = _mm256_sub_pd(_mm256_mul_pd(cx, by), _mm256_mul_pd(cy, bx));
  const __m256d e1 = _mm256_sub_pd(_mm256_mul_pd(ax, cy), _mm256_mul_pd(ay, cx));
  const __m256d e2 = _mm256_sub_pd(_mm256_mul_pd(bx, ay), _mm256_mul_pd(by, ax));

  const __m256d zero = _mm256_setzero_pd();
  wide = any_edge<_CMP_EQ_OQ>(e0, e1, e2) & lanes;
  const uint32_t inside =
      ~(any_edge<_CMP_LT_OQ>(e0, e1, e2) & any_edge<_CMP_GT_OQ>(e0, e1, e2)) & lanes & ~wide;
  const __m256d det = _mm256_add_pd(_mm256_add_pd(e0, e1), e2);
  const uint32_t nonzero = uint32_t(_mm256_movemask_pd(_mm256_cmp_pd(det, zero, _CMP_NEQ_UQ)));
  const __m256d sz = l.shear[2];
  const __m256d scaled = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(e0, _mm256_mul_pd(sz, az)),
                                                     _mm256_mul_pd(e1, _mm256_mul_pd(sz, bz))),
                                       _mm256_mul_pd(e2, _mm256_mul_pd(sz, cz)));
  const __m128 t = _mm256_cvtpd_ps(_mm256_add_pd(l.shift, _mm256_div_pd(scaled, det)));
  const uint32_t in_range = uint32_t(_mm_movemask_ps(
      _mm_and_ps(_mm_cmp_ps(t, l.tmin, _CMP_GT_OQ), _mm_cmp_ps(t, l.tmax, _CMP_LE_OQ))));
  const uint32_t hits = inside & nonzero & in_range;
  if (hits != 0) {
    _mm_storeu_ps(t_out, t);
    _mm_storeu_ps(u_out, _mm256_cvtpd_ps(_mm256_div_pd(e1, det)));
    _mm_storeu_ps(v_out, _mm256_cvtpd_ps(_mm256_div_pd(e2, det)));
  }
  return hits;
}

// widened_exit (box_test.h) on eight lanes.
inline __m256 widened_exit8(__m256 exact_far) {
  return _mm256_max_ps(_mm256_mul_ps(exact_far, _mm256_set1_ps(kExitGrowth)),
                       _mm256_mul_ps(exact_far, _mm256_set1_ps(kExitShrink)));
}

}  // namespace

uint32_t test_lanes_avx2(const LeafView& leaf, uint32_t first, uint32_t lanes,
                         const PreparedRay<KernelReal>& ray, float tmax, LaneHits& out) {
  const __m128i mask = _mm_cmpgt_epi32(
      _mm_and_si128(_mm_set1_epi32(int(lanes)), _mm_setr_epi32(1, 2, 4, 8)), _mm_setzero_si128());
  const int axes[3] = {ray.kx, ray.ky, ray.kz};
  Lanes l;
  for (int k = 0; k < 3; ++k)
    for (int a = 0; a < 3; ++a)
      l.corner[k][a] = coordinate(leaf.corner(first, k) + size_t(axes[a]) * leaf.count, mask);
  for (int a = 0; a < 3; ++a) l.origin[a] = _mm256_set1_pd(ray.origin[axes[a]]);
  l.shear[0] = _mm256_set1_pd(ray.sx), l.shear[1] = _mm256_set1_pd(ray.sy);
  l.shear[2] = _mm256_set1_pd(ray.sz);
  l.shift = _mm256_set1_pd(ray.shift);
  l.tmin = _mm_set1_ps(ray.tmin), l.tmax = _mm_set1_ps(tmax);
  uint32_t wide = 0;
  uint32_t hits = hit_lanes(l, lanes, wide, out.t, out.u, out.v);
  if (wide != 0) hits |= test_lanes_scalar(leaf, first, wide, ray, tmax, out);
  return hits;
}

uint64_t test_rays_avx2(const LeafView& leaf, uint32_t tri, const RayLanes& rays, uint64_t lanes,
                        RayHits& out) {
  const int axes[3] = {rays.kx, rays.ky, rays.kz};
  Lanes l;
  for (int k = 0; k < 3; ++k)
    for (int a = 0; a < 3; ++a)
      l.corner[k][a] = _mm256_set1_pd(double(leaf.corner(tri, k)[size_t(axes[a]) * leaf.count]));
  uint64_t hits = 0, wide_lanes = 0;
  for (; lanes != 0; lanes &= ~(uint64_t{15} << 4 * (std::countr_zero(lanes) / 4))) {
    const uint32_t first = uint32_t(std::countr_zero(lanes)) & ~3u;
    const uint32_t group = uint32_t(lanes >> first) & 15u;
    l.origin[0] = _mm256_loadu_pd(rays.ox + first), l.origin[1] = _mm256_loadu_pd(rays.oy + first);
    l.origin[2] = _mm256_loadu_pd(rays.oz + first);
    l.shear[0] = _mm256_loadu_pd(rays.sx + first), l.shear[1] = _mm256_loadu_pd(rays.sy + first);
    l.shear[2] = _mm256_loadu_pd(rays.sz + first);
    l.shift = _mm256_loadu_pd(rays.shift + first);
    l.tmin = _mm_loadu_ps(rays.tmin + first), l.tmax = _mm_loadu_ps(rays.tmax + first);
    uint32_t wide = 0;
    hits |= uint64_t(hit_lanes(l, group, wide, out.t + first, out.u + first, out.v + first))
            << first;
    wide_lanes |= uint64_t(wide) << first;
  }
  if (wide_lanes != 0) hits |= test_rays_scalar(leaf, tri, rays, wide_lanes, out);
  return hits;
}

uint64_t rays_crossed_avx2(const RayBoxLanes& lanes, const float* boxes, uint32_t stride,
                           uint32_t first, uint64_t which, uint64_t rays, uint64_t* crossing) {
  // slab_test4's operations, eight rays at a time.
  for (uint64_t boxes_left = which; boxes_left != 0; boxes_left &= boxes_left - 1)
    crossing[std::countr_zero(boxes_left)] = 0;
  for (uint64_t left = rays; left != 0;) {
    const uint32_t group = uint32_t(std::countr_zero(left)) & ~7u;
    const __m256 t0 = _mm256_load_ps(lanes.t0 + group), t1 = _mm256_load_ps(lanes.t1 + group);
    __m256 origin[3], inv_dir[3];
    for (int a = 0; a < 3; ++a)
      origin[a] = _mm256_load_ps(lanes.origin[a] + group),
      inv_dir[a] = _mm256_load_ps(lanes.inv_dir[a] + group);
    for (uint64_t boxes_left = which; boxes_left != 0; boxes_left &= boxes_left - 1) {
      const auto k = uint32_t(std::countr_zero(boxes_left));
      __m256 entry = t0, least_far = _mm256_set1_ps(INFINITY);
      for (int a = 0; a < 3; ++a) {
        const __m256 near_face = _mm256_set1_ps(boxes[lanes.near_array[a] * stride + first + k]);
        const __m256 far_face = _mm256_set1_ps(boxes[lanes.far_array[a] * stride + first + k]);
        const __m256 t_near = _mm256_mul_ps(_mm256_sub_ps(near_face, origin[a]), inv_dir[a]);
        const __m256 exact_far = _mm256_mul_ps(_mm256_sub_ps(far_face, origin[a]), inv_dir[a]);
        entry = _mm256_max_ps(t_near, entry);
        least_far = _mm256_min_ps(exact_far, least_far);
      }
      const __m256 exit = _mm256_min_ps(widened_exit8(least_far), t1);
      crossing[k] |= uint64_t(uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(entry, exit, _CMP_LE_OQ))))
                     << group;
    }
    left &= ~(uint64_t{255} << group);
  }
  return boxes_with_crossers(which, rays, crossing);
}

uint64_t boxes_crossed_avx2(const RayBoxes& ray, const float* boxes, uint32_t stride,
                            uint32_t first, uint32_t count, __m128 t0, __m128 t1) {
  // slab_test4's operations, eight boxes at a time; the last eight read only boxes below
  // `count` (masked loads: the block may end at the end of its storage).
  __m256 origin[3], inv_dir[3];
  for (int a = 0; a < 3; ++a)
    origin[a] = _mm256_set1_ps(_mm_cvtss_f32(ray.origin[a])),
    inv_dir[a] = _mm256_set1_ps(_mm_cvtss_f32(ray.inv_dir[a]));
  const __m256 start = _mm256_set1_ps(_mm_cvtss_f32(t0)), end = _mm256_set1_ps(_mm_cvtss_f32(t1));
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  uint64_t met = 0;
  for (uint32_t k = 0; k < count; k += 8) {
    const __m256i load = _mm256_cmpgt_epi32(_mm256_set1_epi32(int(count - k)), lane);
    __m256 entry = start, least_far = _mm256_set1_ps(INFINITY);
    for (int a = 0; a < 3; ++a) {
      const __m256 near_face =
          _mm256_maskload_ps(boxes + ray.near_array[a] * stride + first + k, load);
      const __m256 far_face =
          _mm256_maskload_ps(boxes + ray.far_array[a] * stride + first + k, load);
      const __m256 t_near = _mm256_mul_ps(_mm256_sub_ps(near_face, origin[a]), inv_dir[a]);
      const __m256 exact_far = _mm256_mul_ps(_mm256_sub_ps(far_face, origin[a]), inv_dir[a]);
      entry = _mm256_max_ps(t_near, entry);
      least_far = _mm256_min_ps(exact_far, least_far);
    }
    const __m256 exit = _mm256_min_ps(widened_exit8(least_far), end);
    met |= uint64_t(uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(entry, exit, _CMP_LE_OQ)))) << k;
  }
  return count == 64 ? met : met & ((uint64_t{1} << count) - 1);
}

uint64_t bounds_crossed_avx2(const RayBoxLanes& lanes, const float* boxes, uint32_t stride,
                             uint32_t first, uint32_t count) {
  // RayBoxBounds::may_cross4's operations, eight boxes at a time; masked loads as in
  // boxes_crossed_avx2.
  const RayBoxBounds& bounds = lanes.bounds;
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  uint64_t met = 0;
  for (uint32_t k = 0; k < count; k += 8) {
    const __m256i load = _mm256_cmpgt_epi32(_mm256_set1_epi32(int(count - k)), lane);
    __m256 entry = _mm256_set1_ps(_mm_cvtss_f32(bounds.t0_lo)),
           greatest_far = _mm256_set1_ps(INFINITY);
    for (int a = 0; a < 3; ++a) {
      if (!(bounds.axes >> a & 1)) continue;
      const __m256 near_gap =
          _mm256_sub_ps(_mm256_maskload_ps(boxes + lanes.near_array[a] * stride + first + k, load),
                        _mm256_set1_ps(_mm_cvtss_f32(bounds.near_origin[a])));
      const __m256 far_gap =
          _mm256_sub_ps(_mm256_maskload_ps(boxes + lanes.far_array[a] * stride + first + k, load),
                        _mm256_set1_ps(_mm_cvtss_f32(bounds.far_origin[a])));
      const __m256 inv_lo = _mm256_set1_ps(_mm_cvtss_f32(bounds.inv_lo[a])),
                   inv_hi = _mm256_set1_ps(_mm_cvtss_f32(bounds.inv_hi[a]));
      const __m256 least_near =
          _mm256_min_ps(_mm256_mul_ps(near_gap, inv_lo), _mm256_mul_ps(near_gap, inv_hi));
      const __m256 exact_far =
          _mm256_max_ps(_mm256_mul_ps(far_gap, inv_lo), _mm256_mul_ps(far_gap, inv_hi));
      entry = _mm256_max_ps(least_near, entry);
      greatest_far = _mm256_min_ps(exact_far, greatest_far);
    }
    const __m256 exit =
        _mm256_min_ps(widened_exit8(greatest_far), _mm256_set1_ps(_mm_cvtss_f32(bounds.t1_hi)));
    met |= uint64_t(uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(entry, exit, _CMP_NGT_UQ)))) << k;
  }
  return count == 64 ? met : met & ((uint64_t{1} << count) - 1);
}

}  // namespace gs

#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
