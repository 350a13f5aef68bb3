// The renderer's point light and the rays that leave a surface: shared by the renderer and by
// the sampling pass of an image (which samples the shadow rays the image will cast).
#pragma once
#include <glm/vec3.hpp>
#include <optional>

#include "core/geometry/ray.h"
#include "core/scene/camera.h"
#include "core/scene/scene.h"

namespace gs {

// The point light and the scene's scale, fixed for one image.
struct Lighting {
  glm::vec3 light;
  float offset_scale;  // rays leave a surface this far (times the coordinates' size) off it
};

// The light at `placed`, or by default above and behind the camera, for a scene whose box
// (Scene::bounds) is `scene_box`. The box, not the scene: renders take it from their
// structure (Accelerator::bounds), since a scan of every triangle per pass cost the viewer's
// passes over the 871k-triangle dragon about 6 ms each.
Lighting make_lighting(const Box& scene_box, const Camera& camera,
                       const std::optional<glm::vec3>& placed);

// A hit point and its normal, turned to face where the ray came from (two-sided surfaces).
struct Surface {
  glm::vec3 point;
  glm::vec3 normal;
};

Surface surface_at(const Scene& scene, const Hit& hit, const glm::vec3& ray_dir);

// Where rays leaving a surface start: off it on the normal's side, so that the triangle
// cannot hit itself.
glm::vec3 ray_start(const Surface& surface, const Lighting& lighting);

// The shadow ray from a surface toward the light and the cosine of the light's angle to the
// normal.
struct LightPath {
  float lambert;
  Ray shadow;
};

// None when the light is behind the surface.
std::optional<LightPath> light_path(const Surface& surface, const Lighting& lighting);

}  // namespace gs
