#include "core/trace/sampling.h"

#include <algorithm>

namespace gs {

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

}  // namespace gs
