#include "core/accel/zero_overhead.h"

#include <chrono>
#include <utility>

#include "core/base/error.h"
#include "core/base/timing.h"
#include "core/geometry/ray_io.h"

namespace gs {

ZeroOverhead::ZeroOverhead(const AccelParams& params) : oracle_path_(params.oracle_path) {
  if (oracle_path_.empty())
    throw UsageError("structure 'zero' needs --oracle FILE.hits (the hits of an earlier run)");
}

ZeroOverhead::ZeroOverhead(std::vector<Hit> oracle)
    : oracle_path_("(memory)"), oracle_in_memory_(true), oracle_(std::move(oracle)) {}

void ZeroOverhead::build(const Scene& scene) {
  const auto start = Clock::now();
  if (!oracle_in_memory_) oracle_ = read_hits(oracle_path_);
  for (size_t i = 0; i < oracle_.size(); ++i) {
    const int32_t id = oracle_[i].id;
    if (id < -1 || (id >= 0 && size_t(id) >= scene.triangle_count()))
      fail_input(oracle_path_, "hit " + std::to_string(i) + " names triangle " +
                                   std::to_string(id) + ", but the scene has " +
                                   std::to_string(scene.triangle_count()) + " triangles");
  }
  triangles_ = gather_triangles(scene);
  bounds_ = scene.bounds();
  clip_box_ = ClipBox(bounds_);
  build_seconds_ = seconds_since(start);
}

void ZeroOverhead::check_ray_keys(size_t keys, const std::string& what) const {
  if (oracle_.size() != keys)
    fail_input(oracle_path_, "holds " + std::to_string(oracle_.size()) + " hits, not one per " +
                                 what + " (" + std::to_string(keys) + ")");
}

std::unique_ptr<ThreadContext> ZeroOverhead::make_context() const {
  return std::make_unique<ThreadContext>();
}

Hit ZeroOverhead::intersect(const Ray& ray, ThreadContext& context) const {
  if (context.ray_index == ThreadContext::kNoRayIndex)
    throw UsageError(
        "structure 'zero' answers only rays with a key (trace's ray index or a "
        "render's ray key): its oracle is indexed by it");
  if (context.ray_index >= oracle_.size())
    fail_input(oracle_path_, "has no hit for ray " + std::to_string(context.ray_index));
  Hit hit;
  const int32_t id = oracle_[context.ray_index].id;
  if (id < 0) return hit;
  double t_enter, t_leave;
  if (!clip_box_.clip(ray, t_enter, t_leave)) return hit;
  const PreparedRay<KernelReal> prepared(ray, t_enter);
  const TriangleVerts& tri = triangles_[size_t(id)];
  float t, u, v;
  ++context.counters.intersection_tests;
  if (intersect_triangle(prepared, tri.v0, tri.v1, tri.v2, ray.tmax, t, u, v)) hit = {id, t, u, v};
  return hit;
}

Hit ZeroOverhead::any_hit(const Ray& ray, ThreadContext& context) const {
  return intersect(ray, context);
}

StructureStats ZeroOverhead::stats() const {
  StructureStats s;  // nodes, leaves, voxels, states: null, there is no structure
  s.memory_bytes = oracle_.size() * sizeof(Hit) + triangles_.size() * sizeof(TriangleVerts);
  s.build_seconds = build_seconds_;
  return s;
}

}  // namespace gs
