// The box every structure (brute included) clips rays to, and the stopping rule every walk
// shares, so that every structure answers exactly what brute answers (docs/design.md §6).
#pragma once
#include <algorithm>
#include <bit>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/geometry/box_test.h"
#include "core/geometry/ray.h"
#include "core/scene/scene.h"

namespace gs {

// Clips [t0, t1] to the box lo..hi; false when nothing is left. A zero direction
// component constrains only through the origin.
bool clip_segment(const double origin[3], const double dir[3], const double lo[3],
                  const double hi[3], double& t0, double& t1);

// The scene box padded by kPadding of the largest coordinate magnitude. With the ray's
// origin moved to where it enters this box, the kernel's answers are off from exact
// geometry by a few double ulps of the scene's coordinates; `padding` covers that (and the
// double rounding of a walk's cell location for origins up to ~1e6 scene sizes away), so a
// hit the kernel reports lies inside the box and inside every cell a structure sorted the
// triangle into with that padding.
struct ClipBox {
  static constexpr double kPadding = 1e-9;
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  double magnitude = 0.0;  // largest |coordinate| of the scene box
  double padding = 0.0;    // kPadding * magnitude
  bool empty = true;

  // Cells narrower than this many float ulps of their own coordinates separate nothing,
  // and neither do cells only a few paddings wide (docs/design.md §1, degenerate input).
  static constexpr double kMinCellUlps = 256.0;
  static constexpr double kMinCellPaddings = 4.0;

  // The box rounded outward to float (lane 3 unused), and the largest origin coordinate
  // magnitude the float test below holds for (WalkLine::kNearRange times the magnitude):
  // for misses_surely.
  alignas(16) float lo_float[4] = {}, hi_float[4] = {};
  float near_range = 0.0f;
  // The box rounded inward to float, lane 3 zero: for starts_inside.
  alignas(16) float lo_inward[4] = {}, hi_inward[4] = {};

  ClipBox() = default;
  explicit ClipBox(const Box& scene);
  // The narrowest useful cell in the box lo..hi.
  double min_cell_width(const double lo[3], const double hi[3]) const;
  // The ray's [tmin, tmax] clipped to the box; false for a ray that misses it or is invalid.
  // `inv_dir` receives 1 / dir per axis (infinite for a zero component), for the caller's
  // walk and kernel. Most camera rays framing a scene from outside miss the box (72% of
  // lumpy's, 55% of the bunny's): a float test turns most of them away before the double
  // clip.
  // Per axis, the slab's entry and exit (lo - o) * (1 / d) and (hi - o) * (1 / d) in their
  // order; t0 is the largest of tmin and the entries, t1 the least of tmax and the exits. An
  // axis the ray is parallel to only excludes an origin outside its slab.
  bool clip(const Ray& ray, double& t0, double& t1, double inv_dir[3]) const;
  bool clip(const Ray& ray, double& t0, double& t1) const {
    double inv_dir[3];
    return clip(ray, t0, t1, inv_dir);
  }

  // Whether the clip returns false before its distances: an empty box, a ray the float test
  // turns away, an invalid ray.
  bool turns_away(const Ray& ray) const {
    return empty || misses_surely(ray) || !ray_is_valid(ray);
  }

  // Whether the ray starts inside the box at tmin = 0 (a shadow ray, a camera in a room):
  // clip's t0 is then tmin itself, bit for bit, and its t1 no smaller. Each axis's entry
  // distance, (lo - o) / d or (hi - o) / d, is at most 0 (a rounded difference keeps the exact
  // one's sign) and its exit distance at least 0, and max(±0, x <= 0) is the ±0. One test of
  // four lanes: the origin against the box rounded inward (a float inside it lies inside the
  // box), tmin in the fourth lane against 0.
  bool starts_inside(const Ray& ray) const {
    const __m128 start = _mm_loadu_ps(&ray.origin.x);  // x, y, z, tmin
    const __m128 inside = _mm_and_ps(_mm_cmple_ps(_mm_load_ps(lo_inward), start),
                                     _mm_cmple_ps(start, _mm_load_ps(hi_inward)));
    return !empty && _mm_movemask_ps(inside) == 15;
  }

