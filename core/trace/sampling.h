// Which rays the sampling pass (Jevans 1990 §6.5) traces before a run: a regular subset of
// a ray file, or the sample pixels of an image.
#pragma once
#include <cstddef>
#include <span>
#include <vector>

#include "core/accel/accelerator.h"
#include "core/geometry/ray.h"
#include "core/scene/lighting.h"

namespace gs {

// The sampling pass for a run of `run_rays` rays over `sample`, drawn from them: each sample
// ray stands for an equal share of the run. Nothing for an empty sample. The sample is traced
// on `threads` threads (the run's); the structure does not depend on how many.
void sample_run(Accelerator& accel, std::span<const Ray> sample, size_t run_rays, int threads);

// The sampling pass of an image: `primaries`, the primary rays of its sample pixels drawn from
// an image of `run_primaries` primary rays, and the shadow ray each one's hit casts toward
// the light, which stands for the image's shadow rays with the same weight. On `threads`
// threads, as sample_run.
void sample_image_rays(Accelerator& accel, const Scene& scene, const Lighting& lighting,
                       std::span<const Ray> primaries, size_t run_primaries, int threads);

// Rays 0, every, 2 every, ... of the run.
std::vector<Ray> sample_subset(const std::vector<Ray>& rays, int every);

// The pixels of an image's sampling pass: the centre pixel of every 8x8 block, as indices
// y * width + x in row order (also what `trace --sample-image` picks from a ray file).
std::vector<size_t> image_sample_pixels(int width, int height);
// The rays of an image's sample pixels from its width * height rays in row order.
std::vector<Ray> image_sample(const std::vector<Ray>& rays, int width, int height);

}  // namespace gs
