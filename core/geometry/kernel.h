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
#include <type_traits>

#include "core/geometry/ray.h"

namespace gs {

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

// The two axes the ray is sheared along, after kz (its largest direction component):
// the next two in cyclic order, swapped when the ray runs down kz to keep the winding.
inline void shear_axes(int kz, bool down, int& kx, int& ky) {
  kx = kz == 2 ? 0 : kz + 1;
  ky = kx == 2 ? 0 : kx + 1;
  if (down) std::swap(kx, ky);
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

  PreparedRay() = default;  // for figures set one by one (RayLanes::prepared)
  PreparedRay(const Ray& ray, double shift_to) : PreparedRay(ray, shift_to, nullptr) {}
  // With the ray's 1 / dir per axis (ClipBox::clip's), for double: the one division the
  // set-up needs is then already done, with the same result.
  PreparedRay(const Ray& ray, double shift_to, const double* inv_dir)
      : shift(Real(shift_to)), tmin(ray.tmin) {
    const float* o = &ray.origin.x;
    const float* d = &ray.dir.x;
    for (int a = 0; a < 3; ++a) origin[a] = Real(double(o[a]) + shift_to * double(d[a]));
    const glm::vec3 mag = glm::abs(ray.dir);
    kz = (mag.x >= mag.y) ? (mag.x >= mag.z ? 0 : 2) : (mag.y >= mag.z ? 1 : 2);
    shear_axes(kz, d[kz] < 0.0f, kx, ky);
    sz = inv_dir && std::is_same_v<Real, double> ? Real(inv_dir[kz]) : Real(1) / Real(d[kz]);
    sx = Real(d[kx]) * sz;  // a product, not a quotient: one division per ray, not three
    sy = Real(d[ky]) * sz;
  }
};

// Tests one triangle whose corners' coordinates are c0[a * stride], c1[a * stride],
// c2[a * stride] for axis a (stride 1 for a glm::vec3; a leaf's count for its
// structure-of-arrays block, core/geometry/leaf.h). On a hit with tmin < t <= tmax (t as reported:
// rounded to float) writes t and the barycentric weights of the second (u) and third (v) corner and
// returns true.
template <class Real>
[[gnu::always_inline]] inline bool intersect_triangle(const PreparedRay<Real>& ray, const float* c0,
                                                      const float* c1, const float* c2,
                                                      size_t stride, float tmax, float& t, float& u,
                                                      float& v) {
  const Real* o = ray.origin;
  const int kx = ray.kx, ky = ray.ky, kz = ray.kz;
  const Real az = Real(c0[kz * stride]) - o[kz], bz = Real(c1[kz * stride]) - o[kz],
             cz = Real(c2[kz * stride]) - o[kz];
  const Real ax = (Real(c0[kx * stride]) - o[kx]) - ray.sx * az;
  const Real ay = (Real(c0[ky * stride]) - o[ky]) - ray.sy * az;
  const Real bx = (Real(c1[kx * stride]) - o[kx]) - ray.sx * bz;
  const Real by = (Real(c1[ky * stride]) - o[ky]) - ray.sy * bz;
  const Real cx = (Real(c2[kx * stride]) - o[kx]) - ray.sx * cz;
  const Real cy = (Real(c2[ky * stride]) - o[ky]) - ray.sy * cz;
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

template <class Real>
[[gnu::always_inline]] inline bool intersect_triangle(const PreparedRay<Real>& ray,
                                                      const glm::vec3& p0, const glm::vec3& p1,
                                                      const glm::vec3& p2, float tmax, float& t,
                                                      float& u, float& v) {
  return intersect_triangle(ray, &p0.x, &p1.x, &p2.x, 1, tmax, t, u, v);
}

// Keeps `best` the nearest hit, lowest id among equal t (docs/design.md §3).
inline bool closer(float t, int32_t id, const Hit& best) {
  return t < best.t || (t == best.t && id < best.id);
}

}  // namespace gs
