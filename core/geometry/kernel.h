// The watertight ray/triangle test of Woop, Benthin and Wald, "Watertight Ray/Triangle
// Intersection", JCGT 2(1), 2013. One kernel serves brute and every structure, so that
// structures can be compared with brute exactly. It reads float data (scenes and rays are
// float) and computes in double (KernelReal): on x86-64 scalar double costs the same as
// float here (measured: 2% on grid1d), and its rounding, a few ulps of double, lets a
// structure pad cells by 1e-9 of the scene's size instead of 1e-6, which is what allows
// fine cells around a small cluster in large extents. The long double instantiation
// checks it.
//
// Why watertight: the ray is sheared so that it runs along +z through the origin, and each
// edge is classified by a 2D edge function that two triangles sharing the edge evaluate
// bit-identically (negated). A ray through a shared edge or vertex therefore hits at least
// one of the triangles. Edge functions that round to exactly zero are redone in the next
// wider type, as the paper prescribes.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <limits>
#include <vector>

#include "core/geometry/ray.h"
#include "core/scene/scene.h"

namespace gs {

struct TriangleVerts {
  glm::vec3 v0, v1, v2;
};

// Triangle corners in id order, the layout the kernel reads.
std::vector<TriangleVerts> gather_triangles(const Scene& scene);

template <class Real>
struct WiderType;
template <>
struct WiderType<float> {
  using type = double;
};
template <>
struct WiderType<double> {
  using type = long double;
};
template <>
struct WiderType<long double> {
  using type = long double;
};

// The arithmetic of the kernel every structure uses.
using KernelReal = double;

// Clips [t0, t1] to the box lo..hi; false when nothing is left. A zero direction
// component constrains only through the origin.
bool clip_segment(const double origin[3], const double dir[3], const double lo[3],
                  const double hi[3], double& t0, double& t1);

// The box every structure (brute included) clips rays to before testing triangles: the
// scene box padded by kPadding of the largest coordinate magnitude. With the ray's origin
// moved to where it enters this box, the kernel's answers are off from exact geometry by a
// few double ulps of the scene's coordinates; `padding` covers that (and the double
// rounding of a walk's cell location for origins up to ~1e6 scene sizes away), so a hit the
// kernel reports lies inside the box and inside every cell a structure sorted the
// triangle into with that padding.
struct ClipBox {
  static constexpr double kPadding = 1e-9;
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  double magnitude = 0.0;  // largest |coordinate| of the scene box
  double padding = 0.0;    // kPadding * magnitude
  bool empty = true;

  // Cells narrower than this many float ulps of their own coordinates separate nothing,
  // and neither do cells only a few paddings wide (DESIGN.md §1, degenerate input).
  static constexpr double kMinCellUlps = 256.0;
  static constexpr double kMinCellPaddings = 4.0;

  ClipBox() = default;
  explicit ClipBox(const Box& scene);
  // The narrowest useful cell in the box lo..hi.
  double min_cell_width(const double lo[3], const double hi[3]) const;
  // Every triangle's box (lo.xyz, hi.xyz; 6 doubles each) padded by `padding`: sorting by
  // them puts a triangle in every cell where the kernel could report it hit.
  std::vector<double> padded_boxes(const std::vector<TriangleVerts>& triangles) const;
  // The ray's [tmin, tmax] clipped to the box; false for a ray that misses it or is invalid.
  // `inv_dir` receives 1 / dir per axis (infinite for a zero component), for the caller's
  // walk.
  bool clip(const Ray& ray, double& t0, double& t1, double inv_dir[3]) const {
    if (empty || !ray_is_valid(ray)) return false;
    const float* origin = &ray.origin.x;
    const float* dir = &ray.dir.x;
    t0 = ray.tmin, t1 = ray.tmax;
    for (int a = 0; a < 3; ++a) {
      inv_dir[a] = 1.0 / double(dir[a]);
      if (dir[a] == 0.0f) {
        if (origin[a] < lo[a] || origin[a] > hi[a]) return false;
        continue;
      }
      const double inv = inv_dir[a];
      double ta = (lo[a] - origin[a]) * inv, tb = (hi[a] - origin[a]) * inv;
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta), t1 = std::min(t1, tb);
    }
    return t0 <= t1;
  }
  bool clip(const Ray& ray, double& t0, double& t1) const {
    double inv_dir[3];
    return clip(ray, t0, t1, inv_dir);
  }
};

