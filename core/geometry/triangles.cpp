#include "core/geometry/triangles.h"

#include <glm/common.hpp>

namespace gs {

std::vector<TriangleVerts> gather_triangles(const Scene& scene) {
  std::vector<TriangleVerts> out(scene.triangle_count());
  for (uint32_t i = 0; i < out.size(); ++i)
    out[i] = {scene.vertex(i, 0), scene.vertex(i, 1), scene.vertex(i, 2)};
  return out;
}

BuildInput::BuildInput(const Scene& scene)
    : triangles(gather_triangles(scene)), bounds(scene.bounds()), clip(bounds) {
  boxes.resize(triangles.size() * 6);
  for (uint32_t id = 0; id < triangles.size(); ++id) {
    const TriangleVerts& t = triangles[id];
    const glm::dvec3 lo = glm::dvec3(glm::min(t.v0, glm::min(t.v1, t.v2))) - clip.padding;
    const glm::dvec3 hi = glm::dvec3(glm::max(t.v0, glm::max(t.v1, t.v2))) + clip.padding;
    std::copy(&lo.x, &lo.x + 3, &boxes[size_t(id) * 6]);
    std::copy(&hi.x, &hi.x + 3, &boxes[size_t(id) * 6 + 3]);
    if (scene.is_degenerate(id))
      ++degenerate;
    else
      usable.push_back(id);
  }
}

}  // namespace gs
