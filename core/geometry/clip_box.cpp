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

bool start_walk(const ClipBox& box, const Ray& ray, WalkLine& line) {
  // A ray from inside skips clip's distances (ClipBox::starts_inside): its walk's start then
  // waits for the divisions alone, not for the chain of clip's products and comparisons too.
  if (box.starts_inside(ray)) {
    if (!ray_is_valid(ray)) return false;
    for (int a = 0; a < 3; ++a) line.inv_dir[a] = 1.0 / double(ray.dir[a]);
    line.shift = ray.tmin;
  } else {
    double t_leave;
    if (!box.clip(ray, line.shift, t_leave, line.inv_dir)) return false;
  }
  line.slack = walk_slack(ray, box.magnitude, line.inv_dir);
  line.far = false;
  for (int a = 0; a < 3; ++a) {
    line.dir[a] = ray.dir[a];
    // PreparedRay's origin, computed the same way.
    line.origin[a] = double(ray.origin[a]) + line.shift * double(ray.dir[a]);
    line.far |= !(std::fabs(double(ray.origin[a])) <= WalkLine::kNearRange * box.magnitude);
  }
  // The moved line's own interval in the box; the kernel accepts nothing before tmin.
  line.t0 = double(ray.tmin) - line.shift - line.slack, line.t1 = kInf;
  for (int a = 0; a < 3; ++a) {
    line.t_exit[a] = kInf;
    if (line.dir[a] == 0.0) {
      if (line.origin[a] < box.lo[a] || line.origin[a] > box.hi[a]) return false;
      continue;
    }
    double ta = (box.lo[a] - line.origin[a]) * line.inv_dir[a];
    double tb = (box.hi[a] - line.origin[a]) * line.inv_dir[a];
    if (ta > tb) std::swap(ta, tb);
    line.t_exit[a] = tb;
    line.t0 = std::max(line.t0, ta), line.t1 = std::min(line.t1, tb);
  }
  return line.t0 <= line.t1;
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
