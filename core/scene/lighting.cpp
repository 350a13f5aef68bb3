#include "core/scene/lighting.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

namespace gs {

namespace {

float max_abs(const glm::vec3& p) {
  return std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
}

}  // namespace

Lighting make_lighting(const Box& box, const Camera& camera,
                       const std::optional<glm::vec3>& placed) {
  const float size = box.empty() ? 1.0f : std::max(glm::length(box.hi - box.lo), 1e-6f);
  if (placed) return {*placed, size};
  // Above and behind the viewer, a little to the side, so that faces towards the camera are
  // lit and shadows fall visibly down and away.
  const glm::vec3 light = camera.eye - camera.forward() * (0.5f * size) + camera.true_up() * size +
                          camera.right() * (0.3f * size);
  return {light, size};
}

Surface surface_at(const Scene& scene, const Hit& hit, const glm::vec3& ray_dir) {
  const uint32_t id = uint32_t(hit.id);
  const glm::vec3 &a = scene.vertex(id, 0), &b = scene.vertex(id, 1), &c = scene.vertex(id, 2);
  // The point from the barycentrics lies on the triangle, unlike origin + t * dir.
  const glm::vec3 point = (1.0f - hit.u - hit.v) * a + hit.u * b + hit.v * c;
  glm::vec3 normal = glm::normalize(glm::cross(b - a, c - a));
  if (glm::dot(normal, ray_dir) > 0.0f) normal = -normal;
  return {point, normal};
}

glm::vec3 ray_start(const Surface& surface, const Lighting& lighting) {
  return surface.point +
         surface.normal * (1e-4f * lighting.offset_scale + 1e-5f * max_abs(surface.point));
}

std::optional<LightPath> light_path(const Surface& surface, const Lighting& lighting) {
  const float lambert = glm::dot(surface.normal, glm::normalize(lighting.light - surface.point));
  if (!(lambert > 0.0f)) return std::nullopt;
  Ray shadow;
  shadow.origin = ray_start(surface, lighting);
  shadow.dir = lighting.light - shadow.origin;
  shadow.tmax = 1.0f;  // the light itself
  return LightPath{lambert, shadow};
}

}  // namespace gs
