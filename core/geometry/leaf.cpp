#include "core/geometry/leaf.h"

#include <cstdlib>
#include <limits>
#include <mutex>

#include "core/base/error.h"
#include "core/geometry/clip_box.h"
#include "core/geometry/simd.h"

namespace gs {

// Per triangle a leaf takes 4 bytes of ids and 60 of floats; per leaf at most 8 bytes of
// header and 88 of box padding: the id arena never needs more than 1/12 of the bytes, the
// float arena never more than 15/16.
LeafStore::LeafStore(uint64_t max_bytes) : ids_(max_bytes / 12), coords_(max_bytes / 16 * 15) {}

void LeafStore::reset(uint64_t max_bytes) {
  ids_.reset(max_bytes / 12);
  coords_.reset(max_bytes / 16 * 15);
}

constexpr float kInfinity = std::numeric_limits<float>::infinity();

uint32_t LeafStore::add(const std::vector<uint32_t>& ids, const BuildInput& input) {
  const auto n = uint32_t(ids.size());
  const size_t handle = ids_.append(size_t(n) + 2);
  if (handle == SIZE_MAX || handle >= kFull) return kFull;
  const size_t floats = coords_.append(size_t(9) * n + box_floats(n));
  if (floats == SIZE_MAX || floats > UINT32_MAX) return kFull;
  ids_[handle] = n, ids_[handle + 1] = uint32_t(floats);
  float* coords = &coords_[floats];
  float* boxes = coords + size_t(9) * n;
  const uint32_t stride = box_stride(n);
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t id = ids[i] & ~kOnlyHere;
    ids_[handle + 2 + i] = ids[i];
    const TriangleVerts& t = input.triangles[id];
    const glm::vec3* corners[3] = {&t.v0, &t.v1, &t.v2};
    for (int k = 0; k < 3; ++k)
      for (int a = 0; a < 3; ++a) coords[size_t(3 * k + a) * n + i] = (*corners[k])[a];
    const TriangleBox box = input.box(id);
    for (int a = 0; a < 3; ++a) {
      boxes[a * stride + i] = float_down(box[a]);
      boxes[(a + 3) * stride + i] = float_up(box[a + 3]);
    }
  }
  // Lanes past the last triangle read empty boxes, which no ray crosses.
  for (uint32_t i = n; i < stride; ++i)
    for (int a = 0; a < 3; ++a)
      boxes[a * stride + i] = kInfinity, boxes[(a + 3) * stride + i] = -kInfinity;
  return uint32_t(handle);
}

uint32_t test_lanes_scalar(const LeafView& leaf, uint32_t first, uint32_t lanes,
                           const PreparedRay<KernelReal>& ray, float tmax, LaneHits& out) {
  uint32_t hits = 0;
  for (; lanes != 0; lanes &= lanes - 1) {
    const uint32_t j = uint32_t(std::countr_zero(lanes)), i = first + j;
    if (intersect_triangle(ray, leaf.corner(i, 0), leaf.corner(i, 1), leaf.corner(i, 2), leaf.count,
                           tmax, out.t[j], out.u[j], out.v[j]))
      hits |= 1u << j;
  }
  return hits;
}

uint64_t test_rays_scalar(const LeafView& leaf, uint32_t tri, const RayLanes& rays, uint64_t lanes,
                          RayHits& out) {
  uint64_t hits = 0;
  for (; lanes != 0; lanes &= lanes - 1) {
    const auto r = uint32_t(std::countr_zero(lanes));
    if (intersect_triangle(rays.prepared(r), leaf.corner(tri, 0), leaf.corner(tri, 1),
                           leaf.corner(tri, 2), leaf.count, rays.tmax[r], out.t[r], out.u[r],
                           out.v[r]))
      hits |= uint64_t{1} << r;
  }
  return hits;
}

