#include "core/geometry.h"

namespace gs {

std::vector<TriangleVerts> gather_triangles(const Scene& scene) {
  std::vector<TriangleVerts> out(scene.triangle_count());
  for (uint32_t i = 0; i < out.size(); ++i)
    out[i] = {scene.vertex(i, 0), scene.vertex(i, 1), scene.vertex(i, 2)};
  return out;
}

bool ray_is_valid(const Ray& ray) {
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(ray.origin[k]) || !std::isfinite(ray.dir[k])) return false;
  if (ray.dir.x == 0.0f && ray.dir.y == 0.0f && ray.dir.z == 0.0f) return false;
  if (std::isnan(ray.tmin) || std::isnan(ray.tmax)) return false;
  return ray.tmin <= ray.tmax;
}

}  // namespace gs