  // True only when the ray's segment [tmin, tmax] misses the box, so that no structure can
  // report a hit on it (docs/design.md §6.2): RayBoxes' slab test (Ize's widened exits) with
  // the three axes in three lanes and tmin, tmax in the fourth, against the box rounded
  // outward to float, for rays from outside the box. About 45 instructions where the double
  // clip takes about 130. It holds
  // where the content boxes' test does: for origins within near_range (the kernel's line
  // follows the ray's own), and where no distance overflows or underflows (an infinite
  // entry or exit, and entry and exit within FLT_MIN, say nothing). A zero direction
  // component gives infinite or NaN distances: the ray is then not turned away, nor is an
  // invalid ray, which the clip turns away next.
  bool misses_surely(const Ray& ray) const {
    const __m128 origin = _mm_loadu_ps(&ray.origin.x);  // x, y, z, tmin
    const __m128 lo = _mm_load_ps(lo_float), hi = _mm_load_ps(hi_float);
    // A ray from inside the box (a shadow ray, a camera in a room) is let in at once.
    const __m128 inside = _mm_and_ps(_mm_cmple_ps(lo, origin), _mm_cmple_ps(origin, hi));
    if ((_mm_movemask_ps(inside) & 7) == 7) return false;
    const __m128 dir = _mm_loadu_ps(&ray.dir.x);  // x, y, z, tmax
    const __m128 inv_dir = _mm_div_ps(_mm_set1_ps(1.0f), dir);
    const __m128 t_lo = _mm_mul_ps(_mm_sub_ps(lo, origin), inv_dir);
    const __m128 t_hi = _mm_mul_ps(_mm_sub_ps(hi, origin), inv_dir);
    // minps / maxps give their second operand for a NaN: t_hi, infinite, then.
    const __m128 t_near = _mm_min_ps(t_lo, t_hi), exact_far = _mm_max_ps(t_lo, t_hi);
    const __m128 t_far = widened_exit(exact_far);
    // Lanes 0..2 the axes', lane 3 tmin (entry) and tmax (exit): (a0, a1, a2, b3).
    const auto axes_then = [](__m128 a, __m128 b) {
      return _mm_shuffle_ps(a, _mm_unpackhi_ps(a, b), _MM_SHUFFLE(3, 0, 1, 0));
    };
    __m128 entry = axes_then(t_near, origin), exit = axes_then(t_far, dir);
    entry = _mm_max_ps(entry, _mm_shuffle_ps(entry, entry, _MM_SHUFFLE(2, 3, 0, 1)));
    entry = _mm_max_ps(entry, _mm_shuffle_ps(entry, entry, _MM_SHUFFLE(1, 0, 3, 2)));
    exit = _mm_min_ps(exit, _mm_shuffle_ps(exit, exit, _MM_SHUFFLE(2, 3, 0, 1)));
    exit = _mm_min_ps(exit, _mm_shuffle_ps(exit, exit, _MM_SHUFFLE(1, 0, 3, 2)));
    const float t_entry = _mm_cvtss_f32(entry), t_exit = _mm_cvtss_f32(exit);
    if (!(t_entry > t_exit + FLT_MIN && t_entry < INFINITY && t_exit > -INFINITY)) return false;
    const __m128 near =
        _mm_cmple_ps(_mm_andnot_ps(_mm_set1_ps(-0.0f), origin), _mm_set1_ps(near_range));
    return (_mm_movemask_ps(near) & 7) == 7;
  }
};

// How far past the nearest hit a structure's walk must look before it may stop. The
// kernel's t is off from the exact crossing by a few double ulps of the distances involved
// (1e-9 of them is ample), so a hit may be reported slightly before the wall it lies behind.
// `inv_dir` as ClipBox::clip gives it: 1 / the longest direction component is the largest
// of its magnitudes, so no division is needed.
inline double walk_slack(const Ray& ray, double scene_magnitude, const double inv_dir[3]) {
  double largest = scene_magnitude, shortest_inverse = kInf;
  for (int a = 0; a < 3; ++a) {
    largest = std::max(largest, std::fabs(double(ray.origin[a])));
    shortest_inverse = std::min(shortest_inverse, std::fabs(inv_dir[a]));
  }
  return 1e-9 * largest * shortest_inverse;
}

// The line a structure walks: the one the kernel tests (PreparedRay moves the origin to
// where the ray enters the clip box, in double), with t measured from there: t' = t - shift.
// Walking the kernel's own line keeps every structure exact wherever the ray starts: for an
// origin far away the moved origin lies off the true line by far more than the padding, and
// a walk along the true line would miss hits the kernel reports (docs/design.md §6.2).
struct WalkLine {
  // Beyond this many times the scene's magnitude, the moved origin may lie off the true
  // line by more than a tenth of the padding (double rounding: ~1e-15 of the distance), so
  // tests made on the true line in float (content and node boxes) are not made at all.
  static constexpr double kNearRange = 1e4;
  double origin[3], dir[3], inv_dir[3];
  double shift;      // t_enter of ClipBox::clip: true t = t' + shift
  double t0, t1;     // the interval of t' the walk covers: inside the clip box, from tmin on
  double t_exit[3];  // where the line leaves the clip box's slab on each axis (inf: parallel)
  double slack;      // walk_slack
  bool far;          // the true origin lies beyond kNearRange times the scene's magnitude
  // The stop distance of stop_distance(tmax, slack), in t'.
  double stop(float tmax) const;
};
// False when the ray misses the clip box (or is invalid): then the kernel is never called.
bool start_walk(const ClipBox& box, const Ray& ray, WalkLine& line);

// The next float above x (toward +infinity); x itself for +infinity and NaN. What
// std::nextafter(x, +inf) gives, without the library call.
inline float next_float_up(float x) {
  if (!(x < std::numeric_limits<float>::infinity())) return x;
  if (x == 0.0f) return std::numeric_limits<float>::denorm_min();
  const uint32_t bits = std::bit_cast<uint32_t>(x);
  return std::bit_cast<float>(x > 0.0f ? bits + 1 : bits - 1);
}

// The next float below x (toward -infinity); x itself for -infinity and NaN.
inline float next_float_down(float x) { return -next_float_up(-x); }

// The nearest floats at or below / at or above x: a double box rounded outward to float
// still contains everything the double box did.
inline float float_down(double x) {
  const float f = float(x);
  return double(f) > x ? next_float_down(f) : f;
}
inline float float_up(double x) {
  const float f = float(x);
  return double(f) < x ? next_float_up(f) : f;
}

// The box of `count` triangles' padded boxes (`boxes`: lo.xyz, hi.xyz each, as BuildInput
// keeps them) within the cell lo..hi grown by `padding`, rounded outward to float: lo[3],
// hi[3]. A hit the kernel reports in the cell lies inside it with a margin of about
// `padding`, so a walk that finds the ray's segment in the cell off this box may skip the
// cell's tests (docs/design.md §6).
template <class BoxOf>
void content_box(uint32_t count, BoxOf&& box_of, const double lo[3], const double hi[3],
                 double padding, float out[6]) {
  double content[6] = {kInf, kInf, kInf, -kInf, -kInf, -kInf};
  for (uint32_t i = 0; i < count; ++i) {
    const auto box = box_of(i);
    for (int a = 0; a < 3; ++a)
      content[a] = std::min(content[a], box[a]),
      content[a + 3] = std::max(content[a + 3], box[a + 3]);
  }
  for (int a = 0; a < 3; ++a) {
    out[a] = float_down(std::max(content[a], lo[a] - padding));
    out[a + 3] = float_up(std::min(content[a + 3], hi[a] + padding));
  }
}

// A walk may stop once the current cell's (or node's) entry or exit lies beyond this: the
// nearest hit's t (or tmax) is rounded to float, so a triangle hit at the same float t —
// which wins if its id is lower — may cross the ray up to the next float beyond it.
inline double stop_distance(float tmax, double slack) {
  return double(next_float_up(tmax)) + slack;
}
// The same in a walk line's t (WalkLine::stop).
inline double walk_stop(float tmax, double slack, double shift) {
  return stop_distance(tmax, slack) - shift;
}
inline double WalkLine::stop(float tmax) const { return walk_stop(tmax, slack, shift); }

}  // namespace gs
