// A pinhole camera and its one string form (docs/design.md §3: `--camera` takes and prints it):
//   eye=X,Y,Z;target=X,Y,Z;up=X,Y,Z;fov=DEG
// fov is the vertical field of view in degrees. Pixel (0,0) is the top-left of the image.
#pragma once
#include <glm/vec3.hpp>
#include <string>

#include "core/geometry/ray.h"
#include "core/scene/scene.h"

namespace gs {

struct Camera {
  glm::vec3 eye{0.0f, 0.0f, 1.0f};
  glm::vec3 target{0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float fov = 45.0f;  // vertical, degrees, in (0, 180)

  // The ray through image point (px + jx, py + jy) of a width x height image: jx = jy = 0.5
  // is the pixel centre. tmin 0, tmax +inf, direction not normalised.
  Ray primary_ray(int px, int py, int width, int height, float jx = 0.5f, float jy = 0.5f) const;
  // The unit vectors the image plane is spanned by: view direction, right, and up.
  glm::vec3 forward() const;
  glm::vec3 right() const;
  glm::vec3 true_up() const;
};

// A camera's primary rays for one image size: what Camera::primary_ray derives from the
// camera for every pixel (a tangent, two normalisations), derived once. The rays are
// Camera::primary_ray's, bit for bit.
class PrimaryRays {
 public:
  PrimaryRays(const Camera& camera, int width, int height);
  Ray operator()(int px, int py, float jx = 0.5f, float jy = 0.5f) const;

 private:
  glm::vec3 eye_, forward_, right_, up_;
  float half_height_, half_width_;
  int width_, height_;
};

// Parses the string form. Keys may come in any order, each exactly once. Throws UsageError
// for a missing or repeated part, a non-number, NaN or infinity, eye == target, an up vector
// parallel to the view direction (or zero), or fov outside (0, 180).
Camera parse_camera(const std::string& text);
// The string form, each number with 9 significant digits so that parsing it gives back the
// same floats.
std::string to_string(const Camera& camera);

// The default camera: looks at the box's centre along -(1, 0.8, 1.3), far enough back that
// the box's bounding sphere fits the field of view of an image with this aspect
// (width / height). A flat, point-like or empty box still gives a valid camera.
Camera frame_box(const Box& box, float aspect = 1.0f);

}  // namespace gs
