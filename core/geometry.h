// The watertight ray/triangle test of Woop, Benthin and Wald, "Watertight Ray/Triangle
// Intersection", JCGT 2(1), 2013. One float kernel serves brute and every structure, so
// that structures can be compared with brute exactly; the double instantiation checks it.
//
// Why watertight: the ray is sheared so that it runs along +z through the origin, and each
// edge is classified by a 2D edge function that two triangles sharing the edge evaluate
// bit-identically (negated). A ray through a shared edge or vertex therefore hits at least
// one of the triangles. Edge functions that round to exactly zero are redone in the next
// wider type, as the paper prescribes.
#pragma once
#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "core/ray.h"
#include "core/scene.h"

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

// The per-ray part of the test: axis permutation and shear (section 3 of the paper).
template <class Real>
struct PreparedRay {
  using Vec = glm::vec<3, Real>;
  Vec origin;
  Real tmin;
  int kx, ky, kz;
  Real sx, sy, sz;

  explicit PreparedRay(const Ray& ray) : origin(Vec(ray.origin)), tmin(Real(ray.tmin)) {
    const Vec dir(ray.dir);
    const Vec mag = glm::abs(dir);
    kz = (mag.x >= mag.y) ? (mag.x >= mag.z ? 0 : 2) : (mag.y >= mag.z ? 1 : 2);
    kx = kz == 2 ? 0 : kz + 1;
    ky = kx == 2 ? 0 : kx + 1;
    if (dir[kz] < Real(0)) std::swap(kx, ky);  // keep the winding
    sx = dir[kx] / dir[kz];
    sy = dir[ky] / dir[kz];
    sz = Real(1) / dir[kz];
  }
};

struct TriangleHit {
  float t, u, v;
};

// Tests one triangle. On a hit with tmin < t <= tmax writes t and the barycentric weights
// of the second (u) and third (v) corner and returns true.
template <class Real>
inline bool intersect_triangle(const PreparedRay<Real>& ray, const glm::vec3& p0,
                               const glm::vec3& p1, const glm::vec3& p2, Real tmax, Real& t,
                               Real& u, Real& v) {
  using Vec = glm::vec<3, Real>;
  const Vec a = Vec(p0) - ray.origin;
  const Vec b = Vec(p1) - ray.origin;
  const Vec c = Vec(p2) - ray.origin;
  const Real ax = a[ray.kx] - ray.sx * a[ray.kz];
  const Real ay = a[ray.ky] - ray.sy * a[ray.kz];
  const Real bx = b[ray.kx] - ray.sx * b[ray.kz];
  const Real by = b[ray.ky] - ray.sy * b[ray.kz];
  const Real cx = c[ray.kx] - ray.sx * c[ray.kz];
  const Real cy = c[ray.ky] - ray.sy * c[ray.kz];
  Real e0 = cx * by - cy * bx;  // weight of p0
  Real e1 = ax * cy - ay * cx;  // weight of p1
  Real e2 = bx * ay - by * ax;  // weight of p2
  if (e0 == Real(0) || e1 == Real(0) || e2 == Real(0)) {
    using W = typename WiderType<Real>::type;
    e0 = Real(W(cx) * W(by) - W(cy) * W(bx));
    e1 = Real(W(ax) * W(cy) - W(ay) * W(cx));
    e2 = Real(W(bx) * W(ay) - W(by) * W(ax));
  }
  if ((e0 < 0 || e1 < 0 || e2 < 0) && (e0 > 0 || e1 > 0 || e2 > 0)) return false;
  const Real det = e0 + e1 + e2;
  if (det == Real(0)) return false;
  const Real az = ray.sz * a[ray.kz];
  const Real bz = ray.sz * b[ray.kz];
  const Real cz = ray.sz * c[ray.kz];
  const Real scaled_t = e0 * az + e1 * bz + e2 * cz;
  const Real hit_t = scaled_t / det;
  if (!(hit_t > ray.tmin && hit_t <= tmax)) return false;
  t = hit_t;
  u = e1 / det;
  v = e2 / det;
  return true;
}

// Keeps `best` the nearest hit, lowest id among equal t (DESIGN.md §3).
inline bool closer(float t, int32_t id, const Hit& best) {
  return t < best.t || (t == best.t && id < best.id);
}

}  // namespace gs
