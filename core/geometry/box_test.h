// A ray's segment against an axis-aligned box, in double: how walks decide that a cell's or
// node's contents (their triangles' padded boxes) lie off the ray and need no look.
#pragma once
#include <cmath>

namespace gs {

// The ray as the test reads it: origin, 1 / dir (infinite for a zero component) and, per
// axis, which face it meets first. A face the origin lies on gives 0 * inf = NaN, which the
// selects below ignore: that axis does not constrain the ray, as it should not.
struct RayBoxTest {
  double origin[3], inv_dir[3];
  bool near_hi[3];  // the ray runs toward -axis: it meets the box's hi face first

  RayBoxTest(const double origin_[3], const double inv_dir_[3]) {
    for (int a = 0; a < 3; ++a)
      origin[a] = origin_[a], inv_dir[a] = inv_dir_[a], near_hi[a] = std::signbit(inv_dir[a]);
  }
  // True when the ray meets the box lo..hi somewhere in [t0, t1]. Conservative for boxes
  // whose contents keep a margin of ClipBox::padding from their faces (docs/design.md §6):
  // double rounding is far below it.
  bool crosses(const float lo[3], const float hi[3], double t0, double t1) const {
    for (int a = 0; a < 3; ++a) {
      const double near_face = near_hi[a] ? hi[a] : lo[a], far_face = near_hi[a] ? lo[a] : hi[a];
      const double t_near = (near_face - origin[a]) * inv_dir[a];
      const double t_far = (far_face - origin[a]) * inv_dir[a];
      t0 = t_near > t0 ? t_near : t0;
      t1 = t_far < t1 ? t_far : t1;
    }
    return t0 <= t1;
  }
};

}  // namespace gs
