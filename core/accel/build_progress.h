// How far a structure's build has got, for a progress display (the viewer's build bar): the
// building thread adds to a BuildProgress while another thread reads it. Only structures that
// build voxel by voxel report one (Accelerator::build_progress); the others build in one call
// that says nothing until it returns.
#pragma once
#include <atomic>
#include <cstdint>
#include <optional>

namespace gs {

// A snapshot of a BuildProgress: plain numbers a display can keep.
struct BuildFigures {
  // The structure's own voxels: examined (cut, or made a leaf), cut, and the triangles
  // sorted into the cells of those cut (a voxel's triangles once per cut made).
  uint64_t voxels_built = 0;
  uint64_t voxels_subdivided = 0;
  uint64_t triangles_sorted = 0;
  // Of triangles_sorted, those of cuts the sampling pass's scout had made the same way: taken
  // from it as they stand, not sorted again.
  uint64_t triangles_from_scout = 0;
  // The sampling pass (§6.5): its rays (those it spawns, shadow rays, not counted), how many
  // of them were traced, and the voxels of the scout those rays built (the scout is the
  // sample-less structure that finds where the sample's rays end; the structure keeps what it
  // built for the cuts it makes the same way).
  uint64_t sample_rays = 0;
  uint64_t sample_rays_traced = 0;
  uint64_t scout_voxels_built = 0;

  // The share of the sampling pass done, from its rays traced: the one part of the build
  // whose total is known before it ends (how deep the lazy build goes depends on the rays
  // still to come). Nothing before the sampling pass has begun.
  std::optional<double> sampling_fraction() const;
};

// Relaxed atomics: each figure is shown on its own and never tells a reader that other data
// is ready, so no ordering is needed; the counts are exact once the build has returned.
struct BuildProgress {
  std::atomic<uint64_t> voxels_built{0};
  std::atomic<uint64_t> voxels_subdivided{0};
  std::atomic<uint64_t> triangles_sorted{0};
  std::atomic<uint64_t> triangles_from_scout{0};
  std::atomic<uint64_t> sample_rays{0};
  std::atomic<uint64_t> sample_rays_traced{0};
  std::atomic<uint64_t> scout_voxels_built{0};

  BuildFigures figures() const;
};

// Adds `amount` to a progress counter (relaxed: see BuildProgress).
inline void add_progress(std::atomic<uint64_t>& counter, uint64_t amount = 1) {
  counter.fetch_add(amount, std::memory_order_relaxed);
}

}  // namespace gs
