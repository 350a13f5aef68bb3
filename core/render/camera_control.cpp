#include "core/render/camera_control.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace gs {

namespace {

constexpr double kPi = 3.14159265358979323846;
// Orbit stops this far (radians, about one degree) short of looking along ±up.
constexpr double kPoleMargin = kPi / 180.0;
// Dolly moves the eye at most this fraction of the way to the target in one step.
constexpr float kMaxDolly = 0.999f;

// Rodrigues: v rotated by `angle` about the unit `axis` (right-handed).
glm::dvec3 rotate(const glm::dvec3& v, const glm::dvec3& axis, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return v * c + glm::cross(axis, v) * s + axis * (glm::dot(axis, v) * (1.0 - c));
}

bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

// Yaw turns right-handed about the camera's up vector (positive: counter-clockwise seen from
// above, the view direction swinging toward the camera's left); pitch turns
// right-handed about camera.right(), positive tilting the view direction toward up (the eye
// goes down). Both rotate eye and target rigidly about the pivot; up is kept.
Camera orbit(const Camera& camera, const glm::vec3& pivot, float yaw, float pitch) {
  if (!std::isfinite(yaw) || !std::isfinite(pitch) || !finite(pivot)) return camera;
  const glm::dvec3 up = glm::normalize(glm::dvec3(camera.up));
  const glm::dvec3 p(pivot);
  glm::dvec3 eye = glm::dvec3(camera.eye) - p, target = glm::dvec3(camera.target) - p;
  eye = rotate(eye, up, double(yaw));
  target = rotate(target, up, double(yaw));
  const glm::dvec3 forward = glm::normalize(target - eye);
  // The angle between forward and up is kept within [margin, pi - margin]; a pitch that
  // would leave that range stops at its edge (a camera already outside may only move back).
  const double angle = std::acos(std::clamp(glm::dot(forward, up), -1.0, 1.0));
  const double most = angle - kPoleMargin, least = angle - (kPi - kPoleMargin);
  const double turn = std::clamp(double(pitch), std::min(least, 0.0), std::max(most, 0.0));
  const glm::dvec3 right = glm::normalize(glm::cross(forward, up));
  eye = rotate(eye, right, turn);
  target = rotate(target, right, turn);
  Camera result = camera;
  result.eye = glm::vec3(p + eye);
  result.target = glm::vec3(p + target);
  if (result.eye == result.target) return camera;
  return result;
}

// Eye and target move by dx * H along right() and dy * H along true_up(), H being the height
// the view spans at the target's distance. Dragging the scene with the mouse is a pan by
// minus the drag (in fractions of the viewport's height, y up).
Camera pan(const Camera& camera, float dx, float dy) {
  if (!std::isfinite(dx) || !std::isfinite(dy)) return camera;
  const double distance = glm::length(glm::dvec3(camera.target) - glm::dvec3(camera.eye));
  const double height = 2.0 * distance * std::tan(double(camera.fov) * kPi / 360.0);
  const glm::dvec3 move =
      (glm::dvec3(camera.right()) * double(dx) + glm::dvec3(camera.true_up()) * double(dy)) *
      height;
  Camera result = camera;
  result.eye = glm::vec3(glm::dvec3(camera.eye) + move);
  result.target = glm::vec3(glm::dvec3(camera.target) + move);
  if (!finite(result.eye) || !finite(result.target) || result.eye == result.target) return camera;
  return result;
}

// The eye moves to eye + factor * (target - eye): the distance becomes (1 - factor) times
// what it was. factor is capped at kMaxDolly (never at or past the target); a negative
// factor backs away. A step that would put the eye on the target (float resolution) is not
// taken.
Camera dolly(const Camera& camera, float factor) {
  if (!std::isfinite(factor)) return camera;
  const double f = std::min(double(factor), double(kMaxDolly));
  const glm::dvec3 eye(camera.eye), target(camera.target);
  Camera result = camera;
  result.eye = glm::vec3(eye + (target - eye) * f);
  if (!finite(result.eye) || result.eye == result.target) return camera;
  // Rounding must not carry the eye past the target.
  if (glm::dot(glm::dvec3(result.target) - glm::dvec3(result.eye), target - eye) <= 0.0)
    return camera;
  return result;
}

Camera fly(const Camera& camera, const glm::vec3& forward_right_up) {
  if (!finite(forward_right_up)) return camera;
  const glm::dvec3 move = glm::dvec3(camera.forward()) * double(forward_right_up.x) +
                          glm::dvec3(camera.right()) * double(forward_right_up.y) +
                          glm::dvec3(camera.true_up()) * double(forward_right_up.z);
  Camera result = camera;
  result.eye = glm::vec3(glm::dvec3(camera.eye) + move);
  result.target = glm::vec3(glm::dvec3(camera.target) + move);
  if (!finite(result.eye) || !finite(result.target) || result.eye == result.target) return camera;
  return result;
}

}  // namespace gs
