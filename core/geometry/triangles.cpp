#include "core/geometry/triangles.h"

namespace gs {

std::vector<TriangleVerts> gather_triangles(const Scene& scene) {
  std::vector<TriangleVerts> out(scene.triangle_count());
  for (uint32_t i = 0; i < out.size(); ++i)
    out[i] = {scene.vertex(i, 0), scene.vertex(i, 1), scene.vertex(i, 2)};
  return out;
}

BuildInput::BuildInput(const Scene& scene)
    : triangles(gather_triangles(scene)), bounds(scene.bounds()), clip(bounds) {
  usable.reserve(triangles.size());
  for (uint32_t id = 0; id < triangles.size(); ++id) {
    if (scene.is_degenerate(id))
      ++degenerate;
    else
      usable.push_back(id);
  }
}

}  // namespace gs
