// Triangles as every structure consumes them, and the preamble every build starts with.
#pragma once
#include <algorithm>
#include <array>
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

// A triangle's box, lo.xyz then hi.xyz.
using TriangleBox = std::array<double, 6>;

// What every structure's build starts from: the triangles by id, the ones it may use
// (degenerate triangles keep their ids but are set aside), the padded clip box every ray is
// clipped to, and each triangle's box padded as the clip box is (docs/design.md §6): sorting
// triangles into cells by these boxes puts each in every cell where the kernel could report
// it hit.
struct BuildInput {
  std::vector<TriangleVerts> triangles;  // every triangle, by id
  std::vector<uint32_t> usable;          // ids of the non-degenerate ones, ascending
  Box bounds;
  ClipBox clip;
  size_t degenerate = 0;

  BuildInput() = default;  // no scene: an empty clip box
  explicit BuildInput(const Scene& scene);
  // Triangle `id`'s padded box, the same doubles at every call. Computed from its corners
  // rather than stored: a stored copy is 48 bytes a triangle that every build first writes,
  // and memory not touched before is dear to touch on virtual machines (0.16-0.24 s for the
  // 871k-triangle dragon's 42 MB here); the extra arithmetic costs less (README.md,
  // "Performance").
  double box_lo(uint32_t id, int axis) const {
    const TriangleVerts& t = triangles[id];
    return double(std::min(t.v0[axis], std::min(t.v1[axis], t.v2[axis]))) - clip.padding;
  }
  double box_hi(uint32_t id, int axis) const {
    const TriangleVerts& t = triangles[id];
    return double(std::max(t.v0[axis], std::max(t.v1[axis], t.v2[axis]))) + clip.padding;
  }
  TriangleBox box(uint32_t id) const {
    return {box_lo(id, 0), box_lo(id, 1), box_lo(id, 2),
            box_hi(id, 0), box_hi(id, 1), box_hi(id, 2)};
  }
  // Frees the per-triangle data once a structure built up front has copied what it keeps.
  void release_triangles() { triangles = {}, usable = {}; }
};

}  // namespace gs
