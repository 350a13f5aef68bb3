#include "core/scene/camera.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <limits>
#include <map>

#include "core/base/error.h"

namespace gs {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Built with append: GCC 12 warns falsely (-Wrestrict) about "literal" + std::string.
std::string quote(std::string_view word) { return std::string("'").append(word).append("'"); }

[[noreturn]] void bad_camera(const std::string& text, const std::string& problem) {
  throw UsageError("--camera " + quote(text) + ": " + problem);
}

float parse_number(const std::string& text, std::string_view word) {
  double value = 0.0;
  const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
  // A finite double can still overflow the float the camera keeps; NaN fails this too.
  if (error != std::errc() || end != word.data() + word.size() ||
      !(std::abs(value) <= double(std::numeric_limits<float>::max())))
    bad_camera(text, quote(word) + " is not a finite number");
  return float(value);
}

glm::vec3 parse_vector(const std::string& text, std::string_view word) {
  const size_t first = word.find(',');
  const size_t second = word.find(',', first + 1);
  if (first == std::string_view::npos || second == std::string_view::npos ||
      word.find(',', second + 1) != std::string_view::npos)
    bad_camera(text, quote(word) + " is not three numbers X,Y,Z");
  return {parse_number(text, word.substr(0, first)),
          parse_number(text, word.substr(first + 1, second - first - 1)),
          parse_number(text, word.substr(second + 1))};
}

// Splits "key=value;key=value" into a map, rejecting repeated and unknown keys.
std::map<std::string, std::string_view> split_parts(const std::string& text) {
  std::map<std::string, std::string_view> parts;
  std::string_view rest(text);
  while (!rest.empty()) {
    const size_t semicolon = std::min(rest.find(';'), rest.size());
    const std::string_view part = rest.substr(0, semicolon);
    rest = rest.substr(std::min(semicolon + 1, rest.size()));
    const size_t equals = part.find('=');
    const std::string key(part.substr(0, equals));
    if (equals == std::string_view::npos ||
        (key != "eye" && key != "target" && key != "up" && key != "fov"))
      bad_camera(text, "expected eye=X,Y,Z;target=X,Y,Z;up=X,Y,Z;fov=DEG");
    if (!parts.emplace(key, part.substr(equals + 1)).second)
      bad_camera(text, quote(key) + " is given twice");
  }
  for (const char* key : {"eye", "target", "up", "fov"})
    if (!parts.count(key)) bad_camera(text, quote(key) + " is missing");
  return parts;
}

void validate(const std::string& text, const Camera& camera) {
  const glm::vec3 view = camera.target - camera.eye;
  if (view == glm::vec3(0.0f)) bad_camera(text, "eye and target are the same point");
  const glm::vec3 side = glm::cross(glm::normalize(view), camera.up);
  // Relative to |up|, so that a short but valid up vector is accepted.
  if (!(glm::length(side) > 1e-6f * glm::length(camera.up)))
    bad_camera(text, "up is zero or parallel to the view direction");
  if (!(camera.fov > 0.0f && camera.fov < 180.0f))
    bad_camera(text, "fov must lie strictly between 0 and 180 degrees");
}

}  // namespace

glm::vec3 Camera::forward() const { return glm::normalize(target - eye); }
glm::vec3 Camera::right() const { return glm::normalize(glm::cross(forward(), up)); }
glm::vec3 Camera::true_up() const { return glm::cross(right(), forward()); }

Ray Camera::primary_ray(int px, int py, int width, int height, float jx, float jy) const {
  return PrimaryRays(*this, width, height)(px, py, jx, jy);
}

PrimaryRays::PrimaryRays(const Camera& camera, int width, int height)
    : eye_(camera.eye),
      forward_(camera.forward()),
      right_(camera.right()),
      up_(camera.true_up()),
      half_height_(float(std::tan(double(camera.fov) * kPi / 360.0))),
      half_width_(half_height_ * float(width) / float(height)),
      width_(width),
      height_(height) {}

Ray PrimaryRays::operator()(int px, int py, float jx, float jy) const {
  const float sx = ((float(px) + jx) / float(width_) * 2.0f - 1.0f) * half_width_;
  const float sy = (1.0f - (float(py) + jy) / float(height_) * 2.0f) * half_height_;
  Ray ray;
  ray.origin = eye_;
  ray.dir = forward_ + sx * right_ + sy * up_;
  return ray;
}

Camera parse_camera(const std::string& text) {
  const auto parts = split_parts(text);
  Camera camera;
  camera.eye = parse_vector(text, parts.at("eye"));
  camera.target = parse_vector(text, parts.at("target"));
  camera.up = parse_vector(text, parts.at("up"));
  camera.fov = parse_number(text, parts.at("fov"));
  validate(text, camera);
  return camera;
}

std::string to_string(const Camera& camera) {
  char buffer[512];
  const glm::vec3 &e = camera.eye, &t = camera.target, &u = camera.up;
  std::snprintf(buffer, sizeof buffer,
                "eye=%.9g,%.9g,%.9g;target=%.9g,%.9g,%.9g;up=%.9g,%.9g,%.9g;fov=%.9g", e.x, e.y,
                e.z, t.x, t.y, t.z, u.x, u.y, u.z, camera.fov);
  return buffer;
}

Camera frame_box(const Box& box, float aspect) {
  Camera camera;
  const glm::vec3 centre = box.empty() ? glm::vec3(0.0f) : (box.lo + box.hi) * 0.5f;
  const float magnitude = std::max({std::abs(centre.x), std::abs(centre.y), std::abs(centre.z)});
  // A point-like box gets a radius that is still resolvable at its coordinates.
  const float radius = std::max(box.empty() ? 1.0f : glm::length(box.hi - box.lo) * 0.5f,
                                1e-3f * (1.0f + magnitude));
  const double half_v = double(camera.fov) * kPi / 360.0;
  const double half_h = std::atan(std::tan(half_v) * double(aspect));
  const double distance = 1.05 * double(radius) / std::sin(std::min(half_v, half_h));
  camera.target = centre;
  camera.eye = centre + glm::normalize(glm::vec3(1.0f, 0.8f, 1.3f)) * float(distance);
  // Meshes are mostly y-up, the SPD scenes and our built-ins z-up: a box much flatter in z
  // than in x and y is taken as z-up, seen from above its ground.
  const glm::vec3 extent = box.empty() ? glm::vec3(1.0f) : box.hi - box.lo;
  if (extent.z < 0.5f * std::min(extent.x, extent.y)) {
    camera.up = {0.0f, 0.0f, 1.0f};
    camera.eye = centre + glm::normalize(glm::vec3(1.0f, -1.3f, 0.8f)) * float(distance);
  }
  return camera;
}

}  // namespace gs
