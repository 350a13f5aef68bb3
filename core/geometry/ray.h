// Rays and hits exactly as the ray and hit files store them (docs/design.md §3).
#pragma once
#include <cstdint>
#include <glm/vec3.hpp>
#include <limits>

namespace gs {

// Distances along rays: "never" (a zero direction component's next wall, no hit yet).
inline constexpr double kInf = std::numeric_limits<double>::infinity();

// 32 bytes: ox oy oz tmin dx dy dz tmax, little-endian float32 in files.
// t is measured in units of dir (dir need not be normalised).
struct Ray {
  glm::vec3 origin{0.0f};
  float tmin = 0.0f;
  glm::vec3 dir{0.0f, 0.0f, 1.0f};
  float tmax = std::numeric_limits<float>::infinity();
};
static_assert(sizeof(Ray) == 32);

// 16 bytes: triangle id (-1 = miss), t, and the barycentric weights of the triangle's
// second (u) and third (v) vertex.
struct Hit {
  int32_t id = -1;
  float t = std::numeric_limits<float>::infinity();
  float u = 0.0f;
  float v = 0.0f;

  bool found() const { return id >= 0; }
  bool operator==(const Hit&) const = default;
};
static_assert(sizeof(Hit) == 16);

// +1, -1, or 0 for a zero direction component (either sign of zero): the way a walk steps.
inline int step_of(float d) { return int(d > 0.0f) - int(d < 0.0f); }  // two compares, no branch

// Rays with a NaN or infinite origin, a NaN, infinite or zero direction, or tmin > tmax
// (or a NaN bound) are answered as misses by every structure.
bool ray_is_valid(const Ray& ray);

}  // namespace gs
