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

bool start_walk(const ClipBox& box, const Ray& ray, WalkLine& line) {
  double t_leave;
  if (!box.clip(ray, line.shift, t_leave, line.inv_dir)) return false;
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

double WalkLine::stop(float tmax) const { return walk_stop(tmax, slack, shift); }

bool ray_is_valid(const Ray& ray) {
  // x - x is NaN exactly when x is infinite or NaN: one test for the six components.
  const glm::vec3 o = ray.origin, d = ray.dir;
  const float finite =
      (o.x - o.x) + (o.y - o.y) + (o.z - o.z) + (d.x - d.x) + (d.y - d.y) + (d.z - d.z);
  if (finite != 0.0f) return false;
  if (d.x == 0.0f && d.y == 0.0f && d.z == 0.0f) return false;
  return ray.tmin <= ray.tmax;  // false for a NaN bound too
}

}  // namespace gs
