// What the uniform grid and the octree share: a per-thread ray-id mailbox and the triangle
// loop, with the stopping rule of every structure (walk_slack, stop_distance in
// core/geometry.h) so that every structure answers exactly as brute.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "core/accel/accelerator.h"
#include "core/geometry/kernel.h"
#include "core/geometry/ray.h"

namespace gs {

// Ray-id mailboxing (Amanatides & Woo 1987; Jevans 1990 §6.4) in a small direct-mapped
// table per thread instead of a stamp per triangle: the paper's per-object stamp would race
// between threads, and the table stays in L1 whatever the scene's size. A collision only
// costs a repeated test, whose answer is the same. Ray ids are 64 bits: they never wrap.
// Cache-line aligned: two threads' contexts must not share a line.
class alignas(64) MailboxContext final : public ThreadContext {
 public:
  static constexpr size_t kSlots = 1024;

  uint64_t next_ray() { return ++ray_id_; }
  bool already_tested(uint32_t triangle, uint64_t ray) {
    const size_t slot = triangle & (kSlots - 1);
    if (ray_[slot] == ray && triangle_[slot] == triangle) return true;
    ray_[slot] = ray, triangle_[slot] = triangle;
    return false;
  }

 private:
  uint64_t ray_id_ = 0;
  uint64_t ray_[kSlots] = {};
  uint32_t triangle_[kSlots] = {};
};

// +1, -1, or 0 for a zero component (either sign of zero).
inline int step_of(float d) { return d > 0.0f ? 1 : d < 0.0f ? -1 : 0; }

// Tests a cell's triangles not yet tested by this ray, keeping `best` the nearest (tie rule
// `closer`) and `tmax` its t; true when one of them became the nearest hit.
template <bool AnyHit>
inline bool test_triangles(const uint32_t* ids, uint32_t count, const TriangleVerts* triangles,
                           const PreparedRay<KernelReal>& prepared, uint64_t ray_id, float& tmax,
                           Hit& best, MailboxContext& context) {
  TraceCounters& counters = context.counters;
  bool found = false;
  for (uint32_t i = 0; i < count; ++i) {
    const uint32_t id = ids[i];
    if (context.already_tested(id, ray_id)) {
      ++counters.mailbox_rejections;
      continue;
    }
    ++counters.intersection_tests;
    const TriangleVerts& tri = triangles[id];
    float t, u, v;
    if (intersect_triangle(prepared, tri.v0, tri.v1, tri.v2, tmax, t, u, v) &&
        closer(t, int32_t(id), best)) {
      best = {int32_t(id), t, u, v};
      tmax = t;
      found = true;
      if (AnyHit) return true;
    }
  }
  return found;
}

}  // namespace gs