const char* isa_name(Isa isa) {
  switch (isa) {
    case Isa::scalar:
      return "scalar";
    case Isa::avx2:
      return "avx2";
    case Isa::avx512:
      return "avx512";
  }
  return "?";
}

bool isa_supported(Isa isa) {
  switch (isa) {
    case Isa::scalar:
      return true;
    case Isa::avx2:
      return __builtin_cpu_supports("avx2");
    case Isa::avx512:
      return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
             __builtin_cpu_supports("avx512dq");
  }
  return false;
}

namespace {

std::mutex isa_mutex;
bool isa_chosen = false;
Isa chosen_isa = Isa::scalar;

Isa checked(Isa isa, const std::string& source) {
  if (!isa_supported(isa))
    throw UsageError(source + ": this CPU cannot run the " + isa_name(isa) + " kernel");
  return isa;
}

Isa from_environment() {
  const char* forced = std::getenv("GRIDSCOPE_ISA");
  if (!forced || !*forced) {
    for (const Isa isa : {Isa::avx512, Isa::avx2})
      if (isa_supported(isa)) return isa;
    return Isa::scalar;
  }
  for (const Isa isa : {Isa::scalar, Isa::avx2, Isa::avx512})
    if (std::string(forced) == isa_name(isa))
      return checked(isa, std::string("GRIDSCOPE_ISA=") + forced);
  throw UsageError(std::string("GRIDSCOPE_ISA=") + forced + ": expected scalar, avx2 or avx512");
}

}  // namespace

Isa kernel_isa() {
  std::lock_guard lock(isa_mutex);
  if (!isa_chosen) chosen_isa = from_environment(), isa_chosen = true;
  return chosen_isa;
}

void force_kernel_isa(Isa isa) {
  std::lock_guard lock(isa_mutex);
  chosen_isa = checked(isa, "force_kernel_isa");
  isa_chosen = true;
}

uint64_t rays_crossed_sse(const RayBoxLanes& lanes, const float* boxes, uint32_t stride,
                          uint32_t first, uint64_t which, uint64_t rays, uint64_t* crossing) {
  for (uint64_t left = which; left != 0; left &= left - 1) {
    const auto k = uint32_t(std::countr_zero(left));
    crossing[k] = lanes.crossed(boxes, stride, first + k, rays);
  }
  return boxes_with_crossers(which, rays, crossing);
}

Kernel kernel_for(Isa isa) {
  switch (isa) {
    case Isa::avx2:
      return {4,
              8,
              test_lanes_avx2,
              test_rays_avx2,
              rays_crossed_avx2,
              boxes_crossed_avx2,
              bounds_crossed_avx2};
    case Isa::avx512:
      return {8,
              16,
              test_lanes_avx512,
              test_rays_avx512,
              rays_crossed_avx512,
              boxes_crossed_avx512,
              bounds_crossed_avx512};
    case Isa::scalar:
      break;
  }
  return {1,
          4,
          test_lanes_scalar,
          test_rays_scalar,
          rays_crossed_sse,
          boxes_crossed_sse,
          bounds_crossed_sse};
}

uint64_t bounds_crossed_sse(const RayBoxLanes& lanes, const float* boxes, uint32_t stride,
                            uint32_t first, uint32_t count) {
  uint64_t met = 0;
  for (uint32_t k = 0; k < count; k += 4)
    met |= uint64_t(lanes.may_cross4(boxes, stride, first + k)) << k;
  return count == 64 ? met : met & ((uint64_t{1} << count) - 1);
}

uint64_t boxes_crossed_sse(const RayBoxes& ray, const float* boxes, uint32_t stride, uint32_t first,
                           uint32_t count, __m128 t0, __m128 t1) {
  uint64_t met = 0;
  for (uint32_t k = 0; k < count; k += 4)
    met |= uint64_t(ray.crossed4(boxes, stride, first + k, t0, t1)) << k;
  return count == 64 ? met : met & ((uint64_t{1} << count) - 1);
}

}  // namespace gs
