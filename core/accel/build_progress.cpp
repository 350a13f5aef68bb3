#include "core/accel/build_progress.h"

namespace gs {

std::optional<double> BuildFigures::sampling_fraction() const {
  if (sample_rays == 0) return std::nullopt;
  return double(sample_rays_traced) / double(sample_rays);
}

BuildFigures BuildProgress::figures() const {
  constexpr auto relaxed = std::memory_order_relaxed;
  BuildFigures f;
  f.voxels_built = voxels_built.load(relaxed);
  f.voxels_subdivided = voxels_subdivided.load(relaxed);
  f.triangles_sorted = triangles_sorted.load(relaxed);
  f.triangles_from_scout = triangles_from_scout.load(relaxed);
  f.sample_rays = sample_rays.load(relaxed);
  f.sample_rays_traced = sample_rays_traced.load(relaxed);
  f.scout_voxels_built = scout_voxels_built.load(relaxed);
  return f;
}

}  // namespace gs
