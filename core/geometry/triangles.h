// Triangles as every structure consumes them, and the preamble every build starts with.
#pragma once
#include <cstdint>
#include <glm/vec3.hpp>
#include <vector>

#include "core/geometry/clip_box.h"
#include "core/scene/scene.h"

namespace gs {

struct TriangleVerts {
  glm::vec3 v0, v1, v2;
};
static_assert(sizeof(TriangleVerts) == 36);

// Triangle corners in id order.
std::vector<TriangleVerts> gather_triangles(const Scene& scene);

// What every structure's build starts from: the triangles by id, the ones it may use
// (degenerate triangles keep their ids but are set aside), the padded clip box every ray is
// clipped to, and each triangle's box padded as the clip box is (docs/design.md §6): sorting
// triangles into cells by these boxes puts each in every cell where the kernel could report
// it hit.
struct BuildInput {
  std::vector<TriangleVerts> triangles;  // every triangle, by id
  std::vector<uint32_t> usable;          // ids of the non-degenerate ones, ascending
  std::vector<double> boxes;             // per triangle lo.xyz, hi.xyz, padded
  Box bounds;
  ClipBox clip;
  size_t degenerate = 0;

  BuildInput() = default;  // no scene: an empty clip box
  explicit BuildInput(const Scene& scene);
  const double* box(uint32_t id) const { return &boxes[size_t(id) * 6]; }
  // Frees the per-triangle data once a structure built up front has copied what it keeps.
  void release_triangles() { triangles = {}, usable = {}, boxes = {}; }
};

}  // namespace gs
