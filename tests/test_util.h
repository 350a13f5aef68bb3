// Helpers shared by the test suites: the shared-scenes folder, temporary files, scenes and
// ray sets made in code, and tracing a ray set through a structure.
#pragma once
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "core/accelerator.h"
#include "core/ray.h"
#include "core/scene.h"

namespace gs::test {

// Path of a file under ../shared, or "" when ../shared is absent (callers GTEST_SKIP).
std::string shared_file(const std::string& relative);
// A fresh path under the system temp folder; the file is not created.
std::string temp_path(const std::string& name);

// A closed UV sphere with shared vertices (poles included), `rings` x `segments`.
Scene make_sphere(glm::vec3 centre, float radius, int rings, int segments);
// `count` random triangles of size about `size` inside [lo, hi].
Scene make_soup(uint32_t seed, int count, glm::vec3 lo, glm::vec3 hi, float size);
// Appends b's triangles (and vertices) after a's.
Scene merge(const Scene& a, const Scene& b);
// Every vertex mapped by p -> p * scale + offset.
Scene transformed(const Scene& scene, float scale, glm::vec3 offset);

// Ray sets over a scene's box.
std::vector<Ray> camera_rays(const Box& box, int width, int height);
std::vector<Ray> random_chords(const Box& box, uint32_t seed, int count);
std::vector<Ray> axis_parallel_rays(const Box& box, uint32_t seed, int count);
// Rays from far away aimed exactly at triangle vertices and at points on triangle edges.
std::vector<Ray> edge_and_vertex_rays(const Scene& scene, uint32_t seed, int count);

// Traces every ray with `threads` threads, each with its own context.
std::vector<Hit> trace_all(const Accelerator& accel, const std::vector<Ray>& rays, int threads,
                           bool any_hit = false);
// The sampling pass as the command line does it: every `every`-th ray.
void run_sampling_pass(Accelerator& accel, const std::vector<Ray>& rays, int every);

}  // namespace gs::test
