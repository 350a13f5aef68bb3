#include "core/geometry/clip_box.h"

#include <emmintrin.h>

#include <algorithm>
#include <cfloat>

namespace gs {

bool clip_segment(const double origin[3], const double dir[3], const double lo[3],
                  const double hi[3], double& t0, double& t1) {
  for (int a = 0; a < 3; ++a) {
    if (dir[a] == 0.0) {
      if (origin[a] < lo[a] || origin[a] > hi[a]) return false;
      continue;
    }
    double ta = (lo[a] - origin[a]) / dir[a], tb = (hi[a] - origin[a]) / dir[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta), t1 = std::min(t1, tb);
  }
  return t0 <= t1;
}

ClipBox::ClipBox(const Box& scene) : empty(scene.empty()) {
  if (empty) return;
  for (int a = 0; a < 3; ++a)
    magnitude =
        std::max({magnitude, std::fabs(double(scene.lo[a])), std::fabs(double(scene.hi[a]))});
  padding = kPadding * magnitude;
  for (int a = 0; a < 3; ++a) {
    lo[a] = scene.lo[a] - padding, hi[a] = scene.hi[a] + padding;
    lo_float[a] = float_down(lo[a]), hi_float[a] = float_up(hi[a]);
    lo_inward[a] = float_up(lo[a]), hi_inward[a] = float_down(hi[a]);
  }
  near_range = float_down(WalkLine::kNearRange * magnitude);
}

double ClipBox::min_cell_width(const double lo[3], const double hi[3]) const {
  double local_magnitude = 0.0;
  for (int a = 0; a < 3; ++a)
    local_magnitude = std::max({local_magnitude, std::fabs(lo[a]), std::fabs(hi[a])});
  return std::max(kMinCellUlps * FLT_EPSILON * local_magnitude, kMinCellPaddings * padding);
}

namespace {

// Three axes' doubles, two at a time (SSE2, so every x86-64 runs it): x and y in one
// register, z in the low lane of another, whose high lane no result uses. Each lane makes
// the scalar clip's operations on its axis, so the figures are the scalar ones bit for bit
// (ClipBoxTest.ClipAndWalkStartAreTheScalarClipBitForBit). start_walk was 16% of a camera
// ray's time on the F-15; the walks' single-ray traces take 1-6% less time with the axes in
// pairs than one at a time (README "Performance"), for about 1% more instructions.
struct AxisPairs {
  __m128d xy, z;
  void store(double out[3]) const { _mm_storeu_pd(out, xy), _mm_store_sd(out + 2, z); }
};

// A ray's origin, direction and 1 / direction in double (infinite for a zero component).
struct RayPairs {
  AxisPairs origin, dir, inv;
  explicit RayPairs(const Ray& ray) {
    const __m128 o = _mm_loadu_ps(&ray.origin.x), d = _mm_loadu_ps(&ray.dir.x);
    origin = {_mm_cvtps_pd(o), _mm_cvtps_pd(_mm_movehl_ps(o, o))};
    dir = {_mm_cvtps_pd(d), _mm_cvtps_pd(_mm_movehl_ps(d, d))};
    const __m128d one = _mm_set1_pd(1.0);
    inv = {_mm_div_pd(one, dir.xy), _mm_div_sd(one, dir.z)};
  }
};

// Where lines origin + t dir enter and leave the slabs lo..hi of the axes in `lanes` of one
// register: (lo - o) * inv and (hi - o) * inv in their order (minpd and maxpd, as the scalar
// clip's `if (ta > tb) swap`; the two never tie, a slab has width). An axis the line is
// parallel to gives -inf and +inf, which change no maximum of entries or minimum of exits,
// and `outside` when the origin lies outside its slab.
struct SlabPair {
  __m128d entry, exit;
  bool outside;
};
[[gnu::always_inline]] inline SlabPair slab_pair(__m128d o, __m128d d, __m128d inv, __m128d lo,
                                                 __m128d hi, int lanes) {
  const __m128d flat = _mm_cmpeq_pd(d, _mm_setzero_pd());
  const __m128d off = _mm_and_pd(flat, _mm_or_pd(_mm_cmplt_pd(o, lo), _mm_cmpgt_pd(o, hi)));
  const __m128d ta = _mm_mul_pd(_mm_sub_pd(lo, o), inv), tb = _mm_mul_pd(_mm_sub_pd(hi, o), inv);
  const auto or_flat = [&](__m128d value, double parallel) {
    return _mm_or_pd(_mm_and_pd(flat, _mm_set1_pd(parallel)), _mm_andnot_pd(flat, value));
  };
  return {or_flat(_mm_min_pd(tb, ta), -kInf), or_flat(_mm_max_pd(ta, tb), kInf),
          (_mm_movemask_pd(off) & lanes) != 0};
}

// The three axes' slabs (slab_pair), their exits in `exit`, and [t0, t1] clipped to them: t0
// raised to each entry and t1 lowered to each exit, x, y, then z, as std::max(t0, entry) and
// std::min(t1, exit) do (maxsd and minsd keep their second operand on a tie: the signs of
// zero come out the scalar clip's). False when the lines lie outside a slab they are
// parallel to, or nothing is left.
[[gnu::always_inline]] inline bool clip_to_slabs(const AxisPairs& origin, const AxisPairs& dir,
                                                 const AxisPairs& inv, const double lo[3],
                                                 const double hi[3], double& t0, double& t1,
                                                 AxisPairs& exit) {
  const SlabPair xy = slab_pair(origin.xy, dir.xy, inv.xy, _mm_loadu_pd(lo), _mm_loadu_pd(hi), 3);
  const SlabPair z = slab_pair(origin.z, dir.z, inv.z, _mm_load_sd(lo + 2), _mm_load_sd(hi + 2), 1);
  exit = {xy.exit, z.exit};
  if (xy.outside || z.outside) return false;
  __m128d start = _mm_set_sd(t0), end = _mm_set_sd(t1);
  start = _mm_max_sd(xy.entry, start), end = _mm_min_sd(xy.exit, end);
  start = _mm_max_sd(_mm_unpackhi_pd(xy.entry, xy.entry), start);
  end = _mm_min_sd(_mm_unpackhi_pd(xy.exit, xy.exit), end);
  start = _mm_max_sd(z.entry, start), end = _mm_min_sd(z.exit, end);
  t0 = _mm_cvtsd_f64(start), t1 = _mm_cvtsd_f64(end);
  return t0 <= t1;
}

// ClipBox::clip's distances for a ray it does not turn away.
[[gnu::always_inline]] inline bool clip_pairs(const ClipBox& box, const Ray& ray,
                                              const RayPairs& pairs, double& t0, double& t1) {
  t0 = ray.tmin, t1 = ray.tmax;
  AxisPairs exit;
  return clip_to_slabs(pairs.origin, pairs.dir, pairs.inv, box.lo, box.hi, t0, t1, exit);
}

}  // namespace

bool ClipBox::clip(const Ray& ray, double& t0, double& t1, double inv_dir[3]) const {
  if (turns_away(ray)) return false;
  const RayPairs pairs(ray);
  pairs.inv.store(inv_dir);
  return clip_pairs(*this, ray, pairs, t0, t1);
}

bool start_walk(const ClipBox& box, const Ray& ray, WalkLine& line) {
  // A ray from inside skips clip's distances (ClipBox::starts_inside): its walk's start then
  // waits for the divisions alone, not for the chain of clip's products and comparisons too.
  const bool inside = box.starts_inside(ray);
  if (inside ? !ray_is_valid(ray) : box.turns_away(ray)) return false;
  const RayPairs pairs(ray);
  double t_leave;
  if (inside)
    line.shift = ray.tmin;
  else if (!clip_pairs(box, ray, pairs, line.shift, t_leave))
    return false;
  pairs.inv.store(line.inv_dir);
  pairs.dir.store(line.dir);
  line.slack = walk_slack(ray, box.magnitude, line.inv_dir);
  // PreparedRay's origin, computed the same way.
  const __m128d shift = _mm_set1_pd(line.shift);
  const AxisPairs origin{_mm_add_pd(pairs.origin.xy, _mm_mul_pd(shift, pairs.dir.xy)),
                         _mm_add_pd(pairs.origin.z, _mm_mul_pd(shift, pairs.dir.z))};
  origin.store(line.origin);
  line.far = false;
  for (int a = 0; a < 3; ++a)
    line.far |= !(std::fabs(double(ray.origin[a])) <= WalkLine::kNearRange * box.magnitude);
  // The moved line's own interval in the box; the kernel accepts nothing before tmin.
  line.t0 = double(ray.tmin) - line.shift - line.slack, line.t1 = kInf;
  AxisPairs exit;
  const bool in_box =
      clip_to_slabs(origin, pairs.dir, pairs.inv, box.lo, box.hi, line.t0, line.t1, exit);
  exit.store(line.t_exit);
  return in_box;
}

bool ray_is_valid(const Ray& ray) {
  // A float is infinite or NaN exactly when its exponent bits are all ones, and zero when
  // all bits but the sign are clear: the six components tested at once, origin and
  // direction each in the first three lanes of one SSE2 register (the fourth holds tmin
  // or tmax, checked below).
  const __m128i origin = _mm_loadu_si128(reinterpret_cast<const __m128i*>(&ray.origin.x));
  const __m128i dir = _mm_loadu_si128(reinterpret_cast<const __m128i*>(&ray.dir.x));
  const __m128i exponent = _mm_set1_epi32(0x7f800000), magnitude = _mm_set1_epi32(0x7fffffff);
  const __m128i non_finite =
      _mm_or_si128(_mm_cmpeq_epi32(_mm_and_si128(origin, exponent), exponent),
                   _mm_cmpeq_epi32(_mm_and_si128(dir, exponent), exponent));
  if (_mm_movemask_ps(_mm_castsi128_ps(non_finite)) & 7) return false;
  const __m128i zero = _mm_cmpeq_epi32(_mm_and_si128(dir, magnitude), _mm_setzero_si128());
  if ((_mm_movemask_ps(_mm_castsi128_ps(zero)) & 7) == 7) return false;
  return ray.tmin <= ray.tmax;  // false for a NaN bound too
}

}  // namespace gs
