#include "core/accel/brute.h"

#include <chrono>

#include "core/base/timing.h"

namespace gs {

void BruteForce::build(const Scene& scene) {
  const auto start = Clock::now();
  triangles_ = gather_triangles(scene);
  usable_.clear();
  for (uint32_t i = 0; i < triangles_.size(); ++i)
    if (!scene.is_degenerate(i)) usable_.push_back(i);
  bounds_ = scene.bounds();
  clip_box_ = ClipBox(bounds_);
  build_seconds_ = seconds_since(start);
}

std::unique_ptr<ThreadContext> BruteForce::make_context() const {
  return std::make_unique<ThreadContext>();
}

template <class Real, bool AnyHit>
Hit BruteForce::trace(const Ray& ray, ThreadContext* context) const {
  Hit best;
  double t_enter, t_leave;
  if (!clip_box_.clip(ray, t_enter, t_leave)) return best;
  const PreparedRay<Real> prepared(ray, t_enter);
  float tmax = ray.tmax;
  for (const uint32_t id : usable_) {
    const TriangleVerts& tri = triangles_[id];
    float t, u, v;
    if (!intersect_triangle(prepared, tri.v0, tri.v1, tri.v2, tmax, t, u, v)) continue;
    if (closer(t, int32_t(id), best)) {
      best = {int32_t(id), t, u, v};
      tmax = t;
      if (AnyHit) break;
    }
  }
  if (context) context->counters.intersection_tests += usable_.size();
  return best;
}

Hit BruteForce::intersect(const Ray& ray, ThreadContext& context) const {
  return trace<KernelReal, false>(ray, &context);
}

Hit BruteForce::any_hit(const Ray& ray, ThreadContext& context) const {
  return trace<KernelReal, true>(ray, &context);
}

Hit BruteForce::intersect_long_double(const Ray& ray) const {
  return trace<long double, false>(ray, nullptr);
}

StructureStats BruteForce::stats() const {
  StructureStats s;
  s.nodes = 1;
  s.leaves = 1;
  s.voxels_subdivided = 0;
  s.traversal_states = std::nullopt;
  s.depth = 0;
  s.memory_bytes = triangles_.size() * sizeof(TriangleVerts) + usable_.size() * sizeof(uint32_t);
  s.build_seconds = build_seconds_;
  return s;
}

}  // namespace gs
