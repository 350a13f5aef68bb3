// Which rays the sampling pass (Jevans 1990 §6.5) traces before a run: a regular subset of
// a ray file, or the sample pixels of an image.
#pragma once
#include <cstddef>
#include <vector>

#include "core/geometry/ray.h"

namespace gs {

// Rays 0, every, 2 every, ... of the run.
std::vector<Ray> sample_subset(const std::vector<Ray>& rays, int every);

// The pixels of an image's sampling pass: the centre pixel of every 8x8 block, as indices
// y * width + x in row order (also what `trace --sample-image` picks from a ray file).
std::vector<size_t> image_sample_pixels(int width, int height);

}  // namespace gs
