#include "core/trace/sampling.h"

#include <algorithm>

namespace gs {

void sample_run(Accelerator& accel, std::span<const Ray> sample, size_t run_rays, int threads) {
  if (!sample.empty()) accel.sample(sample, double(run_rays) / double(sample.size()), {}, threads);
}

void sample_image_rays(Accelerator& accel, const Scene& scene, const Lighting& lighting,
                       std::span<const Ray> primaries, size_t run_primaries, int threads) {
  if (primaries.empty()) return;
  const SpawnRays shadow_ray = [&](const Ray& ray, const Hit& hit, std::vector<Ray>& next) {
    if (!hit.found()) return;
    if (const auto path = light_path(surface_at(scene, hit, ray.dir), lighting))
      next.push_back(path->shadow);
  };
  accel.sample(primaries, double(run_primaries) / double(primaries.size()), shadow_ray, threads);
}

// A regular subset of the run's rays (docs/design.md §1.5): indices 0, k, 2k, ...
std::vector<Ray> sample_subset(const std::vector<Ray>& rays, int every) {
  std::vector<Ray> subset;
  subset.reserve(rays.size() / size_t(every) + 1);
  for (size_t i = 0; i < rays.size(); i += size_t(every)) subset.push_back(rays[i]);
  return subset;
}

std::vector<size_t> image_sample_pixels(int width, int height) {
  constexpr int kBlock = 8;
  std::vector<size_t> pixels;
  for (int by = 0; by < height; by += kBlock)
    for (int bx = 0; bx < width; bx += kBlock)
      pixels.push_back(size_t(std::min(by + kBlock / 2, height - 1)) * size_t(width) +
                       size_t(std::min(bx + kBlock / 2, width - 1)));
  return pixels;
}

std::vector<Ray> image_sample(const std::vector<Ray>& rays, int width, int height) {
  std::vector<Ray> sample;
  for (const size_t pixel : image_sample_pixels(width, height)) sample.push_back(rays.at(pixel));
  return sample;
}

}  // namespace gs