// How far past the nearest hit a structure's walk must look before it may stop. The
// kernel's t is off from the exact crossing by a few double ulps of the distances involved
// (1e-9 of them is ample), so a hit may be reported slightly before the wall it lies behind.
inline double walk_slack(const Ray& ray, double scene_magnitude) {
  double largest = scene_magnitude, longest = 0.0;
  for (int a = 0; a < 3; ++a) {
    largest = std::max(largest, std::fabs(double(ray.origin[a])));
    longest = std::max(longest, std::fabs(double(ray.dir[a])));
  }
  return 1e-9 * largest / longest;
}
// A walk may stop once the current cell's (or node's) entry or exit lies beyond this: the
// nearest hit's t (or tmax) is rounded to float, so a triangle hit at the same float t —
// which wins if its id is lower — may cross the ray up to the next float beyond it.
inline double stop_distance(float tmax, double slack) {
  return double(std::nextafter(tmax, std::numeric_limits<float>::infinity())) + slack;
}

// The per-ray part of the test: axis permutation and shear (section 3 of the paper). The
// origin is first moved along the ray to where it enters the clip box (`shift`), so that
// the kernel's rounding is relative to the scene's size rather than to how far away the
// ray starts; t is reported from the true origin. The shift is one per ray, never per
// triangle: two triangles sharing an edge must see the same origin to stay watertight.
template <class Real>
struct PreparedRay {
  Real origin[3];
  Real shift;
  float tmin;
  int kx, ky, kz;
  Real sx, sy, sz;

  PreparedRay(const Ray& ray, double shift_to) : shift(Real(shift_to)), tmin(ray.tmin) {
    const float* o = &ray.origin.x;
    const float* d = &ray.dir.x;
    for (int a = 0; a < 3; ++a) origin[a] = Real(double(o[a]) + shift_to * double(d[a]));
    const glm::vec3 mag = glm::abs(ray.dir);
    kz = (mag.x >= mag.y) ? (mag.x >= mag.z ? 0 : 2) : (mag.y >= mag.z ? 1 : 2);
    kx = kz == 2 ? 0 : kz + 1;
    ky = kx == 2 ? 0 : kx + 1;
    if (d[kz] < 0.0f) std::swap(kx, ky);  // keep the winding
    sz = Real(1) / Real(d[kz]);
    sx = Real(d[kx]) * sz;  // a product, not a quotient: one division per ray, not three
    sy = Real(d[ky]) * sz;
  }
};

// Tests one triangle. On a hit with tmin < t <= tmax (t as reported: rounded to float)
// writes t and the barycentric weights of the second (u) and third (v) corner and returns
// true.
template <class Real>
[[gnu::always_inline]] inline bool intersect_triangle(const PreparedRay<Real>& ray,
                                                      const glm::vec3& p0, const glm::vec3& p1,
                                                      const glm::vec3& p2, float tmax, float& t,
                                                      float& u, float& v) {
  // Raw component access: glm's operator[] is a switch, too slow for the inner loop.
  const float* c0 = &p0.x;
  const float* c1 = &p1.x;
  const float* c2 = &p2.x;
  const Real* o = ray.origin;
  const int kx = ray.kx, ky = ray.ky, kz = ray.kz;
  const Real az = Real(c0[kz]) - o[kz], bz = Real(c1[kz]) - o[kz], cz = Real(c2[kz]) - o[kz];
  const Real ax = (Real(c0[kx]) - o[kx]) - ray.sx * az;
  const Real ay = (Real(c0[ky]) - o[ky]) - ray.sy * az;
  const Real bx = (Real(c1[kx]) - o[kx]) - ray.sx * bz;
  const Real by = (Real(c1[ky]) - o[ky]) - ray.sy * bz;
  const Real cx = (Real(c2[kx]) - o[kx]) - ray.sx * cz;
  const Real cy = (Real(c2[ky]) - o[ky]) - ray.sy * cz;
  Real e0 = cx * by - cy * bx;  // weight of p0
  Real e1 = ax * cy - ay * cx;  // weight of p1
  Real e2 = bx * ay - by * ax;  // weight of p2
  if (e0 == Real(0) || e1 == Real(0) || e2 == Real(0)) {
    using W = typename WiderType<Real>::type;
    e0 = Real(W(cx) * W(by) - W(cy) * W(bx));
    e1 = Real(W(ax) * W(cy) - W(ay) * W(cx));
    e2 = Real(W(bx) * W(ay) - W(by) * W(ax));
  }
  if (std::min({e0, e1, e2}) < Real(0) && std::max({e0, e1, e2}) > Real(0)) return false;
  const Real det = e0 + e1 + e2;
  if (det == Real(0)) return false;
  const Real scaled_t = e0 * (ray.sz * az) + e1 * (ray.sz * bz) + e2 * (ray.sz * cz);
  const float hit_t = float(ray.shift + scaled_t / det);
  if (!(hit_t > ray.tmin && hit_t <= tmax)) return false;
  t = hit_t;
  u = float(e1 / det);
  v = float(e2 / det);
  return true;
}

// Keeps `best` the nearest hit, lowest id among equal t (DESIGN.md §3).
inline bool closer(float t, int32_t id, const Hit& best) {
  return t < best.t || (t == best.t && id < best.id);
}

}  // namespace gs
