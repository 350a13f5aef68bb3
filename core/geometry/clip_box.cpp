#include "core/geometry/clip_box.h"

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
  for (int a = 0; a < 3; ++a) lo[a] = scene.lo[a] - padding, hi[a] = scene.hi[a] + padding;
}

double ClipBox::min_cell_width(const double lo[3], const double hi[3]) const {
  double local_magnitude = 0.0;
  for (int a = 0; a < 3; ++a)
    local_magnitude = std::max({local_magnitude, std::fabs(lo[a]), std::fabs(hi[a])});
  return std::max(kMinCellUlps * FLT_EPSILON * local_magnitude, kMinCellPaddings * padding);
}

bool ray_is_valid(const Ray& ray) {
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(ray.origin[k]) || !std::isfinite(ray.dir[k])) return false;
  if (ray.dir.x == 0.0f && ray.dir.y == 0.0f && ray.dir.z == 0.0f) return false;
  if (std::isnan(ray.tmin) || std::isnan(ray.tmax)) return false;
  return ray.tmin <= ray.tmax;
}

}  // namespace gs
